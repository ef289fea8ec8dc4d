"""Memory estimated from the lattice before anything is allocated; what would not fit is refused."""

import time

import pytest

from implicit import box, sphere
from spatial.cells.budget import check_mesh_memory, check_tet_memory, estimate_mesh_bytes, estimate_tet_bytes
from spatial.cli import main


def test_estimates_follow_area_and_volume():
    unit = ([0, 0, 0], [1, 1, 1])
    a = estimate_mesh_bytes(unit, 0.01)
    assert estimate_mesh_bytes(unit, 0.005) == pytest.approx(4 * a)          # surface: 1/h^2
    assert estimate_mesh_bytes(([0, 0, 0], [2, 2, 2]), 0.01) == pytest.approx(4 * a)
    assert estimate_tet_bytes(unit, 0.05) == pytest.approx(8 * estimate_tet_bytes(unit, 0.1))
    with pytest.raises(MemoryError, match="use a voxel size of at least"):
        check_mesh_memory(unit, 0.01, max_bytes=a / 2)
    assert check_mesh_memory(unit, 0.01, max_bytes=2 * a) == a
    with pytest.raises(MemoryError, match="tetrahedra of size"):
        check_tet_memory(unit, 0.01, max_bytes=1e9)
    with pytest.raises(ValueError, match="bounds"):
        estimate_mesh_bytes(([0, 0, 0], [1, 1, float("inf")]), 0.1)


def test_huge_resolution_is_refused_at_once(tmp_path, capsys):
    from spatial.meshing.boundary import mesh

    t0 = time.perf_counter()
    with pytest.raises(MemoryError, match="GB"):
        mesh(sphere(1.0), resolution=20000, progress=False)
    model = tmp_path / "ball.py"
    model.write_text("from implicit import sphere\nsolid = sphere(1.0)\n")
    assert main(["mesh", str(model), "--resolution", "20000", "-o", str(tmp_path / "b.stl")]) == 2
    assert main(["fea", str(model), "--size", "1e-5", "-o", str(tmp_path / "b.msh")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 2 and "GB" in err
    assert time.perf_counter() - t0 < 30
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ball.py"]
    assert mesh(box(1.0), resolution=16, progress=False).n_cells > 0
