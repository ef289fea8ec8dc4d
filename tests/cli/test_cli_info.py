"""`implicad info` and `implicad families`, model files and the examples."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from spatial.cli import main
from implicit.models import load_any, load_assembly, load_model

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_info_benchmark_part(capsys):
    status, out, err = run(capsys, "info", EXAMPLES / "benchmark_part.py")
    assert status == 0 and err == ""
    lines = out.splitlines()
    assert lines[1] == "tree:" and lines[2] == "  difference()"
    assert "      sphere(radius=1, center=[0, 0, 0])" in lines
    assert "nodes: 7  primitives: 5 (5 exact, 0 bound)  depth: 3" in out
    assert "kinds: box 1, cylinder 3, difference 1, intersection 1, sphere 1" in out
    assert "field: conservative bound (|f| <= distance), Lipschitz 1" in out
    assert "bounds: (-0.75, -0.75, -0.75) .. (0.75, 0.75, 0.75)  size 1.5 x 1.5 x 1.5" in out


def test_info_family_instance_shows_parameters(capsys):
    status, out, _ = run(capsys, "info", EXAMPLES / "bracket.py", "--no-tree")
    assert status == 0 and "tree:" not in out
    assert "family: l_bracket" in out
    assert "  leg_a = 50 mm" in out and "  holes_per_leg = 2\n" in out
    assert "bounds: (0, 0, 0) .. (50, 30, 40)" in out


def test_info_json(capsys):
    status, out, _ = run(capsys, "info", EXAMPLES / "bracket.py", "--json")
    data = json.loads(out)
    assert status == 0
    assert data["nodes"] == 9 and data["primitives"] == 6 and data["field"] == "bound"
    assert data["exact_primitives"] == 6
    assert data["bounds"] == [[0.0, 0.0, 0.0], [50.0, 30.0, 40.0]]
    assert data["families"][0]["family"] == "l_bracket"
    assert data["families"][0]["params"]["hole_diameter"] == 6.0
    assert data["tree"] == {"kind": "family", "family": "l_bracket", "params": data["families"][0]["params"]}


def test_info_json_tree_file_and_unbounded(capsys, tmp_path):
    status, out, _ = run(capsys, "info", EXAMPLES / "pulley.json", "--json")
    assert status == 0 and json.loads(out)["kinds"] == {"box": 1, "difference": 1, "revolve": 1}
    half = tmp_path / "half.json"
    half.write_text('{"kind": "halfspace", "normal": [0, 0, 1]}')
    status, out, _ = run(capsys, "info", half)
    assert status == 0
    assert "bounds: (-inf, -inf, -inf) .. (inf, inf, 0)  (unbounded: pass --bounds x0 y0 z0 x1 y1 z1" in out
    status, out, _ = run(capsys, "info", half, "--json")
    assert json.loads(out)["bounds"] == [[None, None, None], [None, None, 0.0]]


def test_info_assembly_lists_parts(capsys):
    status, out, _ = run(capsys, "info", EXAMPLES / "assembly.py", "--no-tree")
    assert status == 0 and out.startswith(f"assembly: {EXAMPLES / 'assembly.py'}  (3 parts)")
    assert "[plate]" in out and "[bolt]" in out and "[block]" in out


def test_families_listing(capsys):
    status, out, _ = run(capsys, "families")
    assert status == 0
    for name in ("hex_bolt:", "flanged_pipe:", "l_bracket:", "hole_plate:"):
        assert name in out
    assert "  hole_diameter  float  8        mm     > 0      hole diameter" in out
    status, out, _ = run(capsys, "families", "hex_bolt", "--json")
    data = json.loads(out)
    assert [p["name"] for p in data[0]["parameters"]] == ["diameter", "length", "head_height", "across_flats"]


@pytest.mark.parametrize("content, suffix, match", [
    (None, ".py", r"^implicad: error: .*missing\.py: No such file or directory$"),
    ("solid = 1 / 0\n", ".py", r"^implicad: error: .*part\.py: raised ZeroDivisionError: division by zero$"),
    ("def model():\n    return 1 / 0\n", ".py", r"^implicad: error: .*part\.py: model\(\) raised ZeroDivisionError: division by zero$"),
    ("x = 1\n", ".py", r"defines none of 'solid', 'model\(\)', 'parts' or 'assembly\(\)'$"),
    ("solid = 3\n", ".py", r"part\.py: solid is a int, expected a Solid$"),
    ("def model(:\n", ".py", r"part\.py: line 1: "),
    ("import sys\nsys.exit(3)\n", ".py", r"part\.py: raised SystemExit: 3$"),
    ('{"kind": "sphere", "radius": -2}', ".json", r"part\.json: \$\.radius: expected a positive number, got -2$"),
    ('{"kind": ', ".json", r"part\.json: JSON: Expecting value at line 1 column 10$"),
    ('{"kind": "sphere"}', ".txt", r"part\.txt: expected a \.py or \.json model file$"),
])
def test_bad_model_files_exit_2_with_one_line(capsys, tmp_path, content, suffix, match):
    name = "missing" if content is None else "part"
    path = tmp_path / f"{name}{suffix}"
    if content is not None:
        path.write_text(content)
    status, out, err = run(capsys, "info", path)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert __import__("re").search(match, err.strip()), err


def test_help_everywhere(capsys):
    for argv in (["--help"], ["info", "--help"], ["families", "--help"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "--json" in out and "MODEL" in out


def test_load_model_and_assembly():
    part = load_model(EXAMPLES / "benchmark_part.py")
    assert part.count_primitives() == 5
    parts = load_assembly(EXAMPLES / "assembly.py")
    assert list(parts) == ["plate", "bolt", "block"]
    # The bolt shank (radius 5) overlaps the plate around its hole (radius 4); the block is clear.
    probe = np.array([[-38 + 4.5, -18, 0.0]])
    assert parts["plate"](probe)[0] < 0 and parts["bolt"](probe)[0] < 0
    lo, hi = parts["block"].bounds
    for other in ("plate", "bolt"):
        olo, ohi = parts[other].bounds
        assert np.any(lo > ohi) or np.any(olo > hi)
    assert isinstance(load_any(EXAMPLES / "assembly.py"), dict)
    with pytest.raises(ValueError, match="this is an assembly file"):
        json_assembly = EXAMPLES / "pulley.json"
        load_model(_write_assembly_json(json_assembly))


def test_model_bound_to_a_solid_is_taken_as_it_is(tmp_path, capsys):
    # A Solid is callable (it evaluates points), so ``model = box(...)`` must not be called as ``model()``.
    path = tmp_path / "beam.py"
    path.write_text("from implicit import box\nmodel = box((100, 10, 10), center=(50, 0, 0))\n")
    part = load_model(path)
    assert part.count_primitives() == 1
    np.testing.assert_allclose(part.bounds, [[0, -5, -5], [100, 5, 5]])
    status, out, err = run(capsys, "info", path)
    assert status == 0 and err == "" and "box" in out


def _write_assembly_json(src):
    import tempfile
    folder = Path(tempfile.mkdtemp())
    path = folder / "asm.json"
    path.write_text(json.dumps({"parts": {"pulley": json.loads(src.read_text()),
                                          "pin": {"kind": "sphere", "radius": 0.1}}}))
    return path


def test_json_assembly(tmp_path):
    path = _write_assembly_json(EXAMPLES / "pulley.json")
    parts = load_assembly(path)
    assert list(parts) == ["pulley", "pin"]
    bad = tmp_path / "bad.json"
    bad.write_text('{"parts": {"a": {"kind": "sphere", "radius": 0}}}')
    with pytest.raises(ValueError, match=r"bad\.json: \$\.parts\['a'\]\.radius: expected a positive number, got 0$"):
        load_assembly(bad)
    bad.write_text('{"parts": []}')
    with pytest.raises(ValueError, match=r"bad\.json: expected an object"):
        load_assembly(bad)


@pytest.mark.parametrize("name", ["benchmark_part", "bracket", "assembly"])
def test_examples_main_runs(name, capsys):
    import runpy
    ns = runpy.run_path(str(EXAMPLES / f"{name}.py"))
    result = ns["main"]()
    assert result is not None
    assert capsys.readouterr().out


def test_command_line_smoke():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "spatial.cli", "info", str(EXAMPLES / "pulley.json")],
                          capture_output=True, text=True, env=env, cwd=ROOT, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "revolve(polygon(vertices=" in proc.stdout
