"""Triangle surfaces as arrays (`spatial.files.surface`): the meshers' output inside `arrays_only`,
written as the same STL bytes as the PolyData, manifold exactly when pyvista says so."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import pyvista as pv

from implicit import box, cylinder, sphere
from spatial.files import save_mesh
from spatial.files.surface import TriangleArrays, arrays_only, arrays_wanted, triangle_surface
from spatial.meshing import mesh

PART = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0))


def test_the_switch_is_scoped():
    assert not arrays_wanted()
    with arrays_only():
        assert arrays_wanted()
        assert isinstance(triangle_surface(np.eye(3), [[0, 1, 2]]), TriangleArrays)
    assert not arrays_wanted()
    assert isinstance(triangle_surface(np.eye(3), [[0, 1, 2]]), pv.PolyData)


@pytest.mark.parametrize("features", [False, True])
def test_mesh_as_arrays_is_the_polydata_and_writes_the_same_stl(tmp_path, features):
    poly = mesh(PART, resolution=24, features=features)
    with arrays_only():
        arrays = mesh(PART, resolution=24, features=features)
    assert isinstance(arrays, TriangleArrays)
    assert np.array_equal(arrays.points, poly.points)
    assert np.array_equal(arrays.triangles, poly.faces.reshape(-1, 4)[:, 1:])
    assert set(arrays.field_data) == set(poly.field_data.keys())
    assert int(arrays.field_data["evaluations"][0]) == int(poly.field_data["evaluations"][0])
    assert set(arrays.point_data) == set(poly.point_data.keys())
    assert arrays.is_manifold is True and poly.is_manifold
    save_mesh(poly, tmp_path / "poly.stl")
    save_mesh(arrays, tmp_path / "arrays.stl")
    assert (tmp_path / "poly.stl").read_bytes() == (tmp_path / "arrays.stl").read_bytes()
    back = arrays.to_polydata()
    assert back.n_cells == poly.n_cells and np.array_equal(back.faces, poly.faces)
    assert np.array_equal(back.field_data["voxel_size"], poly.field_data["voxel_size"])


def test_other_formats_go_through_polydata(tmp_path):
    with arrays_only():
        arrays = mesh(sphere(1.0), resolution=12)
    save_mesh(arrays, tmp_path / "ball.ply")
    read = pv.read(tmp_path / "ball.ply")
    assert read.n_cells == arrays.n_cells and read.n_points == arrays.n_points


def test_empty_mesh_inside_the_switch_is_arrays():
    with arrays_only(), pytest.warns(RuntimeWarning, match="empty"):
        empty = mesh(sphere(1.0) - sphere(2.0), resolution=8)
    assert isinstance(empty, TriangleArrays) and empty.n_cells == 0 and "voxel_size" in empty.field_data


@pytest.mark.parametrize("surface", [
    pv.Sphere().triangulate(), pv.Plane().triangulate(), pv.Box().triangulate(),
    # two closed boxes sharing nothing; a box with one triangle removed (open); a fin on a box (3 faces on an edge)
    (pv.Box().triangulate() + pv.Box().translate((3, 0, 0)).triangulate()).clean(),
    pv.Box().triangulate().remove_cells([0]),
], ids=["sphere", "plane", "box", "two boxes", "open box"])
def test_is_manifold_agrees_with_pyvista(surface):
    arrays = TriangleArrays(surface.points, surface.faces.reshape(-1, 4)[:, 1:])
    assert arrays.is_manifold is bool(surface.is_manifold)


def test_an_edge_of_three_triangles_is_not_manifold():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], float)
    faces = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    assert not TriangleArrays(points, faces).is_manifold


def test_the_mesh_command_writes_stl_without_vtk(tmp_path):
    out = tmp_path / "part.stl"
    code = ("import json, sys; from spatial.cli import main; "
            f"status = main(['mesh', 'examples/benchmark_part.py', '-o', {str(out)!r}, '--resolution', '24']); "
            "print(json.dumps(dict(status=status, vtk=[m for m in ('pyvista', 'vtkmodules') if m in sys.modules])))")
    import os

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=root)
    assert proc.returncode == 0, proc.stderr[-2000:]
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    assert result == {"status": 0, "vtk": []}
    assert "watertight yes" in proc.stdout
    read = pv.read(out)
    assert read.n_cells > 1000 and read.is_manifold
