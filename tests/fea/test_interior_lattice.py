"""The interior points `tet_mesh` gives TetGen: a body-centred cubic lattice clear of the surface."""

import numpy as np
import pyvista as pv
import pytest
from scipy.spatial import cKDTree

from implicit import box, sphere
from spatial.fea import tet_mesh
from spatial.fea.tetmesh import LATTICE_CLEARANCE, interior_lattice

SIZE = 0.2


def test_lattice_points_are_inside_clear_of_the_surface_and_body_centred():
    surface = pv.Sphere(radius=1.0, theta_resolution=80, phi_resolution=80)
    spts = np.asarray(surface.points, dtype=np.float64)
    pts = interior_lattice(sphere(1.0), spts, SIZE)
    clear = LATTICE_CLEARANCE * SIZE
    # Inside the unit ball by the clearance, and as far from every surface vertex.
    assert np.linalg.norm(pts, axis=1).max() < 1.0 - clear
    assert cKDTree(spts).query(pts)[0].min() >= clear
    # Body-centred cubic: each point's nearest neighbours at half the cube's diagonal.
    d, _ = cKDTree(pts).query(pts, k=2)
    np.testing.assert_allclose(d[:, 1], 0.5 * np.sqrt(3.0) * SIZE, rtol=1e-9)
    # Two points per cube of side SIZE in the ball of radius 1 - clearance (up to the lattice's rim).
    expected = 2 * (4.0 / 3.0) * np.pi * (1.0 - clear) ** 3 / SIZE**3
    assert len(pts) == pytest.approx(expected, rel=0.08)


def test_a_solid_thinner_than_twice_the_clearance_gets_no_lattice():
    plate = box((4.0, 4.0, 0.2))
    surface = pv.Box(bounds=(-2, 2, -2, 2, -0.1, 0.1), level=8).triangulate()
    assert len(interior_lattice(plate, np.asarray(surface.points, dtype=np.float64), SIZE)) == 0


def test_tet_mesh_fills_the_bulk_from_the_lattice_at_the_asked_quality():
    m = tet_mesh(sphere(1.0), size=SIZE, reference_volume=4.0 / 3.0 * np.pi)
    assert m.info["lattice_points"] > 500
    assert m.quality.min_dihedral >= 10.0 and m.quality.max_radius_edge <= 3.0
    # The lattice points are nodes of the mesh (TetGen keeps every input point).
    assert m.info["tetgen_points"] >= m.info["surface_points"] + m.info["lattice_points"]
    # Edges of about the size asked, not finer (the lattice's cube side is the size).
    e = np.unique(np.sort(m.tets[:, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]].reshape(-1, 2), axis=1), axis=0)
    median = float(np.median(np.linalg.norm(m.points[e[:, 0]] - m.points[e[:, 1]], axis=1)))
    assert 0.75 * SIZE < median < 1.05 * SIZE
