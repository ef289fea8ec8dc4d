"""The pruned facet walks: the full walk's results bit for bit, with work that follows the nearby primitives."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from implicit import (box, capsule, complement, cylinder, extrude, offset, polygon, rotate, rounded_box, scale,
                      smooth_difference, smooth_union, sphere, torus, union)
from implicit.facet_prune import Bins, pruned_decide, subset_values
from implicit.facets import PRUNE_MIN_POINTS, FacetField
from parts import capsule_lattice

_coord = st.floats(-1.0, 1.0)
_size = st.floats(0.15, 0.8)


@st.composite
def _leaf(draw):
    kind = draw(st.sampled_from(["box", "cylinder", "sphere", "torus", "capsule", "rounded_box", "extrude"]))
    c = tuple(draw(_coord) for _ in range(3))
    if kind == "box":
        return box(tuple(draw(_size) for _ in range(3)), center=c)
    if kind == "cylinder":
        return cylinder(draw(_size), 2 * draw(_size), center=c, axis=(draw(_coord), draw(_coord), 1.0))
    if kind == "sphere":
        return sphere(draw(_size), center=c)
    if kind == "torus":
        return torus(draw(st.floats(0.3, 0.6)), draw(st.floats(0.05, 0.2))).translate(c)
    if kind == "capsule":
        return capsule(c, tuple(x + draw(_coord) for x in c), draw(st.floats(0.05, 0.3)))
    if kind == "rounded_box":
        return rounded_box(tuple(draw(_size) for _ in range(3)), 0.05).translate(c)
    s = draw(_size)
    return extrude(polygon([(-s, -s), (s, -s), (0.3 * s, 0.2 * s), (s, s), (-s, s)]), 2 * draw(_size)).translate(c)


def _tree(draw, depth):
    if depth == 0 or draw(st.integers(0, 3)) == 0:
        return draw(_leaf())
    op = draw(st.sampled_from(["union", "intersection", "difference", "smooth_union", "smooth_difference",
                               "rotate", "scale", "offset", "complement"]))
    if op in ("rotate", "scale", "offset", "complement"):
        child = _tree(draw, depth - 1)
        if op == "rotate":
            return rotate(child, draw(st.floats(-180.0, 180.0)), axis=(draw(_coord), draw(_coord), 1.0))
        if op == "scale":
            return scale(child, tuple(draw(st.floats(0.5, 1.5)) for _ in range(3)))
        if op == "offset":
            return offset(child, draw(st.floats(-0.05, 0.1)))
        return complement(child)
    kids = [_tree(draw, depth - 1) for _ in range(draw(st.integers(2, 5)))]
    if op == "union":
        return union(*kids)
    if op == "intersection":
        return kids[0] & union(*kids[1:])
    if op == "difference":
        out = kids[0]
        for k in kids[1:]:
            out = out - k
        return out
    if op == "smooth_union":
        return smooth_union(*kids, blend=draw(st.floats(0.01, 0.2)))
    return smooth_difference(kids[0], *kids[1:], blend=draw(st.floats(0.01, 0.2)))


@st.composite
def trees(draw):
    return _tree(draw, 3)


def _points(seed, n=3000):
    rng = np.random.default_rng(seed)
    p = rng.uniform(-1.6, 1.6, (n, 3))
    p[: n // 4] = np.round(p[: n // 4] * 8) / 8       # on the facets' planes and the bins' borders: ties
    return p


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(trees(), st.integers(0, 2 ** 16), st.sampled_from([4, 16, 64]), st.booleans())
def test_pruned_decide_is_the_full_walk_bit_for_bit(solid, seed, per_bin, split):
    ff = FacetField(solid, split_sides=split)
    p = _points(seed)
    v0, d0 = ff._walk_decide(ff.solid, p, [0])
    v1, d1 = pruned_decide(ff, p, per_bin)
    assert np.array_equal(v0, v1, equal_nan=True)
    assert np.array_equal(d0, d1)
    # the public entry (which prunes only trees of several leaves)
    v2, d2 = ff.decide(p)
    assert np.array_equal(v0, v2, equal_nan=True) and np.array_equal(d0, d2)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(trees(), st.integers(0, 2 ** 16), st.booleans())
def test_values_and_gradients_of_the_facets_asked_are_the_full_walks(solid, seed, split):
    ff = FacetField(solid, split_sides=split)
    p = _points(seed, 800)
    rng = np.random.default_rng(seed)
    which = rng.integers(-1, len(ff.names) + 1, (p.shape[0], 3))
    fv = ff.facet_values(p)
    ok = (which >= 0) & (which < len(ff.names))
    want = np.where(ok, fv[np.where(ok, which, 0), np.arange(p.shape[0])[:, None]], 0.0)
    got = ff.values_of(p, which)
    assert np.array_equal(got, want, equal_nan=True)
    assert np.array_equal(subset_values(ff, p, which), want, equal_nan=True)
    # and the gradients of the facets asked for, each subtree mapped at its own points only
    _, g = ff.facets_with_gradients(p)
    want = np.where(ok[:, :, None], g[np.where(ok, which, 0), np.arange(p.shape[0])[:, None]], 0.0)
    assert np.array_equal(ff.gradients_of(p, which), want, equal_nan=True)


def test_decide_falls_back_on_points_that_are_not_finite():
    ff = FacetField(union(*[sphere(0.2, center=(x, 0.0, 0.0)) for x in range(10)]))
    p = _points(0, PRUNE_MIN_POINTS + 10)
    p[5] = np.nan
    v0, d0 = ff._walk_decide(ff.solid, p, [0])
    v1, d1 = ff.decide(p)
    assert np.array_equal(v0, v1, equal_nan=True) and np.array_equal(d0, d1)


def test_values_of_checks_its_shape():
    ff = FacetField(box(1.0))
    with pytest.raises(ValueError, match="which"):
        ff.values_of(np.zeros((4, 3)), np.zeros((3, 2), dtype=int))


def test_bins_hold_every_point_once_in_tight_boxes():
    p = _points(3, 5000)
    b = Bins(p, 32)
    assert sorted(b.order.tolist()) == list(range(5000))
    assert b.starts[0] == 0 and b.starts[-1] == 5000 and np.all(np.diff(b.starts) > 0)
    for i in range(len(b.starts) - 1):
        q = p[b.order[b.starts[i]:b.starts[i + 1]]]
        assert np.array_equal(q.min(axis=0), b.lo[i]) and np.array_equal(q.max(axis=0), b.hi[i])
    # about the points per bin asked for, over the box (uniform points: most bins hold some)
    assert 5000 / 32 / 2 < len(b.starts) - 1 < 5000 / 32 * 2


@pytest.fixture
def capsule_points(monkeypatch):
    """A counter of the points at which capsules are evaluated, by their own field or in a run of
    capsules (`implicit.facet_prune.Capsules`: one compiled loop over the rows of several)."""
    import implicit.facet_prune as fp

    count = [0]
    kind = type(capsule((0, 0, 0), (1, 0, 0), 0.1))
    evaluate = kind._evaluate
    values_at = fp.Capsules.values_at

    def counted(self, p):
        count[0] += len(p)
        return evaluate(self, p)

    def counted_rows(self, p, rows, which, out):
        count[0] += len(rows)
        return values_at(self, p, rows, which, out)

    monkeypatch.setattr(kind, "_evaluate", counted)
    monkeypatch.setattr(fp.Capsules, "values_at", counted_rows)
    return count


def test_decide_on_a_lattice_evaluates_the_capsules_near_each_point(capsule_points):
    """300 capsules: each point of the surface meets a handful of them (the full walk: all 300)."""
    solid, n_caps = capsule_lattice(4)
    rng = np.random.default_rng(1)
    # points on the capsules' surfaces: at radius 0.12 around random points of the edges
    axis = rng.integers(0, 3, 20000)
    base = rng.integers(0, 5, (20000, 3)).astype(float)
    base[np.arange(20000), axis] = rng.uniform(0, 4, 20000)
    d = rng.normal(size=(20000, 3))
    d[np.arange(20000), axis] = 0.0
    p = base + 0.12 * d / np.linalg.norm(d, axis=1)[:, None]
    ff = FacetField(solid)
    v, dec = ff.decide(p)
    per_point = capsule_points[0] / p.shape[0]
    assert per_point < 60, per_point                 # the full walk: n_caps = 300 a point
    capsule_points[0] = 0
    v0, d0 = ff._walk_decide(ff.solid, p, [0])
    assert capsule_points[0] == n_caps * p.shape[0]
    assert np.array_equal(v, v0) and np.array_equal(dec, d0)
    # one facet a point: at most one capsule a point (the full `facet_values`: all 300)
    capsule_points[0] = 0
    ff.values_of(p, dec)
    assert 0 < capsule_points[0] <= p.shape[0]


def test_the_fold_without_numba_is_the_compiled_fold_bit_for_bit(monkeypatch):
    """A Boolean's operands folded by the compiled loop or one by one by numpy: the same values and facets."""
    import implicit.facet_prune as fp

    solid = union(*[capsule((x, 0.0, 0.0), (x, 1.0, 0.5), 0.3) for x in np.arange(0.0, 5.0, 0.5)]) \
        - sphere(0.8, center=(2.0, 0.5, 0.0))
    ff = FacetField(solid)
    p = _points(4, 6000) * np.array([2.0, 1.0, 1.0]) + np.array([2.0, 0.5, 0.0])
    v0, d0 = ff._walk_decide(ff.solid, p, [0])
    v1, d1 = pruned_decide(ff, p)
    monkeypatch.setattr(fp, "_fold", lambda: None)
    v2, d2 = pruned_decide(ff, p)
    assert np.array_equal(v0, v1) and np.array_equal(d0, d1)
    assert np.array_equal(v0, v2) and np.array_equal(d0, d2)
    assert len(set(d0.tolist())) > 10                       # many capsules decide somewhere


def test_bounds_per_bin_read_the_operands_from_the_tape(capsule_points):
    """The operands' values at the bins' centres come from one run of the compiled tape: no capsule is
    evaluated by numpy for them, and the operands kept per bin are those numpy's values keep."""
    import implicit.facet_prune as fp

    solid, n_caps = capsule_lattice(4)
    c = np.random.default_rng(2).uniform(0.0, 4.0, (500, 3))
    radius = np.full(500, 0.2)
    known = fp._tape_values(solid, c)
    assert known is not None and len(known) == 2             # the union of capsules and the intersection
    capsule_points[0] = 0
    keeps: list = []
    v = fp._record(solid, c, 1.0, radius, keeps, known)
    assert capsule_points[0] == 0
    want: list = []
    v0 = fp._record(solid, c, 1.0, radius, want)
    assert capsule_points[0] == n_caps * 500
    np.testing.assert_allclose(v, v0, rtol=1e-12, atol=1e-12)
    assert len(keeps) == len(want) == 2
    assert all(np.array_equal(a, b) for a, b in zip(keeps, want))
    assert 0 < keeps[1].sum() < keeps[1].size / 10            # a few capsules a bin, not all 300


def test_runs_of_capsules_are_the_per_capsule_walks_bit_for_bit(monkeypatch):
    """Consecutive capsule operands evaluated by one loop over their rows (`Capsules`): the same values,
    deciding facets and gradients as a call per capsule, in unions, intersections and differences whose
    base or tools are runs of capsules, beside operands of other kinds."""
    import implicit.facet_prune as fp

    rng = np.random.default_rng(7)

    def caps(k, shift):
        a = rng.uniform(-1.0, 1.0, (k, 3)) + shift
        return [capsule(tuple(x), tuple(x + rng.uniform(-0.8, 0.8, 3)), float(rng.uniform(0.1, 0.4))) for x in a]

    struts = union(*caps(6, 0.0), sphere(0.3), *caps(5, 0.2), box(0.4, center=(0.5, 0.0, 0.0)))
    holes = caps(4, -0.1)
    solid = (union(*caps(3, 0.3), *caps(2, -0.3)) - holes[0] - holes[1]) | (struts & union(*caps(4, 0.0)))
    solid = solid - rotate(union(*holes[2:]), 30.0, axis=(0.0, 0.0, 1.0))
    d = caps(3, 0.1)
    solid = solid | (d[0] - d[1] - d[2])              # a run of capsules holding the base and the tools
    p = _points(11, 6000)
    ff = FacetField(solid)
    runs = [len(c.children) for node in _booleans(solid) for c in fp.operands(ff, node) if type(c) is fp.Capsules]
    assert sorted(runs) == [2, 2, 3, 4, 5, 5, 6]
    which = rng.integers(-1, len(ff.names) + 1, (p.shape[0], 3))
    got = pruned_decide(ff, p) + (ff.values_of(p, which), ff.gradients_of(p, which))
    plain = FacetField(solid)
    monkeypatch.setattr(fp, "operands", lambda ff, node: list(node.children))
    monkeypatch.setattr("implicit.facets.operands", lambda ff, node: list(node.children))
    want = pruned_decide(plain, p) + (plain.values_of(p, which), plain.gradients_of(p, which))
    v0, d0 = plain._walk_decide(plain.solid, p, [0])
    assert np.array_equal(got[0], v0) and np.array_equal(got[1], d0)
    for a, b in zip(got, want):
        assert np.array_equal(a, b)
    assert len(set(d0.tolist())) > 15                      # many capsules decide somewhere


def _booleans(node):
    out = [node] if node.kind in ("union", "intersection", "difference") else []
    for c in node.children:
        out += _booleans(c)
    return out


def test_bins_by_the_compiled_counting_sort_are_numpys(monkeypatch):
    """`Bins` sorted by the compiled counting sort (`facet_prune_kernel.bin_points`) and by numpy's stable
    argsort: the same order, bins, sorted points and boxes."""
    import implicit.facet_prune as fp

    p = _points(5, 20000)
    p[:3000] = np.round(p[:3000])                       # many equal coordinates, zeros of both signs
    p[:1500] *= -1.0
    for per_bin in (1, 16, 64, 5000):
        got = fp.Bins(p, per_bin)
        with monkeypatch.context() as m:
            m.setattr(fp, "_capsule_loops", lambda: None)
            want = fp.Bins(p, per_bin)
        for name in ("order", "starts", "sorted", "lo", "hi"):
            a, b = getattr(got, name), getattr(want, name)
            assert a.dtype == b.dtype and np.array_equal(a, b)
            assert np.array_equal(np.signbit(a), np.signbit(b))
    assert got.starts.shape[0] > 2 and fp.Bins(p, 16).starts.shape[0] > 500
