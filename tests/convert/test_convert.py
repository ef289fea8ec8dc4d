"""Solids and grids -> fitted curves and surfaces -> solids and meshes."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import cylinder, ellipsoid, sphere, star_solid, torus
from implicit.serialize import from_json, to_json
from implicit.star_solids import fit_radial_function
from parametric.conics import circle as nurbs_circle
from parametric.tensor import sphere as nurbs_sphere, torus as nurbs_torus
from spatial.convert.fitting import (
    curve_to_polydata, fit_section_curve, fit_star_surface, isoparametric_polydata, loft_sections,
    star_radii, surface_to_mesh,
)
from spatial.cells.grid import OccupancyGrid

#: Fit tolerance asked for in the section tests.
FIT_TOL = 1e-4
#: Relative volume change allowed by the solid -> grid -> surface -> solid round trip.
ROUND_TRIP_TOL = 5e-3

ELLIPSOID = (2.0, 1.5, 1.0)


def _grid(solid, cells):
    """Occupancy grid of `solid`: distances at the centres of `cells` voxels across
    its largest side, padded by two voxels."""
    lo, hi = solid.bounds
    h = float(np.max(hi - lo)) / cells
    origin = lo - 2 * h
    shape = np.ceil((hi - lo) / h).astype(int) + 4
    axes = [origin[i] + h * (np.arange(shape[i]) + 0.5) for i in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), -1)
    return OccupancyGrid(solid(pts.reshape(-1, 3)).reshape(pts.shape[:3]), origin=origin, voxel_size=h)


def _blob_radius(theta, phi):
    return 1.0 + 0.15 * np.sin(3 * theta) * np.sin(phi) ** 2 + 0.1 * np.cos(phi)


def _blob_radii(samples=(64, 33)):
    th = 2 * np.pi * np.arange(samples[0]) / samples[0]
    ph = np.linspace(0, np.pi, samples[1])
    T, P = np.meshgrid(th, ph, indexing="ij")
    return _blob_radius(T, P)


# ---------------------------------------------------------------------------- sections

def test_section_of_a_sphere_is_fitted_within_tolerance():
    fit = fit_section_curve(sphere(1.0), "z=0.6", tolerance=FIT_TOL, resolution=128)
    assert fit.max_deviation < FIT_TOL
    t = np.linspace(0, 1, 500)
    pts = fit.curve(t)
    np.testing.assert_allclose(pts[:, 2], 0.6, atol=1e-12)
    np.testing.assert_allclose(np.hypot(pts[:, 0], pts[:, 1]), 0.8, atol=FIT_TOL)
    np.testing.assert_allclose(fit.curve(0.0), fit.curve(1.0), atol=1e-12)
    assert not fit.hole
    # starts where the contour crosses +x from its centroid, runs counter-clockwise
    assert fit.curve(0.0)[0] > 0.79 and abs(fit.curve(0.0)[1]) < 0.02
    assert fit.curve(0.1)[1] > 0


def test_fixed_control_count_and_tighter_tolerance_need_more_points():
    loose = fit_section_curve(ellipsoid(ELLIPSOID), "z=0.2", tolerance=1e-2, resolution=96)
    tight = fit_section_curve(ellipsoid(ELLIPSOID), "z=0.2", tolerance=1e-4, resolution=96)
    assert loose.n_control < tight.n_control
    assert tight.max_deviation < 1e-4 < loose.max_deviation or loose.max_deviation < 1e-2
    fixed = fit_section_curve(ellipsoid(ELLIPSOID), "z=0.2", n_control=10, resolution=96)
    assert fixed.n_control == 10
    assert np.asarray(fixed.curve2d.control_points).shape[0] == 10 + fixed.curve2d.degree


def test_section_of_an_occupancy_grid_uses_its_interpolant():
    grid = _grid(cylinder(1.0, 2.0), 64)
    fit = fit_section_curve(grid, "z=0.1", n_control=16, resolution=128)
    r = np.hypot(*fit.curve(np.linspace(0, 1, 200))[:, :2].T)
    np.testing.assert_allclose(r, 1.0, atol=0.01)


def test_all_loops_of_a_torus_section_with_its_hole():
    fits = fit_section_curve(torus(2.0, 0.5), "z=0", loop="all", n_control=24, resolution=128)
    assert sorted(f.hole for f in fits) == [False, True]
    for f in fits:
        r = np.hypot(*f.curve(np.linspace(0, 1, 100))[:, :2].T)
        np.testing.assert_allclose(r, 1.5 if f.hole else 2.5, atol=1e-3)


def test_section_errors_name_the_argument():
    with pytest.raises(ValueError, match="does not cut"):
        fit_section_curve(sphere(1.0), "z=2")
    with pytest.raises(TypeError, match="solid_or_grid"):
        fit_section_curve("sphere", "z=0")
    with pytest.raises(ValueError, match="loop"):
        fit_section_curve(sphere(1.0), "z=0", loop=3, resolution=64)
    with pytest.raises(ValueError, match="tolerance"):
        fit_section_curve(sphere(1.0), "z=0", tolerance=-1.0)
    with pytest.raises(TypeError, match="n_control"):
        fit_section_curve(sphere(1.0), "z=0", n_control=2.5)


# ---------------------------------------------------------------------------- lofting

def test_loft_through_sections_of_a_cylinder_stays_on_it():
    res = loft_sections(cylinder(1.0, 2.0), "z", 4, n_control=16, resolution=96)
    surf = res.surface
    assert len(res.sections) == 4
    (au, bu), (av, bv) = surf.domain_u, surf.domain_v
    g = surf.grid(np.linspace(au, bu, 60), np.linspace(av, bv, 30))
    np.testing.assert_allclose(np.hypot(g[..., 0], g[..., 1]), 1.0, atol=2e-3)
    np.testing.assert_allclose(g[:, 0, 2], res.levels[0], atol=1e-9)
    np.testing.assert_allclose(g[:, -1, 2], res.levels[-1], atol=1e-9)
    assert res.max_deviation < 2e-3


def test_loft_interpolates_each_section_of_an_ellipsoid():
    res = loft_sections(ellipsoid(ELLIPSOID), "z", [-0.6, -0.2, 0.2, 0.6], n_control=14, resolution=96)
    surf = res.surface
    assert surf.degree_v == 3
    # surface rows meet the sections: the solid's field vanishes there (up to the fit)
    for f in res.sections:
        assert f.max_deviation < 5e-3
    (au, bu), (av, bv) = surf.domain_u, surf.domain_v
    g = surf.grid(np.linspace(au, bu, 40), np.linspace(av, bv, 40)).reshape(-1, 3)
    assert np.max(np.abs(ellipsoid(ELLIPSOID)(g))) < 0.02
    with pytest.raises(ValueError, match="axis"):
        loft_sections(sphere(1.0), "w")
    with pytest.raises(ValueError, match="levels"):
        loft_sections(sphere(1.0), "z", [0.5, 0.1])


# ---------------------------------------------------------------------------- star-shaped

def test_star_radii_of_an_ellipsoid_are_exact():
    a, b, c = ELLIPSOID
    R = star_radii(ellipsoid(ELLIPSOID), np.zeros(3), (16, 9))
    th = 2 * np.pi * np.arange(16) / 16
    ph = np.linspace(0, np.pi, 9)
    T, P = np.meshgrid(th, ph, indexing="ij")
    d = np.stack([np.sin(P) * np.cos(T), np.sin(P) * np.sin(T), np.cos(P)], -1)
    exact = 1.0 / np.sqrt((d[..., 0] / a) ** 2 + (d[..., 1] / b) ** 2 + (d[..., 2] / c) ** 2)
    np.testing.assert_allclose(R, exact, atol=1e-9)


def test_star_surface_closes_at_the_seam_and_poles_and_faces_outward():
    fit = fit_star_surface(ellipsoid(ELLIPSOID), n_control=(20, 10), samples=(48, 25))
    S = fit.surface
    v = np.linspace(0, 1, 20)
    np.testing.assert_allclose(S(np.zeros(20), v), S(np.ones(20), v), atol=1e-12)
    u = np.linspace(0, 1, 20)
    for pole in (0.0, 1.0):
        ring = S(u, np.full(20, pole))
        np.testing.assert_allclose(ring, np.broadcast_to(ring[0], ring.shape), atol=1e-12)
    uu, vv = np.meshgrid(np.linspace(0.05, 0.95, 9), np.linspace(0.1, 0.9, 9), indexing="ij")
    n = S.normal(uu.ravel(), vv.ravel())
    assert np.all(np.einsum("ij,ij->i", n, S(uu.ravel(), vv.ravel()) - fit.center) > 0)
    assert fit.max_deviation < 0.05
    finer = fit_star_surface(ellipsoid(ELLIPSOID), n_control=(32, 16), samples=(64, 33))
    assert finer.max_deviation < 0.5 * fit.max_deviation


def test_round_trip_solid_grid_surface_solid_keeps_the_volume():
    a, b, c = ELLIPSOID
    exact = 4.0 / 3.0 * np.pi * a * b * c
    grid = OccupancyGrid.from_solid(ellipsoid(ELLIPSOID), resolution=128, progress=False)
    fit = fit_star_surface(grid, n_control=(24, 12))
    assert abs(fit.solid.volume() / exact - 1.0) < ROUND_TRIP_TOL
    # the rebuilt solid agrees in sign with the original away from the boundary
    q = np.random.default_rng(7).uniform(-2.2, 2.2, (4000, 3))
    truth = ellipsoid(ELLIPSOID)(q)
    far = np.abs(truth) > 0.05
    assert np.all(np.sign(fit.solid(q)[far]) == np.sign(truth[far]))


def test_round_trip_of_a_smooth_blob_through_its_grid():
    R, dev = fit_radial_function(_blob_radii((96, 49)), n_control=(32, 16))
    blob = star_solid(R, center=(0.2, -0.1, 0.3))
    assert dev < 1e-3
    grid = OccupancyGrid.from_solid(blob, resolution=128, progress=False)
    again = fit_star_surface(grid, center=(0.2, -0.1, 0.3), n_control=(32, 16), samples=(96, 49))
    assert abs(again.solid.volume() / blob.volume() - 1.0) < ROUND_TRIP_TOL


def test_star_solid_of_a_constant_radius_is_the_exact_sphere():
    R, _ = fit_radial_function(np.full((32, 17), 1.5), n_control=(8, 6))
    ball = star_solid(R, center=(1.0, 0.0, 0.0))
    q = np.random.default_rng(3).uniform(-2, 3, (2000, 3))
    np.testing.assert_allclose(ball(q), sphere(1.5).translate((1, 0, 0))(q), atol=1e-9)
    assert ball.volume() == pytest.approx(4 / 3 * np.pi * 1.5 ** 3, rel=1e-12)
    again = from_json(to_json(ball))
    np.testing.assert_array_equal(again(q), ball(q))


BLOB, _ = fit_radial_function(_blob_radii(), n_control=(24, 12))
BLOB_SOLID = star_solid(BLOB)
_T, _P = np.meshgrid(np.linspace(0, 1, 400, endpoint=False), np.linspace(0, 1, 201), indexing="ij")
_DIRS_PHI = np.pi * (1 - _P)
_DIRS = np.stack([np.sin(_DIRS_PHI) * np.cos(2 * np.pi * _T), np.sin(_DIRS_PHI) * np.sin(2 * np.pi * _T),
                  np.cos(_DIRS_PHI)], -1)
BLOB_SURFACE = (BLOB(_T, _P) * _DIRS).reshape(-1, 3)


@settings(derandomize=True, max_examples=30, deadline=None)
@given(p=st.tuples(*[st.floats(-2.0, 2.0)] * 3))
def test_star_solid_field_never_exceeds_the_distance(p):
    q = np.array(p)
    upper = np.min(np.linalg.norm(BLOB_SURFACE - q, axis=1))     # >= true distance
    f = float(BLOB_SOLID(q[None])[0])
    assert abs(f) <= upper + 1e-9


def test_star_errors():
    with pytest.raises(ValueError, match="center"):
        fit_star_surface(sphere(1.0), center=(3.0, 0.0, 0.0))
    with pytest.raises(TypeError, match="solid"):
        fit_star_surface(nurbs_sphere(1.0))
    with pytest.raises(ValueError, match="radii"):
        fit_radial_function(-np.ones((8, 5)))


# ---------------------------------------------------------------------------- meshes

def test_surface_to_mesh_is_a_triangulated_grid_with_parameters():
    m = surface_to_mesh(nurbs_torus(2.0, 0.5), 80, 40)
    assert m.n_points == 3200 and m.n_cells == 2 * 79 * 39
    assert m.is_all_triangles
    np.testing.assert_allclose(m.point_data["uv"][-1], [1.0, 1.0])
    r = np.hypot(np.hypot(m.points[:, 0], m.points[:, 1]) - 2.0, m.points[:, 2])
    np.testing.assert_allclose(r, 0.5, atol=1e-6)
    # closed surface: the welded mesh encloses the torus' volume to a few percent
    vol = m.clean(tolerance=1e-9).volume
    assert vol == pytest.approx(2 * np.pi ** 2 * 2.0 * 0.25, rel=0.01)
    with pytest.raises(TypeError, match="surface"):
        surface_to_mesh(nurbs_circle(1.0))


def test_isoparametric_lines_at_steps_of_a_tenth():
    iso = isoparametric_polydata(nurbs_sphere(1.0), step=0.1, samples=30)
    assert iso.n_lines == 22
    assert iso.cell_data["direction"].tolist() == [0] * 11 + [1] * 11
    np.testing.assert_allclose(np.linalg.norm(iso.points, axis=1), 1.0, atol=1e-12)


def test_curve_to_polydata_lifts_planar_curves():
    poly = curve_to_polydata(nurbs_circle(2.0, center=(0.0, 0.0)), 40)
    assert poly.n_points == 40 and poly.n_lines == 1
    np.testing.assert_allclose(poly.points[:, 2], 0.0)
    np.testing.assert_allclose(np.linalg.norm(poly.points, axis=1), 2.0, atol=1e-12)
    with pytest.raises(ValueError, match="n"):
        curve_to_polydata(nurbs_circle(1.0), 1)


def test_fitted_star_surface_bounds_a_solid_through_surface_solid():
    from implicit import surface_solid
    from scipy.spatial import cKDTree

    fit = fit_star_surface(ellipsoid(ELLIPSOID), n_control=(24, 12), samples=(48, 25))
    solid = surface_solid(fit.surface)
    q = np.random.default_rng(11).uniform(-2.2, 2.2, (3000, 3))
    f = solid(q)
    truth = ellipsoid(ELLIPSOID)(q)
    far = np.abs(truth) > 0.05
    assert np.all(np.sign(f[far]) == np.sign(truth[far]))
    dense = fit.surface.grid(np.linspace(0, 1, 400), np.linspace(0, 1, 200)).reshape(-1, 3)
    upper, _ = cKDTree(dense).query(q)          # >= distance to the fitted surface
    assert np.all(np.abs(f) <= upper + 1e-9)
    assert np.max(upper - np.abs(f)) < 0.02
