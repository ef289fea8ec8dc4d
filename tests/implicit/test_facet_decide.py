"""The deciding operand of a sharp Boolean of two: what ``argmin`` / ``argmax`` of their stack picks."""

import numpy as np
import pytest

from implicit.facets import _decide


def _stacked(kind, results):
    values = np.stack([r[0] for r in results])
    decs = np.stack([r[1] for r in results])
    if kind == "difference":
        values[1:] *= -1.0
    idx = values.argmin(axis=0) if kind == "union" else values.argmax(axis=0)
    cols = np.arange(values.shape[1])
    return values[idx, cols], decs[idx, cols]


@pytest.mark.parametrize("kind", ["union", "intersection", "difference"])
def test_two_operands_decide_as_the_stack_does_ties_zeros_and_nans_included(kind):
    rng = np.random.default_rng(5)
    a = rng.integers(-3, 4, 2000).astype(np.float64)
    b = rng.integers(-3, 4, 2000).astype(np.float64)
    a[rng.random(2000) < 0.1] = np.nan
    b[rng.random(2000) < 0.1] = np.nan
    a[::7], b[::7] = 0.0, -0.0                       # ties of signed zeros: the first operand wins
    da, db = rng.integers(0, 9, 2000), rng.integers(10, 19, 2000)
    value, dec = _decide(kind, [(a, da), (b, db)])
    want_value, want_dec = _stacked(kind, [(a, da), (b, db)])
    assert np.array_equal(dec, want_dec)
    assert np.array_equal(value.view(np.int64), want_value.view(np.int64))     # the same bits
    assert (dec >= 10).any() and (dec < 10).any()
    three = [(a, da), (b, db), (-a, db + 20)]
    assert all(np.array_equal(x, y, equal_nan=True) for x, y in zip(_decide(kind, three), _stacked(kind, three)))


@pytest.mark.parametrize("kind", ["box", "cylinder", "sphere"])
def test_compiled_leaves_decide_as_numpy_bit_for_bit(kind, monkeypatch):
    """A box's, a cylinder's and a sphere's field and deciding facet by their compiled loops
    (`implicit.facet_leaf_kernel`) against numpy's passes: on the leaf's faces and edges (ties, the
    signed zeros of points on a face's plane), at NaNs and infinities, in tilted frames."""
    import implicit.facet_prune as fp
    from implicit import box, cylinder, sphere
    from implicit.facets import FacetField

    rng = np.random.default_rng(9)
    leaves = {"box": [box((1.5, 1.0, 0.5)), box(1.0, center=(0.25, -0.5, 0.125))],
              "cylinder": [cylinder(0.5, 2.0), cylinder(0.5, 4, axis=(1, 0, 0)), cylinder(0.5, 4, axis=(0, -1, 0)),
                           cylinder(0.25, 1.0, center=(0.5, 0.0, -0.25), axis=(0, 0, -1)),
                           cylinder(0.3, 1.0, axis=(1, 2, 3))],
              "sphere": [sphere(1.0), sphere(0.75, center=(0.5, 0.25, 0.0))]}[kind]
    p = rng.uniform(-1.5, 1.5, (20000, 3))
    p[:8000] = np.round(p[:8000] * 8) / 8                   # on the faces' planes and edges: ties and zeros
    p[8000:8500] = -p[8500:9000] * 0.0                      # signed zeros
    p[9000:9010] = np.nan
    p[9010:9020] = np.inf
    p[9020:9030, 1] = -np.inf
    assert fp.leaf_loops() is not None
    ff = FacetField(leaves[0])
    for leaf in leaves:
        with np.errstate(invalid="ignore"), monkeypatch.context() as m:
            got = ff._leaf_decide(leaf, p, 3)
            m.setattr("implicit.facets.leaf_loops", lambda: None)
            want = ff._leaf_decide(leaf, p, 3)
        assert np.array_equal(got[0], want[0], equal_nan=True)
        assert np.array_equal(np.signbit(got[0]), np.signbit(want[0]))
        assert np.array_equal(got[1], want[1])
    if kind != "sphere":
        assert len(set(want[1].tolist())) == (6 if kind == "box" else 3)
