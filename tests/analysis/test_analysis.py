"""Topology, Euler-Poincare and validity checks of meshes and solids."""

import numpy as np
import pytest
import pyvista as pv

from implicit import box, cylinder, halfspace, sphere, torus
from spatial.analysis.validity import check, topology
from test_mass import MESHER

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))


def _cube(lo=0.0, hi=1.0):
    return pv.Box((lo, hi, lo, hi, lo, hi)).triangulate().clean()


def test_sphere_mesh_topology():
    t = topology(pv.Sphere(theta_resolution=16, phi_resolution=16).triangulate().clean())
    assert (t.shells, t.genus, t.euler, t.loops) == (1, 0, 2, 0)
    assert t.closed and t.manifold and t.oriented and t.signed_volume > 0
    assert t.vertices - t.edges + t.faces == 2
    assert 3 * t.faces == 2 * t.edges
    assert t.euler_poincare == (2, 2) and t.euler_poincare_holds


def test_benchmark_part_genus_five():
    report = check(BENCH, resolution=48, mesher=MESHER)
    t = report.topology
    assert report.valid and report.bodies == 1
    assert t.genus == 5 and t.euler == -8 and t.shell_euler == (-8,)
    lhs, rhs = t.euler_poincare
    assert lhs == rhs == 2 * (1 - 5)


def test_torus_and_void():
    t = check(torus(1.0, 0.3), resolution=32, mesher=MESHER).topology
    assert t.genus == 1 and t.euler == 0
    hollow = check(sphere(1.0) - sphere(0.5), resolution=32, mesher=MESHER)
    assert hollow.valid and hollow.bodies == 1
    assert hollow.topology.shells == 2 and hollow.topology.euler == 4
    vols = sorted(hollow.topology.shell_volume)
    assert vols[0] < 0 < vols[1]                      # the void's shell encloses negative volume


def test_isolated_parts_flagged():
    report = check(sphere(0.5) | sphere(0.3, center=(2.0, 0, 0)), resolution=32, mesher=MESHER)
    assert not report.valid and report.bodies == 2
    assert any("isolated parts" in f for f in report.flags)


def test_open_shell_flagged():
    mesh = _cube()
    open_mesh = pv.PolyData(mesh.points, mesh.faces.reshape(-1, 4)[1:].ravel())
    report = check(open_mesh)
    assert not report.valid and not report.closed
    assert report.topology.open_edges == 3
    assert any("open shell" in f for f in report.flags)
    # the open form of the law: F - E + V = B - G for a disc-like open shell
    t = report.topology
    assert t.faces - t.edges + t.vertices == 1


def test_inconsistent_orientation_and_inside_out():
    mesh = _cube()
    faces = mesh.faces.reshape(-1, 4).copy()
    faces[0, 1:] = faces[0, 1:][::-1]
    report = check(pv.PolyData(mesh.points, faces.ravel()))
    assert not report.oriented and not report.valid
    faces = mesh.faces.reshape(-1, 4).copy()
    faces[:, 1:] = faces[:, 1:, ][:, ::-1]
    report = check(pv.PolyData(mesh.points, faces.ravel()))
    assert report.oriented and report.volume < 0 and not report.valid
    assert any("inside out" in f for f in report.flags)


def test_nonmanifold_vertex_and_edge():
    pinched = (_cube(0, 1) + _cube(1, 2)).clean()
    t = topology(pinched)
    assert t.nonmanifold_vertices == 1 and t.nonmanifold_edges == 0
    a = _cube(0, 1)
    b = a.copy()
    b.points = b.points + np.array([1.0, 1.0, 0.0])
    t = topology((a + b).clean())                    # two cubes sharing an edge
    assert t.nonmanifold_edges == 1
    assert not check((a + b).clean()).manifold


def test_infinite_and_not_finite():
    report = check(halfspace((0, 0, 1)))
    assert not report.valid and not report.bounded
    assert any("infinite extent" in f for f in report.flags)
    bad = _cube()
    bad.points[0] = [np.nan, 0, 0]
    assert not check(bad).finite
    with pytest.raises(ValueError, match="resolution"):
        check(sphere(1.0), resolution=1)


def test_report_text_and_dict():
    report = check(_cube())
    assert report.valid
    text = report.summary()
    assert "Euler-Poincare" in text and "holds" in text
    d = report.to_dict()
    assert d["topology"]["euler"] == 2 and d["bodies"] == 1
