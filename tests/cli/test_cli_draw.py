"""`implicad draw`: sheets of parts and assemblies; bad input is one line and status 2."""

import os
import xml.etree.ElementTree as ET

import pytest

from spatial.cli import main

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
NS = {"s": "http://www.w3.org/2000/svg"}


@pytest.fixture
def plate(tmp_path):
    model = tmp_path / "plate.py"
    model.write_text("from implicit import box, cylinder\n"
                     "solid = box((40, 20, 10)) - cylinder(4, 30, center=(10, 0, 0))\n")
    return model


def test_draw_a_part_in_third_angle_with_a_section(plate, tmp_path, capsys):
    out = tmp_path / "plate.svg"
    assert main(["draw", str(plate), "-o", str(out), "--projection", "third", "--section", "y=0",
                 "--resolution", "32"]) == 0
    assert "third-angle projection, scale 2:1" in capsys.readouterr().out
    root = ET.parse(out).getroot()
    assert root.find(".//s:g[@id='title-block']", NS).get("data-projection") == "third"
    assert root.find(".//s:g[@id='view-front']", NS).get("data-section") == "A-A"
    title = [t.text for t in root.iter(f"{{{NS['s']}}}text")]
    assert "plate" in title


def test_draw_an_exploded_assembly_writes_the_parts_list(tmp_path, capsys):
    out = tmp_path / "asm.png"
    assert main(["draw", os.path.join(EXAMPLES, "assembly.py"), "-o", str(out), "--explode",
                 "--resolution", "24"]) == 0
    assert "3 parts, 3 items" in capsys.readouterr().out
    assert out.exists() and (tmp_path / "asm.csv").read_text().startswith("item,name,family")


@pytest.mark.parametrize("argv, message", [
    (["-o", "x.doc"], "--output: output: expected a name ending in .svg"),
    (["-o", "x.svg", "--section", "q=1"], "--section: plane: expected"),
    (["-o", "x.svg", "--explode"], "--explode: the model is a single part"),
    (["-o", "x.svg", "--resolution", "4"], "--resolution: expected a whole number from 16 to 1024"),
    (["-o", "nowhere/x.svg"], "--output: no such directory"),
])
def test_bad_input_is_one_line_and_status_2(plate, tmp_path, capsys, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(["draw", str(plate), *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plate.py"]


@pytest.mark.parametrize("declare, flag, label", [("", [], "units of the model"), ("units = 'mm'\n", [], "mm"),
                                                   ("units = 'mm'\n", ["--units", "in"], "in")])
def test_the_sheet_states_the_unit_the_model_declares_or_units_gives(tmp_path, capsys, declare, flag, label):
    model = tmp_path / "blk.py"
    model.write_text("from implicit import box\n" + declare + "solid = box((40, 20, 10))\n")
    out = tmp_path / "blk.svg"
    assert main(["draw", str(model), "-o", str(out), "--resolution", "24", *flag]) == 0
    assert f"units {label};" in capsys.readouterr().out
    assert ET.parse(out).getroot().find(".//s:g[@id='title-block']", NS).get("data-units") == label
