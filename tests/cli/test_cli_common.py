"""One command line: --json, --quiet, units, warnings as one line, mesh files as solids, compare and report."""

import json
import os
import warnings

import pytest

from spatial.cli import COMMAND_MODULES, build_parser, main
from spatial.cli.common import install_warning_handler

HERE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PART = os.path.join(HERE, "examples", "benchmark_part.py")


@pytest.fixture()
def small_model(tmp_path):
    path = tmp_path / "plate.py"
    path.write_text("from implicit import box, cylinder\nunits = 'mm'\nsolid = box((40, 20, 5)) - cylinder(4, 10)\n")
    return str(path)


def test_every_command_takes_json_quiet_and_progress():
    parser = build_parser()
    for name, sub in parser._subparsers._group_actions[0].choices.items():
        for flag in ("--json", "--quiet", "--progress"):
            assert flag in sub._option_string_actions, (name, flag)
    # the old spellings still work
    assert build_parser().parse_args(["mesh", "m.py", "-o", "m.stl", "--resolution", "8", "--quiet"]).progress is False
    assert build_parser().parse_args(["fea", "m.py", "-o", "m.msh", "--size", "1", "--no-progress"]).progress is False


def test_json_is_one_object_even_for_commands_without_their_own(capsys, tmp_path, small_model):
    out = tmp_path / "plate.stl"
    status = main(["mesh", small_model, "-o", str(out), "--resolution", "16", "--json"])
    text = capsys.readouterr().out
    data = json.loads(text)
    assert status == 0 and data["command"] == "mesh" and data["status"] == 0
    assert out.exists()


def test_mass_uses_declared_units_and_says_when_it_assumes(capsys, tmp_path, small_model):
    main(["mass", small_model, "--resolution", "16"])
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "units: mm (declared by the model)"
    bare = tmp_path / "bare.json"
    bare.write_text(json.dumps({"kind": "box", "size": [1, 2, 3], "center": [0, 0, 0]}))
    main(["mass", str(bare), "--resolution", "16"])
    assert capsys.readouterr().out.splitlines()[0].startswith("units: m assumed")
    with_units = tmp_path / "mm.json"
    with_units.write_text(json.dumps({"kind": "box", "size": [1, 2, 3], "center": [0, 0, 0], "units": "mm"}))
    main(["mass", str(with_units), "--resolution", "16", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert data["units"] == "mm" and data["units_assumed"] is False and data["volume_of"] == "solid"
    assert data["volume"] == pytest.approx(6.0, rel=2e-3)


def test_bad_declared_units_are_one_line(capsys, tmp_path):
    path = tmp_path / "bad.py"
    path.write_text("from implicit import box\nunits = 'furlong'\nsolid = box(1)\n")
    assert main(["mass", str(path)]) == 2
    assert "units: expected one of m, cm, mm, in, ft, got 'furlong'" in capsys.readouterr().err


def test_a_closed_mesh_file_is_read_as_a_solid(capsys, tmp_path, small_model):
    stl = str(tmp_path / "plate.stl")
    assert main(["mesh", small_model, "-o", stl, "--resolution", "48", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["info", stl, "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["kind"] == "grid"
    lo, hi = info["bounds"]
    assert hi[0] - lo[0] == pytest.approx(40.0, abs=2.0)
    assert main(["section", stl, "--plane", "z=0", "-o", str(tmp_path / "s.png")]) == 0


def test_check_and_mass_label_mesh_and_solid_volumes(capsys, small_model):
    main(["check", small_model, "--resolution", "16"])
    out = capsys.readouterr().out
    assert "mesh volume:" in out and "the boundary mesh of the solid" in out
    main(["mass", small_model, "--resolution", "16"])
    assert "what:  solid volume" in capsys.readouterr().out


def test_warnings_reach_the_terminal_as_one_line(capsys):
    saved = warnings.showwarning
    try:
        install_warning_handler()
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            warnings.warn("thin wall\nsecond line", UserWarning)
        err = capsys.readouterr().err
    finally:
        warnings.showwarning = saved
    assert err == "implicad: warning: thin wall\n"


def test_compare_json_and_markdown(capsys, tmp_path, small_model):
    chart = tmp_path / "chart.png"
    assert main(["compare", small_model, "--resolution", "16", "--queries", "1000", "--json",
                 "--chart", str(chart)]) == 0
    data = json.loads(capsys.readouterr().out)
    names = [r["name"] for r in data["representations"]]
    assert "half-space form" in names and chart.stat().st_size > 10_000
    half = next(r for r in data["representations"] if r["name"] == "half-space form")
    assert half["applies"] is False  # a drilled hole is not planar
    assert main(["compare", small_model, "--resolution", "16", "--queries", "1000"]) == 0
    assert capsys.readouterr().out.startswith("| representation |")


def test_report_writes_every_page(capsys, tmp_path, small_model):
    out = tmp_path / "rep"
    assert main(["report", small_model, "-o", str(out), "--resolution", "24", "--compare-resolution", "16",
                 "--json"]) == 0
    paths = json.loads(capsys.readouterr().out)["report"]
    for key in ("mesh", "section", "shaded", "sheet", "compare", "occupancy", "markdown", "html", "json"):
        assert os.path.getsize(paths[key]) > 100, key
    page = open(paths["html"], encoding="utf-8").read()
    assert page.count("data:image/png;base64,") == 5 and "src=\"shaded.png\"" not in page
    facts = json.load(open(paths["json"], encoding="utf-8"))
    assert facts["units"] == "mm" and facts["brep"]["euler_poincare_holds"]
    assert facts["mass_properties"]["volume"] == pytest.approx(40 * 20 * 5 - 3.14159265 * 16 * 5, rel=1e-2)
    md = open(paths["markdown"], encoding="utf-8").read()
    assert "![shaded view](shaded.png)" in md and "drawing sheet from spatial.drafting" in md
    assert os.path.getsize(paths["sheet_svg"]) > 1000
    assert 'data-units="mm"' in open(paths["sheet_svg"], encoding="utf-8").read()


def test_the_report_s_sheet_states_the_unit_the_report_assumed(capsys, tmp_path):
    model = tmp_path / "plain.py"
    model.write_text("from implicit import box\nsolid = box((4, 2, 1))\n")
    out = tmp_path / "rep"
    assert main(["report", str(model), "-o", str(out), "--resolution", "16", "--compare-resolution", "12",
                 "--json"]) == 0
    paths = json.loads(capsys.readouterr().out)["report"]
    sheet = open(paths["sheet_svg"], encoding="utf-8").read()
    assert 'data-units="m, assumed"' in sheet and "Dimensions in m, assumed;" in sheet
    assert "m (assumed" in open(paths["markdown"], encoding="utf-8").read()


def test_report_refuses_a_file_as_folder(capsys, tmp_path, small_model):
    f = tmp_path / "x"
    f.write_text("")
    assert main(["report", small_model, "-o", str(f)]) == 2
    assert "exists and is not a folder" in capsys.readouterr().err
