"""The analysis commands: implicad mass, check, section, interfere."""

import json

import numpy as np
import pytest

from spatial.cli import main

SPHERE = "from implicit import sphere\nsolid = sphere(1.0, center=(1.0, 2.0, 3.0))\n"
TWO = "from implicit import sphere\nsolid = sphere(0.5) | sphere(0.5, center=(3, 0, 0))\n"
PLATE = "from implicit import box, cylinder\nsolid = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0)\n"
ASSEMBLY = """from implicit import box, cylinder
parts = {
    "plate": box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0),
    "pin": cylinder(0.3, 1.0),
    "cap": box((0.5, 0.5, 0.2), center=(0.0, 0.0, 2.0)),
    "far": box(0.5, center=(5.0, 5.0, 5.0)),
}
"""


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_mass_json(tmp_path, capsys):
    model = _write(tmp_path, "ball.py", SPHERE)
    assert main(["mass", model, "--density", "7850", "--units", "mm", "--resolution", "64", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("volume", "mass", "area", "centroid", "inertia", "inertia_origin", "principal_moments",
                "principal_axes", "error", "voxel_size", "units", "density"):
        assert key in d
    V = 4 * np.pi / 3
    assert d["volume"] == pytest.approx(V, rel=1e-6)
    assert d["mass"] == pytest.approx(7850 * V * 1e-9, rel=1e-6)
    assert d["units"] == "mm" and d["density"] == 7850
    np.testing.assert_allclose(d["centroid"], [1, 2, 3], atol=1e-8)
    assert np.shape(d["inertia"]) == (3, 3) and np.shape(d["error"]["inertia_origin"]) == (3, 3)
    assert set(d["error"]) >= {"volume", "mass", "area", "centroid", "inertia", "principal_moments"}
    assert abs(d["volume"] - V) <= d["error"]["volume"]


def test_mass_table_and_mesh_file(tmp_path, capsys):
    import pyvista as pv

    stl = str(tmp_path / "block.stl")
    pv.Box((0, 2, 0, 1, 0, 1)).triangulate().save(stl)
    assert main(["mass", stl, "--density", "1000"]) == 0
    out = capsys.readouterr().out
    assert "volume" in out and "kg*m^2" in out
    line = [ln for ln in out.splitlines() if ln.startswith("volume")][0]
    assert float(line.split()[1]) == pytest.approx(2.0, rel=1e-9)
    assert main(["mass", stl, "--resolution", "32"]) == 2
    assert "mesh file is integrated exactly" in capsys.readouterr().err


def test_mass_errors(tmp_path, capsys):
    model = _write(tmp_path, "ball.py", SPHERE)
    assert main(["mass", model, "--density", "-1"]) == 2
    assert "density" in capsys.readouterr().err
    assert main(["mass", str(tmp_path / "missing.py")]) == 2
    with pytest.raises(SystemExit) as exc:
        main(["mass", model, "--units", "furlong"])
    assert exc.value.code == 2


def test_check_exit_status(tmp_path, capsys):
    good = _write(tmp_path, "plate.py", PLATE)
    assert main(["check", good, "--resolution", "32"]) == 0
    out = capsys.readouterr().out
    assert "valid:     yes" in out and "genus:     1" in out and "Euler-Poincare" in out
    bad = _write(tmp_path, "two.py", TWO)
    assert main(["check", bad, "--resolution", "32", "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["valid"] is False and d["bodies"] == 2
    assert any("isolated parts" in f for f in d["flags"])


def test_section_outputs(tmp_path, capsys):
    model = _write(tmp_path, "plate.py", PLATE)
    png, svg, js = tmp_path / "s.png", tmp_path / "s.svg", tmp_path / "s.json"
    assert main(["section", model, "--plane", "z=0.1", "-o", str(png), "--svg", str(svg),
                 "--json", str(js), "--resolution", "128"]) == 0
    out = capsys.readouterr().out
    assert "1 holes" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = svg.read_text()
    assert text.startswith("<svg") and 'fill-rule="evenodd"' in text and text.count(" Z") == 2
    d = json.loads(js.read_text())
    assert d["area"] == pytest.approx(2.0 - np.pi * 0.0625, rel=1e-6)
    assert sorted(lp["hole"] for lp in d["loops"]) == [False, True]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".section-")]
    assert main(["section", model, "--point", "0", "0", "0", "--normal", "1", "0", "0", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["area"] == pytest.approx(1.0 * 0.5 - 0.5 * 0.5, rel=1e-6)     # hole cut through its axis


def test_section_errors(tmp_path, capsys):
    model = _write(tmp_path, "plate.py", PLATE)
    assert main(["section", model, "--plane", "w=2"]) == 2
    assert "plane" in capsys.readouterr().err
    assert main(["section", model, "-o", str(tmp_path / "nope" / "s.png")]) == 2
    assert main(["section", model, "-o", str(tmp_path / "s.txt")]) == 2
    assert "expected a .png" in capsys.readouterr().err


def test_interfere(tmp_path, capsys):
    asm = _write(tmp_path, "asm.py", ASSEMBLY)
    assert main(["interfere", asm, "--resolution", "32", "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["parts"] == 4 and d["pairs_possible"] == 6 and d["full_checks"] == 1
    assert [(p["a"], p["b"]) for p in d["interfering"]] == [("plate", "pin")]
    ring = np.pi * (0.3 ** 2 - 0.25 ** 2) * 0.5
    assert abs(d["interfering"][0]["volume"] - ring) <= d["interfering"][0]["volume_error"]
    assert main(["interfere", asm, "--resolution", "32"]) == 1
    assert "INTERFERE  plate / pin" in capsys.readouterr().out
    ok = _write(tmp_path, "ok.json", json.dumps({"parts": {
        "a": {"kind": "sphere", "radius": 1.0, "center": [0, 0, 0]},
        "b": {"kind": "sphere", "radius": 1.0, "center": [5, 0, 0]}}}))
    assert main(["interfere", ok]) == 0
    assert "no interference" in capsys.readouterr().out
