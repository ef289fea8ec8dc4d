"""Primitives: closed-form distances, exactness against the boundary, bounds."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from implicit import (
    box, capsule, cone, convex_polyhedron, cylinder, ellipsoid, frustum, halfspace, prism, pyramid,
    rounded_box, sphere, torus, wedge,
)
from implicit.polyhedra import triangle_distance

#: Tolerance for closed-form distances (float64 rounding only).
EXACT = 1e-12
#: A surface cloud of this many points is within this distance of every boundary point.
CLOUD_POINTS = 30000
CLOUD_TOL = 0.04


def at(solid, *pts):
    return solid(np.asarray(pts, dtype=float))


# ---------------------------------------------------------------------------
# closed forms
# ---------------------------------------------------------------------------

def test_sphere_inside_on_outside():
    s = sphere(2.0, center=(1, 0, 0))
    np.testing.assert_allclose(at(s, (1, 0, 0), (3, 0, 0), (1, 0, 5), (4, 4, 0)),
                               [-2, 0, 3, np.hypot(3, 4) - 2], atol=EXACT)


def test_box_faces_edges_corners():
    b = box((2, 4, 6))
    pts = [(0, 0, 0), (1, 0, 0), (3, 0, 0), (0, 0, -5), (2, 3, 0), (2, 3, 4), (0.5, 1.5, 2.5)]
    want = [-1, 0, 2, 2, np.hypot(1, 1), np.sqrt(3), -0.5]
    np.testing.assert_allclose(at(b, *pts), want, atol=EXACT)


def test_box_scalar_size_is_a_cube():
    np.testing.assert_allclose(at(box(1.5), (0, 0, 1.0)), [0.25], atol=EXACT)


def test_rounded_box_corner_is_a_sphere():
    b = rounded_box((2, 2, 2), radius=0.5)
    # Beyond the corner the field is the distance to a ball of radius 0.5 at (0.5, 0.5, 0.5).
    p = np.array([2.0, 2.0, 2.0])
    np.testing.assert_allclose(at(b, p), [np.linalg.norm(p - 0.5) - 0.5], atol=EXACT)
    np.testing.assert_allclose(at(b, (0, 0, 0), (1, 0, 0)), [-1, 0], atol=EXACT)


def test_cylinder_axis_rim_and_oriented():
    c = cylinder(1.0, 2.0)
    np.testing.assert_allclose(at(c, (0, 0, 0), (0, 0, 2), (3, 0, 0), (2, 0, 2), (0.5, 0, 0.9)),
                               [-1, 1, 2, np.sqrt(2), -0.1], atol=EXACT)
    tilted = cylinder(1.0, 2.0, center=(1, 1, 1), axis=(1, 1, 0))
    a = np.array([1, 1, 0]) / np.sqrt(2)
    perp = np.array([0, 0, 1.0])
    np.testing.assert_allclose(at(tilted, (1, 1, 1) + 3 * a, (1, 1, 1) + 2.5 * perp), [2, 1.5], atol=EXACT)


def test_cone_apex_base_and_slant():
    c = cone(1.0, 1.0)
    # Slant line from (1, 0) to (0, 1) in (r, z): distance of (r, z) = (1, 1) is 1/sqrt(2).
    np.testing.assert_allclose(at(c, (0, 0, 2), (0, 0, -1), (1, 0, 1), (0, 0, 0.5)),
                               [1, 1, np.sqrt(0.5), -0.5 / np.sqrt(2)], atol=EXACT)


def test_frustum_closed_forms():
    f = frustum(1.0, 0.5, 2.0)
    slant = np.array([-0.5, 2.0]) / np.hypot(0.5, 2.0)   # base rim to top rim in (r, z)
    normal = np.array([slant[1], -slant[0]])            # outward normal of the slant line
    p_rz = np.array([0.75, 1.0]) + 0.3 * normal          # 0.3 outside the middle of the slant
    np.testing.assert_allclose(at(f, (p_rz[0], 0, p_rz[1])), [0.3], atol=EXACT)
    np.testing.assert_allclose(at(f, (0, 0, 3), (0, 0, -0.5), (0, 0, 1)), [1, 0.5, -0.75 * normal[0]], atol=EXACT)


def test_torus_tube_and_axis():
    t = torus(2.0, 0.5, axis=(0, 1, 0))
    np.testing.assert_allclose(at(t, (2, 0, 0), (0, 0, -2.5), (0, 0, 0), (0, 3, 0)),
                               [-0.5, 0, 1.5, np.hypot(2, 3) - 0.5], atol=EXACT)


def test_halfspace_signed_plane_distance():
    h = halfspace((0, 0, 2), point=(0, 0, 1))
    np.testing.assert_allclose(at(h, (5, 5, 3), (0, 0, 0)), [2, -1], atol=EXACT)
    assert h.bounds[1][2] == 1.0 and np.isinf(h.bounds[0]).all()


def test_capsule_segment_distance():
    c = capsule((0, 0, 0), (0, 0, 2), 0.5)
    np.testing.assert_allclose(at(c, (0, 0, 3), (0, 0, -1), (2, 0, 1), (0, 0, 1)), [0.5, 0.5, 1.5, -0.5],
                               atol=EXACT)
    np.testing.assert_allclose(c.bounds[0], [-0.5, -0.5, -0.5])
    point = capsule((1, 1, 1), (1, 1, 1), 1.0)                      # degenerate segment: a ball
    np.testing.assert_allclose(at(point, (1, 1, 3)), [1.0], atol=EXACT)


def test_ellipsoid_values_on_the_axes_and_flags():
    e = ellipsoid((3, 2, 1), center=(1, 0, 0))
    # (|q/r| - 1) * min(r): along x at 2 beyond the tip, |q/r| = 5/3.
    np.testing.assert_allclose(at(e, (6, 0, 0), (1, 0, 2), (1, 0, 0)), [(5 / 3 - 1) * 1, 1, -1], atol=EXACT)
    assert not e.exact and ellipsoid(2.0).exact
    np.testing.assert_allclose(e.bounds[1], [4, 2, 1])


def test_wedge_faces():
    w = wedge((2, 1, 1), corner=(1, 0, 0))
    # Slope plane x/2 + z = 1 (relative to the corner); its unit normal is (1, 0, 2)/sqrt(5).
    np.testing.assert_allclose(at(w, (1.5, 0.5, -1), (1.5, 2, 0.2), (4, 0.5, 0)), [1, 1, 1], atol=EXACT)
    p = np.array([1 + 1.0, 0.5, 0.5 + 0.2 * 2 / np.sqrt(5)]) + np.array([0.2 / np.sqrt(5), 0, 0])
    np.testing.assert_allclose(at(w, p), [0.2], atol=1e-12)
    np.testing.assert_allclose(w.bounds[0], [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(w.bounds[1], [3, 1, 1], atol=1e-9)


def test_convex_polyhedron_cube_matches_box_everywhere():
    normals = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    cube = convex_polyhedron(normals, np.array(normals, float) * 0.5)
    pts = np.random.default_rng(1).uniform(-2, 2, (4000, 3))
    np.testing.assert_allclose(cube(pts), box(1.0)(pts), atol=1e-12)
    np.testing.assert_allclose(cube.bounds[1], [0.5] * 3, atol=1e-9)


def test_polyhedron_points_projecting_onto_face_diagonals():
    # A lattice puts many points straight above the diagonals that split square faces.
    normals = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    cube = convex_polyhedron(normals, np.array(normals, float) * 0.5)
    lattice = np.stack(np.meshgrid(*[np.linspace(-2, 2, 17)] * 3, indexing="ij"), -1).reshape(-1, 3)
    np.testing.assert_allclose(cube(lattice), box(1.0)(lattice), atol=1e-9)
    np.testing.assert_allclose(at(wedge((1, 1, 1)), (0.5, 0.5, -1), (-1, 0.5, 0.5)), [1, 1], atol=1e-12)


def test_convex_polyhedron_tetrahedron_bounds_from_vertices():
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    normals = [[-1, 0, 0], [0, -1, 0], [0, 0, -1], [1, 1, 1]]
    points = [verts[0], verts[0], verts[0], verts[1]]
    tet = convex_polyhedron(normals, points)
    np.testing.assert_allclose(tet.bounds[0], [0, 0, 0], atol=1e-9)
    np.testing.assert_allclose(tet.bounds[1], [1, 1, 1], atol=1e-9)
    # Beyond the vertex (1, 0, 0) along +x; the centroid is 1/(4 sqrt 3) behind the slanted face.
    np.testing.assert_allclose(at(tet, (3, 0, 0), (0.25, 0.25, 0.25)), [2, -0.25 / np.sqrt(3)], atol=1e-12)


def test_pyramid_apex_base_and_slant():
    p = pyramid([(-1, -1), (1, -1), (1, 1), (-1, 1)], 2.0, center=(0, 0, 1))
    np.testing.assert_allclose(at(p, (0, 0, 4), (0, 0, 0), (0, 0, 1.5)), [1, 1, -0.5], atol=1e-12)
    # Either orientation of the base gives the same solid.
    q = pyramid([(-1, 1), (1, 1), (1, -1), (-1, -1)], 2.0, center=(0, 0, 1))
    pts = np.random.default_rng(2).uniform(-2, 3, (500, 3))
    np.testing.assert_allclose(p(pts), q(pts), atol=1e-12)


def test_prism_of_a_nonconvex_polygon():
    ell = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    p = prism(ell, 2.0)
    np.testing.assert_allclose(at(p, (1.5, 1.5, 0), (0.5, 0.5, 0), (0.5, 0.5, 3), (1.5, 1.5, 2)),
                               [0.5, -0.5, 2, np.hypot(0.5, 1)], atol=1e-12)


def test_triangle_distance_regions():
    tri = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0.0]]])
    pts = np.array([[0.2, 0.2, 2], [-1, -1, 0], [2, 0, 0], [0.5, 0.5, 1], [0.5, -1, 0]])
    want = [2, np.sqrt(2), 1, np.sqrt(1 + 0), 1]
    np.testing.assert_allclose(triangle_distance(pts, tri), want, atol=1e-12)


# ---------------------------------------------------------------------------
# exactness against the boundary, 1-Lipschitz
# ---------------------------------------------------------------------------

EXACT_PRIMITIVES = {
    "sphere": sphere(1.0, center=(0.2, 0, 0)),
    "box": box((1.5, 1.0, 0.6)),
    "rounded_box": rounded_box((1.5, 1.0, 0.8), radius=0.2),
    "cylinder_tilted": cylinder(0.5, 1.2, axis=(1, 2, 3)),
    "cone": cone(0.7, 1.2, center=(0, 0, -0.6)),
    "frustum": frustum(0.8, 0.3, 1.0, axis=(0, 1, 1)),
    "torus": torus(0.8, 0.25, axis=(1, 0, 1)),
    "capsule": capsule((-0.5, 0, 0), (0.5, 0.3, 0.2), 0.3),
    "wedge": wedge((1.2, 0.8, 1.0), corner=(-0.6, -0.4, -0.5)),
    "pyramid": pyramid([(-0.6, -0.5), (0.7, -0.4), (0.5, 0.6), (-0.4, 0.5)], 1.0, center=(0, 0, -0.5),
                       axis=(0.3, 0, 1)),
    "convex_polyhedron": convex_polyhedron(
        [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 1, 1]],
        [[0.6, 0, 0], [-0.6, 0, 0], [0, 0.5, 0], [0, -0.5, 0], [0, 0, 0.4], [0, 0, -0.4], [0.3, 0.3, 0.3]]),
    "prism": prism([(0, 0), (1, 0), (1, 0.4), (0.4, 0.4), (0.4, 1), (0, 1)], 0.8, center=(-0.5, -0.5, 0),
                   axis=(0, 1, 0)),
}


def surface_cloud(solid, n, seed=0):
    """Points on the zero set: random points pushed by Newton steps ``p - f grad / |grad|^2``."""
    rng = np.random.default_rng(seed)
    lo, hi = solid.bounds
    pad = 0.25 * (hi - lo).max()
    p = rng.uniform(lo - pad, hi + pad, (n, 3))
    for _ in range(5):
        f = solid(p)
        g = solid.gradient(p, step=1e-7)
        g2 = np.einsum("ij,ij->i", g, g)
        p = p - (f / np.where(g2 > 1e-12, g2, 1.0))[:, None] * g
    return p[np.abs(solid(p)) < 1e-9]


@pytest.mark.parametrize("name", sorted(EXACT_PRIMITIVES))
def test_exact_primitive_equals_distance_to_its_boundary(name):
    solid = EXACT_PRIMITIVES[name]
    assert solid.exact
    cloud = surface_cloud(solid, CLOUD_POINTS)
    assert len(cloud) > CLOUD_POINTS // 3
    rng = np.random.default_rng(5)
    lo, hi = solid.bounds
    pts = rng.uniform(lo - 0.5, hi + 0.5, (3000, 3))
    dist, _ = cKDTree(cloud).query(pts)
    f = np.abs(solid(pts))
    # |f| never exceeds the distance (the cloud lies on the boundary) ...
    assert np.all(f <= dist + 1e-7)
    # ... and equals it up to the cloud's spacing.
    assert np.all(dist - f <= CLOUD_TOL), float((dist - f).max())


BOUND_PRIMITIVES = {"ellipsoid": ellipsoid((1.0, 0.5, 0.3)), "flat_ellipsoid": ellipsoid((0.2, 1.0, 1.0))}


@pytest.mark.parametrize("name", sorted(BOUND_PRIMITIVES))
def test_bound_primitive_never_overestimates(name):
    solid = BOUND_PRIMITIVES[name]
    cloud = surface_cloud(solid, CLOUD_POINTS)
    pts = np.random.default_rng(6).uniform(-1.5, 1.5, (3000, 3))
    dist, _ = cKDTree(cloud).query(pts)
    assert np.all(np.abs(solid(pts)) <= dist + 1e-7)


@pytest.mark.parametrize("name", sorted(EXACT_PRIMITIVES) + sorted(BOUND_PRIMITIVES))
def test_primitives_are_1_lipschitz(name):
    solid = {**EXACT_PRIMITIVES, **BOUND_PRIMITIVES}[name]
    rng = np.random.default_rng(7)
    a = rng.uniform(-1.5, 1.5, (10000, 3))
    b = a + rng.normal(size=a.shape) * rng.uniform(1e-4, 0.5, (len(a), 1))
    ratio = np.abs(solid(a) - solid(b)) / np.linalg.norm(a - b, axis=1)
    assert ratio.max() <= 1.0 + 1e-9


def test_ellipsoid_bound_is_not_quilez_overestimate():
    # Near the tip of the long axis the distance is exactly the gap along the axis.
    e = ellipsoid((2.0, 0.5, 0.5))
    assert at(e, (2.5, 0, 0))[0] <= 0.5


@pytest.mark.parametrize("name", sorted(EXACT_PRIMITIVES) + sorted(BOUND_PRIMITIVES))
def test_bounds_hold_the_interior(name):
    solid = {**EXACT_PRIMITIVES, **BOUND_PRIMITIVES}[name]
    lo, hi = solid.bounds
    pts = np.random.default_rng(8).uniform(lo - 1, hi + 1, (40000, 3))
    inside = pts[solid(pts) <= 0]
    assert len(inside) > 100
    assert np.all(inside >= lo - 1e-12) and np.all(inside <= hi + 1e-12)
    # Bounds are tight to within a few percent for these primitives.
    assert np.all(inside.min(axis=0) - lo < 0.1 * (hi - lo) + 0.02)


# ---------------------------------------------------------------------------
# require_bounds
# ---------------------------------------------------------------------------

def test_require_bounds_finite_unbounded_and_given():
    lo, hi = sphere(1.0).require_bounds()
    np.testing.assert_array_equal(hi, [1, 1, 1])
    with pytest.raises(ValueError, match=r"unbounded.*--bounds x0 y0 z0 x1 y1 z1"):
        halfspace((0, 0, 1)).require_bounds()
    lo, hi = halfspace((0, 0, 1)).require_bounds(((-1, -1, -1), (1, 1, 0)))
    np.testing.assert_array_equal(lo, [-1, -1, -1])
    with pytest.raises(ValueError, match="lower corner <= upper corner"):
        sphere(1.0).require_bounds(((1, 1, 1), (0, 0, 0)))
    with pytest.raises(ValueError, match="expected finite numbers"):
        sphere(1.0).require_bounds(((0, 0, 0), (1, 1, np.inf)))


def test_require_bounds_returns_empty_bounds_as_is():
    empty = sphere(1.0) & sphere(1.0, center=(5, 0, 0))
    lo, hi = empty.require_bounds()
    assert np.any(lo > hi)
