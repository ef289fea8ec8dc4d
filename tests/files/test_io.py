"""Mesh files and OpenVDB level sets: formats, atomic writes, round trips."""

import os
import sys

import numpy as np
import pytest

from implicit import sphere, torus
from spatial import OccupancyGrid, mesh
from spatial.files import MESH_FORMATS, load_mesh, save_mesh
from spatial.cells.vdb import import_openvdb, load_vdb, mesh_to_solid, save_vdb, \
    vdb_metadata

from meshcheck import topology


@pytest.fixture(scope="module")
def ball():
    return mesh(sphere(1.0), resolution=16)


@pytest.mark.parametrize("ext", sorted(MESH_FORMATS))
def test_round_trip_every_format(tmp_path, ball, ext):
    path = save_mesh(ball, tmp_path / f"ball{ext}")
    assert os.listdir(tmp_path) == [f"ball{ext}"]
    back = load_mesh(path)
    assert back.n_cells == ball.n_cells
    assert back.n_points == ball.n_points
    assert topology(back)["edge_counts"] == {2}
    assert back.volume == pytest.approx(ball.volume, rel=1e-5)


def test_stl_is_binary_with_usual_permissions(tmp_path, ball):
    path = save_mesh(ball, tmp_path / "ball.STL")
    assert os.path.getsize(path) == 84 + 50 * ball.n_cells
    plain = tmp_path / "plain"
    plain.write_bytes(b"")
    assert os.stat(path).st_mode == os.stat(plain).st_mode


def test_stl_matches_vtk_writer(tmp_path, ball, monkeypatch):
    """The array writer (in chunks) writes VTK's records: the same corners byte for byte and the
    same unit normals (up to the sign of a zero component)."""
    import spatial.files.meshes as meshes

    monkeypatch.setattr(meshes, "_write_binary_stl",
                        lambda m, path, _w=meshes._write_binary_stl: _w(m, path, chunk=100))
    ours = np.fromfile(save_mesh(ball, tmp_path / "ours.stl"), dtype=np.uint8)
    ball.save(str(tmp_path / "vtk.stl"), binary=True)
    theirs = np.fromfile(tmp_path / "vtk.stl", dtype=np.uint8)
    assert ours.size == theirs.size == 84 + 50 * ball.n_cells
    assert ours[80:84].view("<u4")[0] == ball.n_cells
    a, b = ours[84:].reshape(-1, 50), theirs[84:].reshape(-1, 50)
    assert np.array_equal(a[:, 12:], b[:, 12:])
    na, nb = a[:, :12].copy().view("<f4"), b[:, :12].copy().view("<f4")
    assert np.array_equal(na, nb)  # -0.0 == 0.0
    assert np.allclose(np.linalg.norm(na, axis=1), 1.0, atol=1e-6)


def test_unknown_extension_refused_before_work(tmp_path):
    with pytest.raises(ValueError, match=r"unknown mesh format '\.step'.*\.stl.*\.ply.*\.obj.*\.vtp.*\.vtk"):
        save_mesh(None, tmp_path / "part.step")  # refused before the mesh is even looked at
    with pytest.raises(ValueError, match="no extension"):
        save_mesh(None, tmp_path / "part")
    with pytest.raises(TypeError, match="PolyData"):
        save_mesh("mesh", tmp_path / "part.stl")
    assert os.listdir(tmp_path) == []


def test_failed_write_leaves_nothing(tmp_path, ball, monkeypatch):
    target = tmp_path / "ball.ply"
    target.write_bytes(b"old contents")

    def broken(self, filename, *args, **kwargs):
        with open(filename, "wb") as fh:
            fh.write(b"half a file")
        raise OSError("disk full")

    monkeypatch.setattr(type(ball), "save", broken)
    with pytest.raises(OSError, match="disk full"):
        save_mesh(ball, target)
    assert os.listdir(tmp_path) == ["ball.ply"]
    assert target.read_bytes() == b"old contents"
    with pytest.raises(FileNotFoundError):
        save_mesh(ball, tmp_path / "missing" / "ball.stl")
    with pytest.raises(FileNotFoundError):
        load_mesh(tmp_path / "nothing.stl")


def test_missing_openvdb_names_the_package(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyopenvdb", None)
    with pytest.raises(ImportError, match="python3-openvdb"):
        import_openvdb()


def test_openvdb_marker_skips_or_fails_on_ci(monkeypatch):
    from conftest import require_openvdb

    monkeypatch.setitem(sys.modules, "pyopenvdb", None)
    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(pytest.skip.Exception, match="python3-openvdb"):
        require_openvdb()
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="CI=true"):
        require_openvdb()
    monkeypatch.delitem(sys.modules, "pyopenvdb")
    monkeypatch.delenv("CI")
    assert require_openvdb() is not None  # the real module (or a skip where it is missing)


def test_mesh_to_solid(requires_openvdb, tmp_path, ball):
    h = 0.05
    s = mesh_to_solid(ball, h)
    p = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.97, 0.0], [0.0, 0.0, 1.05], [3.0, 0.0, 0.0]])
    v = s(p)
    assert np.all(np.sign(v) == [-1, -1, -1, 1, 1])
    assert v[2] == pytest.approx(-0.03, abs=0.02) and v[3] == pytest.approx(0.05, abs=0.02)
    # narrow band: deep values are clamped, never larger than the true distance
    assert -0.5 < v[1] <= -0.1
    path = save_mesh(ball, tmp_path / "ball.stl")
    from_file = mesh_to_solid(path, h)
    assert np.allclose(from_file(p), v, atol=1e-5)
    # the level set meshes back to a closed surface
    again = mesh(s, voxel_size=h)
    assert topology(again)["euler"] == 2


def test_vdb_round_trip_with_metadata(requires_openvdb, tmp_path):
    s = torus(1.0, 0.3)
    path = save_vdb(s, tmp_path / "torus.vdb", voxel_size=0.05, units="cm")
    assert os.listdir(tmp_path) == ["torus.vdb"]
    meta = vdb_metadata(path)
    assert meta["voxel_size"] == pytest.approx(0.05) and meta["units"] == "cm"
    back = load_vdb(path)
    p = np.array([[1.0, 0.0, 0.0], [1.2, 0.0, 0.0], [0.0, 1.0, 0.25], [0.0, 0.0, 0.0]])
    true = s(p)
    got = back(p)
    near = np.abs(true) < 0.1
    assert np.allclose(got[near], true[near], atol=5e-3)
    assert np.all(np.sign(got) == np.sign(true))
    assert np.all(np.abs(got) <= np.abs(true) + 5e-3)
    grid = OccupancyGrid.from_solid(s, voxel_size=0.05)
    save_vdb(grid, tmp_path / "grid.vdb")
    assert np.allclose(load_vdb(tmp_path / "grid.vdb")(p)[near], true[near], atol=5e-3)
    with pytest.raises(ValueError, match=r"\.vdb"):
        save_vdb(s, tmp_path / "torus.stl", voxel_size=0.05)
    with pytest.raises(ValueError, match="voxel_size"):
        save_vdb(s, tmp_path / "t.vdb")
    with pytest.raises(TypeError, match="Solid or an OccupancyGrid"):
        save_vdb("torus", tmp_path / "t.vdb")
