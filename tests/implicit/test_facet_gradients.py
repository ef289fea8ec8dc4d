"""Exact facet gradients against central differences of the facet values, and the decider unchanged."""

import numpy as np
import pytest

from implicit import (box, capsule, cone, cylinder, ellipsoid, frustum, halfspace, offset, rotate, rounded_box, scale,
                      smooth_union, sphere, torus, translate)
from implicit.facets import FacetField

LEAVES = [
    box((1.0, 0.8, 0.6), center=(0.1, 0.0, -0.1)),
    cylinder(0.4, 1.2, center=(0.1, 0.2, 0.0), axis=(1.0, 1.0, 0.3)),
    sphere(0.7, center=(0.2, -0.1, 0.1)),
    halfspace((1.0, -2.0, 0.5), (0.1, 0.0, 0.0)),
    torus(0.6, 0.2, axis=(0.2, 1.0, 0.0)),
    frustum(0.5, 0.2, 1.0, center=(0.0, 0.0, -0.5), axis=(0.3, 0.1, 1.0)),
    cone(0.5, 1.0, center=(0.0, 0.0, -0.5)),
    capsule((0.0, 0.0, -0.4), (0.2, 0.1, 0.5), 0.3),
    rounded_box((1.0, 0.8, 0.6), 0.1),
    ellipsoid((0.6, 0.4, 0.3)),
]


def _central(ff, p, step=1e-6):
    cols = [(ff.facet_values(p + e * step) - ff.facet_values(p - e * step)) / (2 * step) for e in np.eye(3)]
    return np.stack(cols, axis=2)


def _check(solid, seed=0):
    rng = np.random.default_rng(seed)
    p = rng.uniform(-1.2, 1.2, (400, 3))
    ff = FacetField(solid)
    value, dec, f, g = ff.facets_with_gradients(p, decide=True)
    v0, d0, f0 = ff(p)
    np.testing.assert_allclose(f, f0, atol=1e-12)
    np.testing.assert_allclose(value, v0, atol=1e-12)
    np.testing.assert_array_equal(dec, d0)
    ref = _central(ff, p)
    # away from the kinks of a leaf (a cone's rim, a capsule's ends) the two agree to the difference error
    err = np.linalg.norm(g - ref, axis=2)
    assert np.quantile(err, 0.99) < 1e-5, np.quantile(err, 0.99)
    return g


@pytest.mark.parametrize("leaf", LEAVES, ids=lambda s: s.kind)
def test_leaf_gradients_match_differences(leaf):
    g = _check(leaf)
    if leaf.kind in ("sphere", "torus", "halfspace", "capsule"):
        # distance fields: unit gradients
        np.testing.assert_allclose(np.linalg.norm(g, axis=2), 1.0, atol=1e-9)


def test_gradients_through_transforms_and_csg():
    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0))
    moved = translate(rotate(scale(part, 0.8), 30.0, axis=(1.0, 1.0, 0.0)), (0.1, -0.2, 0.05))
    tree = offset(moved, 0.05) | smooth_union(torus(0.5, 0.1), sphere(0.2, center=(0.6, 0, 0)), blend=0.1)
    _check(tree, seed=1)
    # a rotated plane's gradient is the rotated normal, exactly
    ff = FacetField(rotate(box(1.0), 90.0, axis=(0.0, 0.0, 1.0)))
    g = ff.facets_with_gradients([[0.0, 0.0, 0.0]])[1]
    np.testing.assert_allclose(g[0, 0], [0.0, 1.0, 0.0], atol=1e-15)
    # a scaled sphere stays a distance: unit gradient
    g = FacetField(scale(sphere(1.0), 3.0)).facets_with_gradients([[4.0, 0.0, 0.0]])[1]
    np.testing.assert_allclose(g[0, 0], [1.0, 0.0, 0.0], atol=1e-12)


def test_gradients_of_selected_facets():
    part = translate(rotate(scale((sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)), 0.8), 30.0,
                            axis=(1.0, 1.0, 0.0)), (0.1, -0.2, 0.05)) | torus(0.5, 0.1, center=(1.0, 0.0, 0.0))
    ff = FacetField(part)
    rng = np.random.default_rng(3)
    p = rng.uniform(-1.2, 1.2, (300, 3))
    _, g = ff.facets_with_gradients(p)
    which = rng.integers(-1, len(ff.names), (300, 2))
    got = ff.gradients_of(p, which)
    want = np.where((which >= 0)[:, :, None], g[np.maximum(which, 0), np.arange(300)[:, None]], 0.0)
    np.testing.assert_allclose(got, want, atol=1e-14)
    assert got.shape == (300, 2, 3)
    with pytest.raises(ValueError, match="which"):
        ff.gradients_of(p, which[:10])


def test_smooth_flags_follow_the_facets():
    """One flag per facet, in the order of `names`: a cone's one facet holds its rims, so it is not smooth."""
    from implicit import box, cone, cylinder, sphere, torus
    from implicit.facets import FacetField

    ff = FacetField((box(2.0) - cylinder(0.5, 4.0)) | sphere(1.0, center=(3.0, 0.0, 0.0)) | torus() | cone(1.0, 0.5))
    assert len(ff.smooth) == len(ff.names) == 6 + 3 + 1 + 1 + 1
    assert ff.smooth.tolist() == [True] * 11 + [False]
    assert ff.names[-1].startswith("cone")


@pytest.mark.parametrize("seed", range(2))
def test_decide_is_the_full_walk_bit_for_bit(seed):
    """`decide` rebuilds box and cylinder fields from their facets: the same field and facet as `__call__`."""
    from implicit import extrude
    from implicit.profiles import rectangle

    rng = np.random.default_rng(seed)
    tree = ((box((1.0, 0.8, 0.6), center=(0.1, 0.0, -0.1)) & sphere(0.75))
            - cylinder(0.25, 2.0, axis=(1.0, 0.2, 0.1)) - rotate(cylinder(0.2, 2.0), 40.0, (0.0, 1.0, 0.0)))
    tree = tree | offset(scale(torus(0.5, 0.1), (1.0, 0.7, 1.2)), 0.02) | extrude(rectangle((0.4, 0.3)), 0.2)
    tree = tree - translate(rounded_box((0.3, 0.3, 0.3), 0.05), (0.4, 0.0, 0.3)) | capsule((0, 0, 0.5), (0, 0.3, 0.6), 0.1)
    for solid in (tree, ~tree, box(1.0), cylinder(0.4, 1.0)):
        for split in (False, True):
            ff = FacetField(solid, split_sides=split)
            p = rng.uniform(-0.9, 0.9, (4000, 3))
            p[:1000] = np.round(p[:1000] * 8) / 8          # points on the facets' planes: ties
            value, dec, _ = ff(p)
            v2, d2 = ff.decide(p)
            assert np.array_equal(value, v2) and np.array_equal(dec, d2)
