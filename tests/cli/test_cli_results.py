"""Good input without an answer: one line on stderr, exit status 1, nothing written."""

import json

import pytest

from spatial.analysis.section import section
from spatial.cli import main

PLATE = "from implicit import box, cylinder\nsolid = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0)\n"


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_section_that_misses_the_part(tmp_path, capsys):
    model = _write(tmp_path, "plate.py", PLATE)
    out = tmp_path / "s.json"
    assert main(["section", model, "--plane", "z=3", "-o", str(out)]) == 1
    cap = capsys.readouterr()
    assert "misses" in cap.err and cap.err.count("\n") == 1 and "nan" not in cap.out.lower()
    assert not out.exists()
    assert main(["section", model, "--plane", "z=3", "--json"]) == 1
    assert capsys.readouterr().out == ""


def test_empty_section_has_no_nan_in_json():
    from implicit import box

    s = section(box(1.0), "z=2", resolution=16)
    assert s.is_empty and s.area == 0.0
    d = s.to_dict()
    assert d["empty"] and d["centroid"] is None and d["centroid3d"] is None
    json.dumps(d, allow_nan=False)
    hit = section(box(1.0), "z=0.1", resolution=16)
    assert not hit.is_empty and hit.area == pytest.approx(1.0, rel=1e-9)
