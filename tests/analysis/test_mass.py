"""Mass properties: exact mesh integrals, solids against closed forms, error bounds."""

import json

import numpy as np
import pytest
import pyvista as pv
from hypothesis import given, settings, strategies as st

from implicit import box, cone, cylinder, sphere, torus
from spatial.analysis.mass import MassProperties, OpenMeshError, UNITS, mass_properties, mesh_moments

#: Relative tolerances of the accuracy targets.
SMOOTH_TOL = 1e-4          # volume and principal moments, smooth parts, N = 128
SHARP_TOL = 1e-3           # same with sharp edges
CENTROID_TOL = 5e-5        # centroid offset / part size, smooth
CENTROID_SHARP_TOL = 5e-4
RICHARDSON_TOL = 1e-6      # extrapolated volume, smooth parts, N = 128


def _mesher():
    """`spatial.mesh` when present, else a dense marching-cubes stand-in."""
    try:
        from spatial.meshing.boundary import mesh as spatial_mesh
        # the plain mesh, as mass_properties' own mesher (raw marching-cubes volumes, their h^2 law)
        return lambda solid, h: spatial_mesh(solid, voxel_size=h, progress=False, features=False)
    except ImportError:  # pragma: no cover - the mesher is part of the package
        from skimage import measure

        def dense(solid, h):
            lo, hi = solid.bounds
            lo = lo - 2 * h
            shape = np.ceil((hi + 2 * h - lo) / h).astype(int) + 1
            axes = [lo[i] + h * np.arange(shape[i]) for i in range(3)]
            grid = np.stack(np.meshgrid(*axes, indexing="ij"), -1)
            d = solid(grid.reshape(-1, 3)).reshape(grid.shape[:3])
            v, f, _, _ = measure.marching_cubes(d, 0.0, spacing=(h, h, h))
            return pv.PolyData(v + lo, np.hstack([np.full((len(f), 1), 3), f]).ravel())
        return dense


MESHER = _mesher()


def reference_parts():
    """name -> (solid, volume, area, centroid, sorted principal moments / density, smooth, size)."""
    out = {}
    V = 4 * np.pi / 3
    out["sphere"] = (sphere(1.0, center=(0.3, -0.2, 0.1)), V, 4 * np.pi, [0.3, -0.2, 0.1], [0.4 * V] * 3, True, 2.0)
    out["sphere0"] = (sphere(0.5), V / 8, np.pi, [0, 0, 0], [0.4 * V / 8 * 0.25] * 3, True, 1.0)
    R, r = 1.0, 0.3
    V = 2 * np.pi ** 2 * R * r * r
    out["torus"] = (torus(R, r), V, 4 * np.pi ** 2 * R * r, [0, 0, 0],
                    sorted([V * (R * R / 2 + 5 * r * r / 8)] * 2 + [V * (R * R + 0.75 * r * r)]), True, 2.6)
    R, H = 0.5, 1.3
    V = np.pi * R * R * H
    out["cylinder"] = (cylinder(R, H), V, 2 * np.pi * R * (R + H), [0, 0, 0],
                       sorted([V * (3 * R * R + H * H) / 12] * 2 + [V * R * R / 2]), False, 1.3)
    R, H = 0.6, 1.2
    V = np.pi * R * R * H / 3
    out["cone"] = (cone(R, H), V, np.pi * R * (R + np.hypot(R, H)), [0, 0, H / 4],
                   sorted([V * (3 * R * R / 20 + 3 * H * H / 80)] * 2 + [0.3 * V * R * R]), False, 1.2)
    a, b, c = 1.0, 0.7, 0.45
    V = a * b * c
    out["box"] = (box((a, b, c)), V, 2 * (a * b + b * c + c * a), [0, 0, 0],
                  sorted([V * (b * b + c * c) / 12, V * (a * a + c * c) / 12, V * (a * a + b * b) / 12]), False, 1.0)
    V = 2 * np.pi / 3
    out["hemisphere"] = (sphere(1.0) & box((2.2, 2.2, 1.1), center=(0, 0, 0.55)), V, 3 * np.pi, [0, 0, 3 / 8],
                         sorted([0.259375 * V] * 2 + [0.4 * V]), False, 2.0)
    return out


PARTS = reference_parts()


# ---------------------------------------------------------------------------
# meshes: exact integrals
# ---------------------------------------------------------------------------

def _box_mesh(lo, hi):
    return pv.Box((lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])).triangulate().clean()


def test_box_mesh_exact():
    p = mass_properties(_box_mesh((0, 0, 0), (2.0, 1.0, 0.5)), density=3.0)
    V = 1.0
    assert p.volume == pytest.approx(V, rel=1e-14)
    assert p.mass == pytest.approx(3.0, rel=1e-14)
    assert p.area == pytest.approx(2 * (2 + 0.5 + 1), rel=1e-14)
    np.testing.assert_allclose(p.centroid, [1.0, 0.5, 0.25], atol=1e-15)
    m = 3.0
    expected = np.diag([m * (1 + 0.25) / 12, m * (4 + 0.25) / 12, m * (4 + 1) / 12])
    np.testing.assert_allclose(p.inertia, expected, atol=1e-14)
    np.testing.assert_allclose(p.principal_moments, np.sort(np.diag(expected)), rtol=1e-13)
    # parallel axis theorem about the origin
    c = p.centroid
    np.testing.assert_allclose(p.inertia_origin, expected + m * (c @ c * np.eye(3) - np.outer(c, c)), atol=1e-13)
    assert p.error.volume < 1e-13 and p.voxel_size == 0.0


def test_box_far_from_origin_keeps_precision():
    near = mass_properties(_box_mesh((0, 0, 0), (2.0, 1.0, 0.5)))
    far = mass_properties(_box_mesh((1e6, 1e6, 1e6), (1e6 + 2.0, 1e6 + 1.0, 1e6 + 0.5)))
    assert far.volume == pytest.approx(near.volume, rel=1e-9)
    np.testing.assert_allclose(far.inertia, near.inertia, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(far.centroid - 1e6, near.centroid, atol=1e-9)


def test_rotation_rotates_inertia():
    mesh = pv.Cylinder(radius=0.3, height=2.0, resolution=40).triangulate().clean()
    mesh.points[:, 0] += 0.4
    p0 = mass_properties(mesh)
    theta = 0.7
    rot = np.array([[1, 0, 0], [0, np.cos(theta), -np.sin(theta)], [0, np.sin(theta), np.cos(theta)]])
    moved = mesh.copy()
    moved.points = mesh.points @ rot.T
    p1 = mass_properties(moved)
    assert p1.volume == pytest.approx(p0.volume, rel=1e-12)
    np.testing.assert_allclose(p1.centroid, rot @ p0.centroid, atol=1e-12)
    np.testing.assert_allclose(p1.inertia, rot @ p0.inertia @ rot.T, atol=1e-12)
    np.testing.assert_allclose(p1.principal_moments, p0.principal_moments, rtol=1e-10)
    # principal axes: unit rows, right-handed, diagonalise the tensor
    ax = p1.principal_axes
    np.testing.assert_allclose(ax @ ax.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(ax) == pytest.approx(1.0)
    np.testing.assert_allclose(ax @ p1.inertia @ ax.T, np.diag(p1.principal_moments), atol=1e-12)


def test_open_mesh_refused():
    mesh = pv.Sphere(theta_resolution=12, phi_resolution=12).triangulate().clean()
    open_mesh = pv.PolyData(mesh.points, mesh.faces.reshape(-1, 4)[1:].ravel())
    with pytest.raises(OpenMeshError, match="not closed"):
        mass_properties(open_mesh)


def test_inconsistent_orientation_refused():
    mesh = _box_mesh((0, 0, 0), (1, 1, 1))
    faces = mesh.faces.reshape(-1, 4).copy()
    faces[0, 1:] = faces[0, 1:][::-1]
    with pytest.raises(OpenMeshError, match="oriented"):
        mass_properties(pv.PolyData(mesh.points, faces.ravel()))


def test_inward_mesh_refused():
    mesh = _box_mesh((0, 0, 0), (1, 1, 1))
    faces = mesh.faces.reshape(-1, 4).copy()
    faces[:, 1:] = faces[:, 1:][:, ::-1]
    with pytest.raises(ValueError, match="positive volume"):
        mass_properties(pv.PolyData(mesh.points, faces.ravel()))


def test_argument_errors():
    mesh = _box_mesh((0, 0, 0), (1, 1, 1))
    with pytest.raises(ValueError, match="units"):
        mass_properties(mesh, units="furlong")
    with pytest.raises(ValueError, match="density"):
        mass_properties(mesh, density=-2.0)
    with pytest.raises(TypeError, match="density"):
        mass_properties(mesh, density="steel")
    with pytest.raises(TypeError, match="obj"):
        mass_properties([1, 2, 3])
    with pytest.raises(ValueError, match="only applies to a Solid"):
        mass_properties(mesh, resolution=64)
    with pytest.raises(ValueError, match="at most one"):
        mass_properties(sphere(1.0), resolution=64, tolerance=1e-3)
    with pytest.raises(ValueError, match="bounded"):
        mass_properties(~sphere(1.0), resolution=32)
    with pytest.raises(ValueError, match="resolution"):
        mass_properties(sphere(1.0), resolution=2)


@pytest.mark.parametrize("units", sorted(UNITS))
def test_units_and_density(units):
    p = mass_properties(_box_mesh((0, 0, 0), (10, 10, 10)), density=7850, units=units)
    scale = UNITS[units]
    assert p.volume == pytest.approx(1000.0)
    assert p.mass == pytest.approx(7850 * 1000 * scale ** 3, rel=1e-13)
    assert p.units == units and p.inertia_unit == f"kg*{units}^2"
    # inertia in kg * units^2: m * (10^2 + 10^2) / 12
    assert p.principal_moments[0] == pytest.approx(p.mass * 200 / 12, rel=1e-12)


def test_to_dict_is_json():
    p = mass_properties(_box_mesh((0, 0, 0), (1, 2, 3)), density=2.0, units="mm")
    d = json.loads(json.dumps(p.to_dict()))
    for key in ("volume", "mass", "area", "centroid", "inertia", "inertia_origin", "principal_moments",
                "principal_axes", "error", "voxel_size", "units", "density"):
        assert key in d
    assert set(d["error"]) >= {"volume", "mass", "area", "centroid", "inertia", "principal_moments"}
    assert np.shape(d["inertia"]) == (3, 3) and np.shape(d["error"]["inertia"]) == (3, 3)
    assert d["volume"] == pytest.approx(6.0) and d["units"] == "mm"
    with pytest.raises(Exception, match="cannot assign"):
        p.volume = 2.0


def test_mesh_moments_reference_point_invariant():
    mesh = pv.Sphere(radius=0.7, theta_resolution=20, phi_resolution=20).triangulate().clean()
    pts, tri = np.asarray(mesh.points), mesh.faces.reshape(-1, 4)[:, 1:]
    a = mesh_moments(pts, tri, center=np.zeros(3))
    b = mesh_moments(pts, tri, center=np.array([5.0, -3.0, 2.0]))
    assert a.volume == pytest.approx(b.volume, rel=1e-12)
    np.testing.assert_allclose(a.m1, b.m1 + b.volume * (np.array([5.0, -3.0, 2.0])), atol=1e-11)


# ---------------------------------------------------------------------------
# solids: closed forms, error estimates that bracket the true error
# ---------------------------------------------------------------------------

def _check_part(name, n):
    s, V, A, c, moments, smooth, size = PARTS[name]
    p = mass_properties(s, resolution=n, mesher=MESHER)
    err_v = abs(p.volume - V)
    err_c = np.abs(p.centroid - c)
    err_i = np.abs(p.principal_moments - moments)
    # the estimate brackets the true error on every quantity
    assert err_v <= p.error.volume, (name, n, err_v, p.error.volume)
    assert np.all(err_c <= p.error.centroid), (name, n, err_c, p.error.centroid)
    assert np.all(err_i <= p.error.principal_moments), (name, n, err_i, p.error.principal_moments)
    assert abs(p.area - A) <= p.error.area, (name, n, p.area - A, p.error.area)
    return p, err_v / V, err_c.max() / size, err_i.max() / max(moments)


@pytest.mark.parametrize("name", sorted(set(PARTS) - {"sphere0"}))
def test_reference_parts_at_64(name):
    _, ev, ec, ei = _check_part(name, 64)
    smooth = PARTS[name][5]
    tol = SMOOTH_TOL if smooth else SHARP_TOL
    assert ev <= tol and ei <= tol
    assert ec <= (CENTROID_TOL if smooth else CENTROID_SHARP_TOL)


@pytest.mark.parametrize("name", ["sphere0", "torus", "hemisphere"])
def test_richardson_at_128(name):
    _, ev, ec, ei = _check_part(name, 128)
    if PARTS[name][5]:
        assert ev <= RICHARDSON_TOL
        assert ei <= 10 * RICHARDSON_TOL
        assert ec <= CENTROID_TOL
    else:
        assert ev <= SMOOTH_TOL and ei <= SMOOTH_TOL


def test_convergence_order_at_least_two():
    """Raw marching-cubes volumes converge as h^2 (error / 4 per doubling);
    with the shell correction and extrapolation, far faster."""
    s, V = PARTS["torus"][0], PARTS["torus"][1]
    errs = [abs(mass_properties(MESHER(s, 2.6 / n)).volume - V) for n in (16, 32, 64)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders >= 1.9), orders
    fine = [abs(mass_properties(s, resolution=n, mesher=MESHER).volume - V) for n in (32, 64)]
    assert np.log2(fine[0] / fine[1]) >= 3.5
    assert fine[1] < errs[2] / 100


def test_boolean_with_known_volume():
    """A box minus a through-hole, and two disjoint parts, by inclusion-exclusion."""
    plate = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0)
    V = 1.0 - np.pi * 0.25 ** 2 * 0.5
    p = mass_properties(plate, resolution=64, mesher=MESHER)
    assert abs(p.volume - V) <= p.error.volume
    assert abs(p.volume - V) / V <= SHARP_TOL
    two = sphere(0.5, center=(-1, 0, 0)) | sphere(0.25, center=(1, 0, 0))
    v1, v2 = 4 / 3 * np.pi * 0.125, 4 / 3 * np.pi * 0.25 ** 3
    p = mass_properties(two, resolution=64, mesher=MESHER)
    assert p.volume == pytest.approx(v1 + v2, rel=SMOOTH_TOL)
    assert p.centroid[0] == pytest.approx((-v1 + v2) / (v1 + v2), abs=CENTROID_TOL * 2.5)


def test_far_from_origin_solid():
    s = box((1.0, 0.7, 0.45)).translate((1e6, -1e6, 1e6))
    p = mass_properties(s, resolution=48, mesher=MESHER)
    np.testing.assert_allclose(p.centroid, [1e6, -1e6, 1e6], atol=CENTROID_SHARP_TOL)
    assert p.volume == pytest.approx(0.315, rel=SHARP_TOL)


def test_tolerance_drives_resolution():
    s, V = PARTS["torus"][0], PARTS["torus"][1]
    loose = mass_properties(s, tolerance=1e-2, mesher=MESHER)
    tight = mass_properties(s, tolerance=1e-5, mesher=MESHER)
    assert tight.voxel_size < loose.voxel_size
    assert tight.error.volume <= 1e-5 * tight.volume
    assert abs(tight.volume - V) <= tight.error.volume


# ---------------------------------------------------------------------------
# octrees and grids: exact FULL cells, fractional BOUNDARY cells, rigorous bounds
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["sphere", "torus", "box", "cone"])
def test_octree_bounds_contain_true_volume(name):
    from spatial.cells.octree import Octree

    s, V, _, c, moments = PARTS[name][:5]
    tree = Octree.from_solid(s, resolution=32)
    lo, hi = tree.volume_bounds()
    assert lo <= V <= hi
    p = mass_properties(tree)
    assert lo <= p.volume <= hi
    assert abs(p.volume - V) <= p.error.volume
    assert np.all(np.abs(p.centroid - c) <= p.error.centroid)
    assert np.all(np.abs(p.principal_moments - moments) <= p.error.principal_moments)
    # fractional occupancy is second order: far better than the bound
    assert abs(p.volume - V) / V < 1e-2


def test_octree_full_cells_integrate_exactly():
    """A box aligned with the cells has no boundary inside it: exact moments."""
    from spatial.cells.octree import Octree

    s = box((1.0, 0.5, 0.25), center=(0.5, 0.25, 0.125))
    tree = Octree.from_solid(s, voxel_size=1 / 16, bounds=((0, 0, 0), (1, 1, 1)))
    p = mass_properties(tree)
    assert p.volume == pytest.approx(0.125, rel=0.05)
    lo, hi = tree.volume_bounds()
    assert lo <= 0.125 <= hi


@pytest.mark.parametrize("name", ["sphere", "torus", "cylinder"])
def test_occupancy_grid_fractional_occupancy(name):
    from spatial.cells.grid import OccupancyGrid

    s, V, A, c, moments = PARTS[name][:5]
    grid = OccupancyGrid.from_solid(s, resolution=48)
    p = mass_properties(grid)
    assert abs(p.volume - V) <= p.error.volume
    assert np.all(np.abs(p.centroid - c) <= p.error.centroid)
    assert np.all(np.abs(p.principal_moments - moments) <= p.error.principal_moments)
    assert abs(p.volume - V) / V < 3e-3                 # second order, far inside the bound
    assert p.area == pytest.approx(A, rel=2e-2)         # co-area estimate
    assert p.voxel_size == pytest.approx(grid.voxel_size)


def test_far_from_origin_smooth_part():
    far = np.array([1e6, -2e6, 5e5])
    s, V, _, c, moments, _, size = PARTS["torus"]
    p = mass_properties(s.translate(far), resolution=64, mesher=MESHER)
    assert np.abs(p.centroid - far).max() <= CENTROID_TOL * size
    assert p.volume == pytest.approx(V, rel=SMOOTH_TOL)
    np.testing.assert_allclose(p.principal_moments, moments, rtol=SMOOTH_TOL)



@settings(derandomize=True, max_examples=25, deadline=None)
@given(angles=st.tuples(*[st.floats(-np.pi, np.pi)] * 3),
       shift=st.tuples(*[st.floats(-1e3, 1e3)] * 3))
def test_rigid_motion_law(angles, shift):
    """A rigid motion moves the centroid and rotates the inertia tensor exactly."""
    mesh = pv.Box((0, 2, 0, 1, 0, 0.5)).triangulate().clean()
    base = mass_properties(mesh)
    ax, ay, az = angles
    rx = np.array([[1, 0, 0], [0, np.cos(ax), -np.sin(ax)], [0, np.sin(ax), np.cos(ax)]])
    ry = np.array([[np.cos(ay), 0, np.sin(ay)], [0, 1, 0], [-np.sin(ay), 0, np.cos(ay)]])
    rz = np.array([[np.cos(az), -np.sin(az), 0], [np.sin(az), np.cos(az), 0], [0, 0, 1]])
    rot = rz @ ry @ rx
    moved = pv.PolyData(mesh.points @ rot.T + np.array(shift), mesh.faces)
    p = mass_properties(moved)
    assert p.volume == pytest.approx(base.volume, rel=1e-11)
    np.testing.assert_allclose(p.centroid, rot @ base.centroid + shift, atol=1e-9)
    np.testing.assert_allclose(p.inertia, rot @ base.inertia @ rot.T, atol=1e-10)
    np.testing.assert_allclose(p.principal_moments, base.principal_moments, rtol=1e-9)


@pytest.mark.parametrize("n", [32, 64])
def test_thin_bracket_error_brackets_volume(n):
    """An L bracket (4 mm plates, re-entrant edge, four holes): the estimate
    holds even where two extrapolations happen to agree."""
    from implicit import union

    base = box((50.0, 30.0, 4.0), center=(25.0, 15.0, 2.0))
    upright = box((4.0, 30.0, 40.0), center=(2.0, 15.0, 20.0))
    holes = [cylinder(3.0, 12.0, center=(x, 15.0, 2.0)) for x in (4 + 46 / 3, 4 + 92 / 3)]
    holes += [cylinder(3.0, 12.0, center=(2.0, 15.0, z), axis=(1, 0, 0)) for z in (4 + 12, 4 + 24)]
    part = union(base, upright) - holes[0] - holes[1] - holes[2] - holes[3]
    V = 10320.0 - 4 * np.pi * 9.0 * 4.0
    p = mass_properties(part, resolution=n, mesher=MESHER)
    assert abs(p.volume - V) <= p.error.volume
    assert abs(p.volume - V) / V <= SHARP_TOL
