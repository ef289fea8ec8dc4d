"""`implicad mesh`: files by extension, summary line, errors before work."""

import os

import pytest

from spatial.cli import main
from spatial.files.meshes import load_mesh

from meshcheck import topology

MODEL = "from implicit import sphere, torus\nsolid = torus(1.0, 0.3)\n"


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "part.py"
    path.write_text(MODEL)
    return path


def test_writes_mesh_and_summary(tmp_path, model, capsys):
    out = tmp_path / "part.stl"
    assert main(["mesh", str(model), "-o", str(out), "--resolution", "32"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""  # no progress bar when stderr is not a terminal
    line = captured.out.strip()
    assert len(line.splitlines()) == 1
    back = load_mesh(out)
    assert f"{back.n_cells} triangles" in line and f"{back.n_points} vertices" in line
    assert "watertight yes" in line and "evaluations" in line and " s, " in line
    assert topology(back)["euler"] == 0


def test_voxel_size_bounds_and_no_refine(tmp_path, capsys):
    path = tmp_path / "half.py"
    path.write_text("from implicit import halfspace\nsolid = halfspace((0, 0, 1))\n")
    out = tmp_path / "half.ply"
    assert main(["mesh", str(path), "-o", str(out), "--voxel-size", "0.25",
                 "--bounds", "-1", "-1", "-1", "1", "1", "0", "--no-refine", "--no-features"]) == 0
    assert "watertight yes" in capsys.readouterr().out
    assert load_mesh(out).volume == pytest.approx(4.0 - 20 * 0.25 ** 2 / 2, rel=0.05)  # cut box edges
    # the default rebuilds the edges of the clipping box too
    assert main(["mesh", str(path), "-o", str(out), "--voxel-size", "0.25",
                 "--bounds", "-1", "-1", "-1", "1", "1", "0", "--no-refine"]) == 0
    assert "watertight yes" in capsys.readouterr().out
    assert load_mesh(out).volume == pytest.approx(4.0, rel=2e-3)
    # unbounded without --bounds: one line naming the fix, exit 2
    assert main(["mesh", str(path), "-o", str(tmp_path / "x.stl"), "--resolution", "8"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("implicad: error:") and "bounds" in err and len(err.strip().splitlines()) == 1


def test_unknown_extension_refused_before_loading(tmp_path, capsys):
    bad = tmp_path / "boom.py"
    bad.write_text("raise SystemExit('the model must not be loaded')\n")
    assert main(["mesh", str(bad), "-o", str(tmp_path / "part.step"), "--resolution", "8"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "unknown mesh format '.step'" in err and ".stl" in err and ".vtk" in err
    assert sorted(os.listdir(tmp_path)) == ["boom.py"]


def test_needs_at_most_one_size(tmp_path, model):
    with pytest.raises(SystemExit):
        main(["mesh", str(model), "-o", str(tmp_path / "a.stl"), "--resolution", "8", "--voxel-size", "0.1"])


def test_default_size_from_the_part(tmp_path, model, capsys):
    assert main(["mesh", str(model), "-o", str(tmp_path / "a.stl"), "--quiet"]) == 0
    assert "watertight yes" in capsys.readouterr().out


def test_features_by_default_and_no_features_for_the_plain_mesh(tmp_path, capsys):
    """The default rebuilds the box's edges and corners: its volume is the box's; --no-features writes
    the plain marching-cubes mesh, whose chamfered edges lose volume."""
    path = tmp_path / "cube.py"
    path.write_text("from implicit import box\nsolid = box(1.0)\n")
    volumes = {}
    for flag in ([], ["--features"], ["--no-features"]):
        out = tmp_path / f"cube{len(volumes)}.stl"
        assert main(["mesh", str(path), "-o", str(out), "--resolution", "10", "--quiet"] + flag) == 0
        assert "watertight yes" in capsys.readouterr().out
        volumes[" ".join(flag)] = load_mesh(out).volume
    assert volumes[""] == volumes["--features"] == pytest.approx(1.0, abs=5e-4)   # measured 0.99964
    assert volumes["--no-features"] < 0.95                                          # measured 0.9451


def test_features_refused_for_a_mesh_in_parts(tmp_path, capsys):
    """A .pvtp in parts is written brick by brick, without the feature pass: --features is refused
    before any cluster starts or file is written (the default there is the plain mesh)."""
    path = tmp_path / "cube.py"
    path.write_text("from implicit import box\nsolid = box(1.0)\n")
    assert main(["mesh", str(path), "-o", str(tmp_path / "cube.pvtp"), "--resolution", "8", "--workers", "2",
                 "--features"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--features" in err and "--no-features" in err
    assert sorted(os.listdir(tmp_path)) == ["cube.py"]
