"""CSG laws, transforms, regularised booleans and conservative value bounds."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import (
    affine, box, capsule, circle, complement, cone, convex_polyhedron, cylinder, difference, ellipsoid,
    extrude, frustum, halfspace, intersection, offset, polygon, prism, pyramid, rectangle, revolve,
    rounded_box, shell, smooth_difference, smooth_intersection, smooth_union, sphere, torus, union, wedge,
)
from implicit.csg import bound_slack
from implicit.families import instance
from implicit.transforms import rotation_matrix

#: Slack for float rounding in comparisons of field values.
TOL = 1e-9

_A = sphere(0.8, center=(0.2, 0.1, 0))
_B = box((1.2, 0.8, 1.0), center=(-0.2, 0, 0.1))
_C = cylinder(0.3, 2.0, axis=(1, 1, 0))

#: One solid of every node kind (and the interesting variants of some).
CATALOG = {
    "sphere": _A,
    "box": _B,
    "rounded_box": rounded_box((1, 1, 1), radius=0.2),
    "cylinder": _C,
    "cone": cone(0.6, 1.0),
    "frustum": frustum(0.6, 0.2, 1.0, axis=(0, 1, 0)),
    "torus": torus(0.7, 0.2),
    "halfspace": halfspace((1, 1, 1), point=(0.1, 0, 0)),
    "ellipsoid": ellipsoid((1.0, 0.4, 0.6)),
    "capsule": capsule((0, 0, 0), (0.5, 0.5, 0), 0.3),
    "wedge": wedge((1, 1, 0.5)),
    "pyramid": pyramid([(-0.5, -0.5), (0.5, -0.5), (0, 0.5)], 0.8),
    "convex_polyhedron": convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                                           [[0.5, 0, 0], [-0.5, 0, 0], [0, 0.5, 0], [0, -0.5, 0], [0, 0, 0.5],
                                            [0, 0, -0.5]]),
    "prism": prism([(0, 0), (1, 0), (1, 1), (0.5, 0.3), (0, 1)], 0.5),
    "union": union(_A, _B, _C),
    "intersection": intersection(_A, _B),
    "difference": difference(_B, _A.translate((0.6, 0, 0)), _C),
    "complement": complement(_A),
    "smooth_union": smooth_union(_A, _B.translate((0.8, 0, 0)), blend=0.3),
    "smooth_intersection": smooth_intersection(_A, _B, blend=0.3),
    "smooth_difference": smooth_difference(_B, _A, blend=0.2),
    "rigid": _B.rotate(30, (1, 2, 3), about=(0.1, 0, 0)).translate((0.2, -0.1, 0.3)),
    "nonuniform_scale": _B.scale((2.0, 0.5, 1.0)),
    "shear": affine(_A, [[1, 0.7, 0], [0, 1, 0], [0.2, 0, 1]], offset=(0.1, 0, 0)),
    "mirror": _C.mirror((1, 0, 0), point=(0.3, 0, 0)),
    "offset_grow": offset(_B, 0.2),
    "offset_shrink": offset(_B, -0.1),
    "shell": shell(_A, 0.1),
    "offset_of_a_bound": offset(ellipsoid((1.0, 0.1, 0.1)), 0.15),
    "shell_of_a_stretch": shell(_A.scale((1.0, 0.25, 1.0)), 0.3),
    "extrude": extrude(circle(0.5) - rectangle((0.3, 0.3)), 0.8, axis=(0, 1, 1)),
    "revolve": revolve(polygon([(0.2, -0.3), (0.7, -0.3), (0.5, 0.3)])),
    "revolve_partial": revolve(circle(0.2, center=(0.6, 0)), 120, axis=(1, 0, 0)),
    "revolve_reflex": revolve(rectangle((0.4, 0.5), center=(0.4, 0)), 250),
    "family_hole_plate": instance("hole_plate", length=2.0, width=1.2, thickness=0.2, hole_diameter=0.3,
                                  rows=2, cols=3, margin=0.3),
    "family_l_bracket": instance("l_bracket", width=1, leg_a=1.5, leg_b=1.2, thickness=0.2,
                                 hole_diameter=0.2, holes_per_leg=2),
}


def _points(seed, n=4000, scale=2.0):
    return np.random.default_rng(seed).uniform(-scale, scale, (n, 3))


# ---------------------------------------------------------------------------
# value bounds: conservative over random boxes, for every node kind
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(CATALOG))
@settings(derandomize=True, max_examples=12, deadline=None)
@given(centre=st.tuples(*[st.floats(-1.5, 1.5)] * 3), half=st.tuples(*[st.floats(0.001, 0.8)] * 3),
       seed=st.integers(0, 2 ** 31))
def test_value_bounds_contain_every_sampled_value(name, centre, half, seed):
    solid = CATALOG[name]
    c, h = np.array(centre), np.array(half)
    lo, hi = c - h, c + h
    vmin, vmax = solid.value_bounds(lo[None], hi[None])
    rng = np.random.default_rng(seed)
    pts = np.vstack([rng.uniform(lo, hi, (200, 3)), np.array(np.meshgrid(*zip(lo, hi))).reshape(3, -1).T])
    vals = solid(pts)
    assert vals.min() >= vmin[0] - TOL
    assert vals.max() <= vmax[0] + TOL


@pytest.mark.parametrize("name", sorted(CATALOG))
def test_every_node_is_lipschitz_with_its_constant(name):
    solid = CATALOG[name]
    rng = np.random.default_rng(3)
    a = _points(4, 10000)
    b = a + rng.normal(size=a.shape) * rng.uniform(1e-4, 0.3, (len(a), 1))
    ratio = np.abs(solid(a) - solid(b)) / np.linalg.norm(a - b, axis=1)
    assert ratio.max() <= solid.lipschitz + 1e-9


@pytest.mark.parametrize("name", sorted(CATALOG))
def test_bounds_hold_the_interior(name):
    solid = CATALOG[name]
    pts = _points(5, 60000, 3.0)
    inside = pts[solid(pts) <= 0]
    lo, hi = solid.bounds
    assert np.all(inside >= lo - 1e-12) and np.all(inside <= hi + 1e-12)


def test_smooth_union_bounds_cover_the_blend_of_stretched_children():
    # Two ellipsoids stretched 4x along x: near their tips each field is a
    # quarter of the distance, so the blend reaches beyond bounds + blend/4.
    stretched = sphere(0.5).scale((4.0, 1.0, 1.0))
    assert bound_slack(stretched) == pytest.approx(4.0)
    s = smooth_union(stretched.translate((0, 0.3, 0)), stretched.translate((0, -0.3, 0)), blend=0.8)
    tip = np.array([[2.3, 0.0, 0.0]])
    assert s(tip)[0] < 0 and tip[0, 0] > 2.0 + 0.8 / 4
    lo, hi = s.bounds
    assert hi[0] >= 2.3
    pts = _points(6, 50000, 3.0)
    inside = pts[s(pts) <= 0]
    assert np.all(inside >= lo) and np.all(inside <= hi)


# ---------------------------------------------------------------------------
# CSG laws at random points
# ---------------------------------------------------------------------------

_SOLIDS = [CATALOG[k] for k in ("sphere", "box", "cylinder", "torus", "wedge", "ellipsoid", "extrude", "rigid")]


@settings(derandomize=True, max_examples=30, deadline=None)
@given(i=st.integers(0, len(_SOLIDS) - 1), j=st.integers(0, len(_SOLIDS) - 1), seed=st.integers(0, 2 ** 31))
def test_csg_laws(i, j, seed):
    a, b = _SOLIDS[i], _SOLIDS[j]
    p = _points(seed, 500)
    fa, fb = a(p), b(p)
    np.testing.assert_array_equal((a | a)(p), fa)                          # A | A == A
    np.testing.assert_array_equal((a & a)(p), fa)                          # A & A == A
    inside = (a & b)(p) <= 0                                               # A & B within A and B
    assert np.all(fa[inside] <= 0) and np.all(fb[inside] <= 0)
    union_in = (a | b)(p) <= 0                                             # A | B is A or B
    np.testing.assert_array_equal(union_in, (fa <= 0) | (fb <= 0))
    np.testing.assert_array_equal((a - b)(p), (a & ~b)(p))                 # A - B == A & ~B
    np.testing.assert_array_equal((~(a | b))(p), (~a & ~b)(p))             # De Morgan
    np.testing.assert_array_equal((~(a & b))(p), (~a | ~b)(p))
    np.testing.assert_array_equal((~~a)(p), fa)


@settings(derandomize=True, max_examples=25, deadline=None)
@given(angle=st.floats(-180, 180), axis=st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1),
       move=st.tuples(*[st.floats(-3, 3)] * 3), k=st.integers(0, len(_SOLIDS) - 1))
def test_rigid_motions_preserve_distances(angle, axis, move, k):
    a = _SOLIDS[k]
    moved = a.rotate(angle, axis).translate(move)
    p = _points(k, 300)
    q = p @ rotation_matrix(angle, axis).T + np.array(move)
    np.testing.assert_allclose(moved(q), a(p), atol=1e-12)
    assert moved.exact == a.exact


def test_uniform_scale_scales_distances():
    s = sphere(1.0).scale(3.0)
    np.testing.assert_allclose(s([[5.0, 0, 0], [0, 0, 0]]), [2, -3], atol=1e-12)
    assert s.exact


def test_nonuniform_scale_is_a_bound():
    s = sphere(1.0).scale((2.0, 1.0, 1.0))
    assert not s.exact
    # At (4, 0, 0) the true distance to the ellipsoid is 2; the bound is (2 - 1) * sigma_min = 1.
    np.testing.assert_allclose(s([[4.0, 0, 0]]), [1.0], atol=1e-12)


def test_transform_chains_fold_into_one_node():
    s = sphere(1.0).translate((1, 0, 0)).rotate(90).scale(2.0).translate((0, 0, 1))
    assert s.count_nodes() == 2
    np.testing.assert_allclose(s([[0, 2, 1]]), [-2.0], atol=1e-12)
    assert sphere(1.0).translate((1, 0, 0)).translate((-1, 0, 0)).kind == "sphere"


def test_translated_halfspace_keeps_its_finite_side():
    h = halfspace((0, 0, 1)).translate((0, 0, 2))
    assert h.bounds[1][2] == 2.0 and np.isinf(h.bounds[0][2])
    tilted = halfspace((0, 0, 1)).rotate(30, (1, 0, 0))
    assert not tilted.is_bounded


def test_nary_operators_flatten():
    u = (_A | _B) | _C
    assert u.kind == "union" and len(u.children) == 3
    d = _B - _A - _C
    assert d.kind == "difference" and len(d.children) == 3


def test_smooth_union_blends_below_the_sharp_union():
    a, b = sphere(1.0), sphere(1.0, center=(1.5, 0, 0))
    p = np.array([[0.75, 0.7, 0.0]])
    sharp = (a | b)(p)[0]
    blended = smooth_union(a, b, blend=0.5)(p)[0]
    assert blended < sharp and sharp - blended <= 0.5 / 4 + 1e-12


# ---------------------------------------------------------------------------
# regularised booleans
# ---------------------------------------------------------------------------

def test_touching_boxes_union_has_no_internal_face():
    """Face-to-face boxes: the shared face is interior to the closure of the
    union's interior, so it is not boundary (the field is <= 0 all around it),
    while a true face has positive values right next to it."""
    left = box((1, 1, 1), center=(0.5, 0.5, 0.5))
    right = box((1, 1, 1), center=(1.5, 0.5, 0.5))
    u = left | right
    rng = np.random.default_rng(9)
    face = np.column_stack([np.ones(500), rng.uniform(0.1, 0.9, (500, 2))])
    ball = face[:, None, :] + rng.normal(size=(500, 20, 3)) * 0.02
    assert np.all(u(ball) <= 0.0)                   # a neighbourhood of the shared face is solid
    off_face = face + [[1e-6, 0, 0]]
    assert np.all(u(off_face) < 0) and np.all(u(face - [[1e-6, 0, 0]]) < 0)
    outer = np.column_stack([np.zeros(500), face[:, 1:]])
    near_outer = outer[:, None, :] + rng.normal(size=(500, 20, 3)) * 0.02
    assert np.all((u(near_outer) > 0).any(axis=1))  # the end faces are boundary


def test_touching_boxes_intersect_to_an_empty_interior():
    left = box((1, 1, 1), center=(0.5, 0.5, 0.5))
    right = box((1, 1, 1), center=(1.5, 0.5, 0.5))
    both = left & right
    grid = np.stack(np.meshgrid(*[np.linspace(-0.5, 2.5, 61)] * 3, indexing="ij"), -1).reshape(-1, 3)
    assert both(grid).min() >= 0.0                  # no point is strictly inside
    assert both([[1.0, 0.5, 0.5]])[0] == 0.0        # the touching face is a measure-zero zero set


def test_offset_and_shell_are_marked_bounds():
    assert not offset(box(1.0), 0.1).exact and offset(box(1.0), 0.0).exact
    assert not shell(sphere(1.0), 0.1).exact
    np.testing.assert_allclose(shell(sphere(1.0), 0.2)([[1.0, 0, 0], [2.0, 0, 0]]), [-0.1, 0.9], atol=1e-12)


@pytest.mark.parametrize("bad", [1, "a", None])
def test_operators_reject_non_solids(bad):
    with pytest.raises(TypeError, match="must be a Solid"):
        union(_A, bad)
    with pytest.raises(TypeError, match="must be a Solid"):
        difference(_A, bad)
    with pytest.raises(TypeError, match="must be a Solid"):
        offset(bad, 0.1)
