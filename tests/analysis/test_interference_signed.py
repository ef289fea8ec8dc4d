"""Interference one can sign: the requested resolution, a bound that brackets, possible contact."""

import sys
from pathlib import Path

import numpy as np
import pytest

from implicit import box
from spatial.analysis.interference import check_assembly, interference

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples"))


def test_bolt_in_an_undersize_hole_brackets_45_pi():
    from assembly import assembly

    parts = assembly()
    exact = 45 * np.pi                     # shank radius 5 in a hole of radius 4, plate 5 thick
    coarse = interference(parts["plate"], parts["bolt"], resolution=32)
    fine = interference(parts["plate"], parts["bolt"], resolution=64)
    for r in (coarse, fine):
        assert r.interferes and abs(r.volume - exact) <= r.volume_error, (r.volume, r.volume_error)
        assert r.volume_error < 0.01 * exact
    assert fine.voxel_size == pytest.approx(coarse.voxel_size / 2)


def test_gap_below_a_cell_is_possible_contact_not_clear():
    h = 1.0 / 16
    a = box(1.0)
    b = box(1.0, center=(1.0 + 0.3 * h, 0.0, 0.0))
    r = interference(a, b, resolution=16)
    assert not r.interferes and not r.touching and r.possible_contact
    assert r.volume == 0.0          # (disjoint boxes: the bounds themselves prove no shared volume)
    assert r.clearance == pytest.approx(0.3 * h, rel=1e-6) and r.clearance - r.clearance_error <= 0.0
    # a sliver of overlap far thinner than a cell: either found, or bounded
    sliver = 1e-4 * h
    s = interference(a, box(1.0, center=(1.0 - sliver, 0.0, 0.0)), resolution=16)
    assert s.interferes or s.touching or s.possible_contact
    if not s.interferes:
        assert s.volume_error >= sliver * 1.0 * 1.0
    far = interference(a, box(1.0, center=(1.5, 0.0, 0.0)), resolution=16)
    assert not far.possible_contact and far.volume_error == 0.0
    report = check_assembly({"a": a, "b": b}, resolution=16)
    assert [(x, y) for x, y, _ in report.possible_contact] == [("a", "b")]
    assert report.to_dict()["possible_contact"][0]["possible_contact"] is True


def test_interfere_command_says_possible_contact(tmp_path, capsys):
    from spatial.cli import main

    model = tmp_path / "asm.py"
    model.write_text("from implicit import box\nparts = {'a': box(1.0), 'b': box(1.0, center=(1.02, 0, 0))}\n")
    assert main(["interfere", str(model), "--resolution", "16"]) == 0
    out = capsys.readouterr().out
    assert "possible contact  a / b" in out and "no interference resolved" in out
