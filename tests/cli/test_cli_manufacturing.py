"""The manufacturing and inspection commands: slice, toolpath, inspect, stackup, bom."""

import json
import os

import numpy as np
import pytest

from spatial.cli import main

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")


@pytest.fixture
def stepped(tmp_path):
    path = tmp_path / "stepped.py"
    path.write_text("from implicit import box, cylinder\n"
                    "solid = (box((4.0, 3.0, 1.0)) | box((2.0, 1.5, 1.0), center=(0, 0, 1.0))) - cylinder(0.4, 6)\n")
    return str(path)


def test_slice_writes_json_csv_svg(stepped, tmp_path, capsys):
    for ext in ("json", "csv", "svg"):
        out = tmp_path / f"s.{ext}"
        assert main(["slice", stepped, "--layer", "0.5", "--resolution", "48", "-o", str(out)]) == 0
    d = json.loads((tmp_path / "s.json").read_text())
    assert [round(ly["z"], 9) for ly in d["layers"]] == [-0.25, 0.25, 0.75, 1.25]
    assert d["layers"][0]["area"] == pytest.approx(12 - 0.16 * np.pi, rel=1e-4)
    assert d["layers"][3]["area"] == pytest.approx(3 - 0.16 * np.pi, rel=1e-3)        # corners cut by chords
    assert "volume of the layers" in capsys.readouterr().out


def test_toolpath_writes_gcode_and_verifies(stepped, tmp_path, capsys):
    ngc = tmp_path / "part.ngc"
    assert main(["toolpath", stepped, "--tool-radius", "0.25", "--resolution", "48", "-o", str(ngc), "--verify",
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    text = ngc.read_text()
    assert text.startswith("%\n(implicad 2.5D milling") and "G21" in text and "M5" in text
    assert summary["verification"]["gouge_volume"] < 1e-3 and summary["verification"]["rapid_volume"] == 0
    assert 0.5 in [round(z, 9) for z in summary["depths"]]


def test_toolpath_refuses_a_narrow_hole(tmp_path, capsys):
    path = tmp_path / "narrow.py"
    path.write_text("from implicit import box, cylinder\nsolid = box((3.0, 3.0, 1.0)) - cylinder(0.3, 4)\n")
    out = tmp_path / "x.ngc"
    assert main(["toolpath", str(path), "--tool-radius", "0.4", "--resolution", "32", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "narrower than the tool diameter 0.8" in err and "near (" in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_inspect_json_and_exit_status(tmp_path, capsys):
    from implicit import sphere
    from spatial.meshing import mesh

    model = tmp_path / "ball.py"
    model.write_text("from implicit import sphere\nsolid = sphere(1.0)\n")
    scan = tmp_path / "scan.xyz"
    np.savetxt(scan, mesh(sphere(1.01), resolution=20).points)
    assert main(["inspect", str(model), str(scan), "--tolerance", "0.02", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["mean_deviation"] == pytest.approx(0.01, abs=2e-4) and d["within_tolerance"] == 1.0
    assert np.array(d["transform"]).shape == (4, 4)
    assert main(["inspect", str(model), str(scan), "--tolerance", "0.005"]) == 1
    assert "FAIL" in capsys.readouterr().out
    assert main(["inspect", str(model), str(tmp_path / "scan.step")]) == 2


def test_stackup_example(capsys):
    path = os.path.join(EXAMPLES, "stackup.py")
    assert main(["stackup", path, "--samples", "20", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["nominal"] == pytest.approx((8.0 - 7.95) / 2, abs=1e-6)
    assert d["worst_min"] == pytest.approx((8.0 - 7.95) / 2 - 0.02, abs=1e-6)
    assert max(d["contributions"], key=d["contributions"].get) == "e"


def test_bom_of_the_example_assembly(tmp_path, capsys):
    out = tmp_path / "bom.csv"
    assert main(["bom", os.path.join(EXAMPLES, "assembly.py"), "-o", str(out), "--tolerance", "1e-2"]) == 0
    text = out.read_text()
    assert text.splitlines()[0].startswith("item,part,family")
    assert "hole_plate" in text and "aluminium" in text and "oak" in text
    assert main(["bom", os.path.join(EXAMPLES, "assembly.py"), "--material", "plate=unobtainium"]) == 2
    assert "unknown material" in capsys.readouterr().err
