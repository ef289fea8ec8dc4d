"""`check` says what is wrong: degenerate and duplicate triangles, vertices at one position, bodies, shells."""

import subprocess
import sys

import numpy as np
import pyvista as pv

import implicit as I
from spatial import check, mesh, triangle_defects  # noqa: F401


def _sphere():
    return pv.Sphere(theta_resolution=16, phi_resolution=12).triangulate().clean()


def test_degenerate_and_duplicate_triangles_are_named():
    s = _sphere()
    f = s.faces.reshape(-1, 4)
    extra = np.array([[3, 0, 0, 1], [3, *f[0, 1:]]])
    bad = pv.PolyData(s.points, np.concatenate([f, extra]).ravel())
    r = check(bad)
    assert not r.valid
    assert (r.degenerate_triangles, r.duplicate_triangles) == (1, 1)
    assert any("degenerate" in x for x in r.flags) and any("duplicate triangles" in x for x in r.flags)


def test_duplicate_vertex_positions_and_nonfinite_vertices():
    s = _sphere()
    f = s.faces.reshape(-1, 4).copy()
    g = f.copy()
    g[:, 1:] += s.n_points
    # the same sphere twice, unwelded: every position twice
    two = pv.PolyData(np.concatenate([s.points, s.points]), np.concatenate([f, g]).ravel())
    r = check(two, assembly=True)
    assert r.duplicate_vertices == s.n_points and not r.valid
    pts = np.array(s.points)
    pts[3] = np.nan
    r = check(pv.PolyData(pts, s.faces))
    assert r.nonfinite_vertices == 1 and not r.finite and not r.valid


def test_bodies_shells_and_genus_apart():
    r = check(I.sphere(1) - I.sphere(0.5), resolution=24)
    assert (r.bodies, r.shells, r.genus, r.valid) == (1, 2, 0, True)
    r = check(I.torus(1, 0.3) | I.sphere(0.5, (4, 0, 0)), resolution=32)
    assert (r.bodies, r.shells, r.genus) == (2, 2, 1)
    assert not r.valid
    r = check(I.torus(1, 0.3) | I.sphere(0.5, (4, 0, 0)), resolution=32, assembly=True)
    assert r.valid and r.assembly


def test_touching_union_checks_as_one_body():
    for res in (63, 64, 100, 128):
        r = check(mesh(I.box((4, 4, 1)) | I.box((1, 1, 1), center=(0, 0, 1)), resolution=res, progress=False))
        assert r.valid and r.bodies == 1


def test_cli_check_assembly(tmp_path):
    model = tmp_path / "two.py"
    model.write_text("from implicit import sphere\nsolid = sphere(1) | sphere(1, center=(3, 0, 0))\n")
    run = [sys.executable, "-m", "spatial.cli", "check", str(model), "--resolution", "24"]
    single = subprocess.run(run, capture_output=True, text=True)
    assert single.returncode == 1 and "isolated parts: 2" in single.stdout
    both = subprocess.run(run + ["--assembly"], capture_output=True, text=True)
    assert both.returncode == 0 and "bodies:    2" in both.stdout


def test_cli_mesh_of_a_thin_plate_prints_no_writer_errors(tmp_path):
    model = tmp_path / "plate.py"
    model.write_text("from implicit import box\nsolid = box((100, 100, 1))\n")
    coarse = subprocess.run([sys.executable, "-m", "spatial.cli", "mesh", str(model), "-o", str(tmp_path / "a.stl"),
                             "--resolution", "64", "--quiet"], capture_output=True, text=True)
    assert coarse.returncode == 1
    assert "vtk" not in coarse.stderr.lower() and "ERR" not in coarse.stderr
    assert "thinnest wall" in coarse.stderr and not (tmp_path / "a.stl").exists()
    assert [line.startswith("implicad: ") for line in coarse.stderr.splitlines()] == [True] * 3
