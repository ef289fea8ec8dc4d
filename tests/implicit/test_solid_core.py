"""The Solid node's contract: evaluation shapes, immutability, bounds, tree walking."""

import numpy as np
import pytest

import implicit as im
from implicit.solid import Solid, as_points


def benchmark_part():
    return (im.sphere(1.0) & im.box(1.5)) - im.cylinder(0.5, 4, axis=(1, 0, 0)) \
        - im.cylinder(0.5, 4, axis=(0, 1, 0)) - im.cylinder(0.5, 4, axis=(0, 0, 1))


def test_evaluation_keeps_leading_shape():
    s = im.sphere(1.0)
    pts = np.zeros((4, 5, 3))
    pts[..., 0] = 2.0
    out = s(pts)
    assert out.shape == (4, 5)
    assert np.allclose(out, 1.0)
    assert s([0.0, 0.0, 0.0]).shape == ()
    assert float(s([0.0, 0.0, 0.0])) == -1.0


def test_large_arrays_are_evaluated_in_chunks_identically():
    part = benchmark_part()
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1, 1, (100_003, 3))
    whole = part(pts)
    pieces = np.concatenate([part(pts[i:i + 1000]) for i in range(0, len(pts), 1000)])
    # Large calls take the compiled path (implicit.evaluate): equal up to rounding.
    np.testing.assert_allclose(whole, pieces, rtol=0, atol=1e-12)


@pytest.mark.parametrize("bad, match", [
    (np.zeros((3, 2)), r"points: expected an array of shape \(\.\.\., 3\)"),
    (np.array([[np.nan, 0, 0]]), "points: expected numbers, got NaN"),
    ("abc", "points: expected an array of shape"),
])
def test_bad_points_are_refused(bad, match):
    with pytest.raises((ValueError, TypeError), match=match):
        im.sphere(1.0)(bad)


def test_solids_refuse_truth_and_equality_and_mutation():
    s = im.sphere(1.0)
    with pytest.raises(TypeError, match="truth value of a Solid is ambiguous"):
        bool(s)
    with pytest.raises(TypeError, match="not compared with =="):
        s == s  # noqa: B015
    with pytest.raises(AttributeError, match="immutable"):
        s.radius = 3
    assert hash(s) == hash(s)
    assert len({s, im.sphere(1.0)}) == 2


def test_operations_return_new_nodes_and_leave_operands_alone():
    a = im.sphere(1.0)
    before = a.params
    moved = a.translate((1, 0, 0))
    assert moved is not a
    assert a.params == before
    assert float(a([1.0, 0, 0])) == 0.0
    assert float(moved([2.0, 0, 0])) == 0.0


def test_tree_walk_counts_and_text():
    part = benchmark_part()
    assert part.count_primitives() == 5
    assert part.count_nodes() == 7
    assert part.depth() == 3
    lines = part.tree().splitlines()
    assert lines[0] == "difference()"
    assert lines[1] == "  intersection()"
    assert lines[2].startswith("    sphere(radius=1")
    assert [n.kind for n in part.walk()] == [
        "difference", "intersection", "sphere", "box", "cylinder", "cylinder", "cylinder"]


def test_nary_operations_flatten():
    a, b, c = im.sphere(1), im.box(1), im.torus(1, 0.2)
    assert (a | b | c).count_nodes() == 4
    assert (a & b & c).count_nodes() == 4
    assert (a - b - c).count_nodes() == 4
    assert (~~a) is a


def test_bounds_of_csg():
    part = benchmark_part()
    lo, hi = part.bounds
    assert np.allclose(lo, -0.75) and np.allclose(hi, 0.75)
    u = im.sphere(1) | im.sphere(1, center=(3, 0, 0))
    assert np.allclose(u.bounds[0], [-1, -1, -1]) and np.allclose(u.bounds[1], [4, 1, 1])
    assert not (~im.sphere(1)).is_bounded
    assert (im.sphere(1) & im.sphere(1, center=(5, 0, 0))).is_empty_bounds


def test_rotated_bounds_hold_the_solid():
    cyl = im.cylinder(0.2, 2.0).rotate(30, axis=(1, 1, 0))
    lo, hi = cyl.bounds
    rng = np.random.default_rng(3)
    pts = rng.uniform(-2, 2, (200_000, 3))
    inside = pts[cyl(pts) <= 0]
    assert len(inside) > 500
    assert np.all(inside >= lo - 1e-12) and np.all(inside <= hi + 1e-12)


def test_value_bounds_contain_samples_and_classify():
    part = benchmark_part()
    rng = np.random.default_rng(7)
    lo = rng.uniform(-1, 1, (200, 3))
    hi = lo + rng.uniform(0.01, 0.4, (200, 3))
    vmin, vmax = part.value_bounds(lo, hi)
    t = rng.uniform(0, 1, (200, 64, 3))
    samples = part(lo[:, None, :] + t * (hi - lo)[:, None, :])
    assert np.all(samples >= vmin[:, None] - 1e-12)
    assert np.all(samples <= vmax[:, None] + 1e-12)


def test_value_bounds_validates_boxes():
    with pytest.raises(ValueError, match="lower corner must be <= its upper corner"):
        im.sphere(1).value_bounds([[1, 1, 1]], [[0, 0, 0]])
    with pytest.raises(ValueError, match="same shape"):
        im.sphere(1).value_bounds([[0, 0, 0]], [[1, 1, 1], [2, 2, 2]])


def test_transform_chains_fold_into_one_node():
    s = im.sphere(1).translate((1, 0, 0)).rotate(90).translate((0, 0, 2))
    assert s.count_nodes() == 2
    assert np.isclose(float(s([0.0, 1.0, 2.0])), -1.0)
    assert s.translate((0, 0, 0)).count_nodes() == 2
    back = s.translate((0, 0, -2)).rotate(-90).translate((-1, 0, 0))
    assert back.kind == "sphere"


def test_non_uniform_scale_is_a_conservative_bound():
    e = im.sphere(1).scale((2.0, 1.0, 0.5))
    assert not e.exact
    rng = np.random.default_rng(5)
    pts = rng.uniform(-3, 3, (5000, 3))
    # Dense sampling of the ellipsoid's boundary.
    u = rng.normal(size=(200_000, 3))
    surf = u / np.linalg.norm(u, axis=1, keepdims=True) * [2.0, 1.0, 0.5]
    from scipy.spatial import cKDTree
    dist, _ = cKDTree(surf).query(pts)
    vals = e(pts)
    assert np.all(np.abs(vals) <= dist + 1e-2)
    inside = (pts[:, 0] / 2) ** 2 + pts[:, 1] ** 2 + (pts[:, 2] / 0.5) ** 2 < 1
    assert np.array_equal(vals < 0, inside)


def test_affine_refuses_singular_matrix():
    with pytest.raises(ValueError, match="matrix: expected an invertible matrix"):
        im.sphere(1).affine(np.diag([1.0, 1.0, 0.0]))
    with pytest.raises(ValueError, match="factor: expected positive scale factors"):
        im.sphere(1).scale((1, -1, 1))


def test_mirror_and_rotation_are_isometries():
    part = benchmark_part().translate((0.3, 0.1, 0.0))
    rng = np.random.default_rng(11)
    pts = rng.uniform(-1.5, 1.5, (1000, 3))
    r = im.rotation_matrix(37.0, (1.0, 2.0, 3.0))
    rotated = part.rotate(37.0, axis=(1.0, 2.0, 3.0))
    assert np.allclose(rotated(pts @ r.T), part(pts), atol=1e-12)
    mirrored = part.mirror((1.0, 0.0, 0.0))
    flipped = pts * [-1, 1, 1]
    assert np.allclose(mirrored(flipped), part(pts), atol=1e-12)


def test_offset_and_shell():
    s = im.sphere(1.0)
    assert np.isclose(float(s.offset(0.25)([1.25, 0, 0])), 0.0)
    assert np.isclose(float(s.offset(-0.25)([0.75, 0, 0])), 0.0)
    wall = s.shell(0.2)
    assert float(wall([0.0, 0.0, 0.0])) > 0
    assert float(wall([1.0, 0.0, 0.0])) == pytest.approx(-0.1)
    assert np.isclose(float(wall([1.1, 0, 0])), 0.0)


def test_smooth_union_adds_a_fillet_and_stays_lipschitz():
    a = im.box(1.0)
    b = im.box(1.0, center=(0.0, 0.0, 1.0))
    sharp = a | b
    smooth = im.smooth_union(a, b, blend=0.2)
    rng = np.random.default_rng(2)
    pts = rng.uniform(-1, 2, (20000, 3))
    assert np.all(smooth(pts) <= sharp(pts) + 1e-12)
    assert np.all(sharp(pts) - smooth(pts) <= 0.2 / 4 + 1e-12)
    q = rng.uniform(-1, 2, (20000, 3))
    ratio = np.abs(smooth(pts) - smooth(q)) / np.linalg.norm(pts - q, axis=1)
    assert ratio.max() <= 1.0 + 1e-9


def test_as_points_returns_float64():
    arr = as_points([[1, 2, 3]])
    assert arr.dtype == np.float64
    assert isinstance(im.sphere(1), Solid)


def test_shell_and_offset_of_an_intersection_stay_inside_their_bounds():
    # Two cubes 0.1 apart: their intersection is empty, its bounds are empty, but max(a, b) < t
    # holds in the gap between them, so a shell or an offset of it is not empty; moved away, the
    # empty bounds used to stay where they were (fuzz seed 3796).
    import implicit as I

    both = (I.box(1.0) & I.box(1.0, center=(1.1, 0.0, 0.0))).rotate(90, axis=(0, 0, 1)).translate((5, 0, 0))
    pts = np.random.default_rng(7).uniform(-1.5, 2.5, (400_000, 3)) + (5.0, 0.5, 0.0)
    for solid in (I.shell(both, 0.3), I.offset(both, 0.15)):
        lo, hi = solid.bounds
        inside = solid(pts) < 0
        assert inside.sum() > 100
        assert np.all((pts[inside] >= lo - 1e-12) & (pts[inside] <= hi + 1e-12))
