"""2.5D tool paths: their G-code read back by an independent parser and checked against the solid."""

import re

import numpy as np
import pytest

from implicit import box, cylinder
from spatial.manufacturing import read_gcode, toolpath

from gcode_check import parse, samples, tool_body

#: How far the tool may enter the part: chords of the finishing offsets cut
#: inside their arcs by h^2 / (8 r) at the grid step h used here.
ENTRY_TOL = 0.01
R = 0.25


@pytest.fixture(scope="module")
def stepped():
    """A plate with a boss on top and a hole through both: floors at 0.5 and -0.5."""
    part = (box((4.0, 3.0, 1.0)) | box((2.0, 1.5, 1.0), center=(0, 0, 1.0))) - cylinder(0.4, 6)
    return part, toolpath(part, R, resolution=48, title="stepped plate")


def test_program_words_and_operations(stepped):
    part, tp = stepped
    text = tp.to_gcode()
    moves, seen = parse(text)
    assert {"G21", "G90", "M3", "M5", "M2", "S", "F", "G0", "G1", "G3"} <= seen
    assert "G20" not in seen and "G2" not in seen             # climb milling: arcs counter-clockwise
    ops = {m["op"] for m in moves}
    assert any(o.startswith("operation 1: pocket") for o in ops if o)
    assert any("profile" in o for o in ops if o)
    for line in text.splitlines():
        if line[:1] in "XYZ":
            raise AssertionError(f"a move line without a G word: {line}")
    assert len(moves) == tp.move_count + 1          # and the final retract


def test_depths_reach_every_floor_in_steps_no_deeper_than_the_step_down(stepped):
    _, tp = stepped
    d = np.array([tp.stock[1][2]] + tp.depths)
    assert np.all(np.diff(d) < 0) and np.all(-np.diff(d) <= R + 1e-9)
    assert np.min(np.abs(np.array(tp.depths) - 0.5)) < 1e-9          # the plate's top face
    assert tp.depths[-1] == pytest.approx(-0.5, abs=1e-9)             # through to the bottom


def test_cutting_moves_stay_in_the_stock_and_out_of_the_part(stepped):
    part, tp = stepped
    moves, _ = parse(tp.to_gcode())
    lo, hi = (np.asarray(b) for b in tp.stock)
    body = tool_body(R, 1.2)
    cutting = [m for m in moves if m["g"] != 0]
    pts = np.concatenate([samples(m, 0.02) for m in cutting])
    assert np.all(pts[:, :2] >= lo[:2] - R - 1e-6) and np.all(pts[:, :2] <= hi[:2] + R + 1e-6)
    assert np.all(pts[:, 2] >= lo[2] - 1e-9) and np.all(pts[:, 2] <= tp.safe_z + 1e-9)
    f = part((pts[:, None, :] + body[None, :, :]).reshape(-1, 3))
    assert f.min() > -ENTRY_TOL
    # the finishing passes do touch the part: the tool runs at r from its walls
    assert f.min() < 0.01
    rapids = np.concatenate([samples(m, 0.05) for m in moves if m["g"] == 0])
    assert part((rapids[:, None, :] + body[None, :, :]).reshape(-1, 3)).min() > -1e-9   # rapids never enter


def _loop_points(moves):
    """End points of the horizontal lines of a pass (plunges and arcs left out)."""
    out, prev = [], None
    for m in moves:
        if isinstance(m[0], str):
            continue
        if m[0] == 1 and prev is not None and m[3] == prev[3] and (m[1], m[2]) != (prev[1], prev[2]):
            out.append((m[1], m[2]))
        prev = m
    return np.array(out)


def test_climb_and_conventional_run_the_boss_profile_in_opposite_senses():
    part = box((4.0, 3.0, 1.0)) | box((2.0, 1.5, 1.0), center=(0, 0, 1.0))
    senses = {}
    for direction in ("climb", "conventional"):
        tp = toolpath(part, R, resolution=40, direction=direction)
        prof = next(op for op in tp.operations if op.kind == "profile")
        xy = _loop_points(prof.moves)
        xy = xy[np.hypot(*xy.T) < 2.0]                 # the loop around the boss
        senses[direction] = np.sign(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]))
    assert senses == {"climb": -1.0, "conventional": 1.0}      # clockwise around the boss when climbing


def test_profile_is_the_exact_offset_of_the_boss():
    part = box((4.0, 3.0, 1.0)) | box((2.0, 1.5, 1.0), center=(0, 0, 1.0))
    tp = toolpath(part, R, resolution=40)
    prof = next(op for op in tp.operations if op.kind == "profile")
    xy = _loop_points(prof.moves)
    xy = xy[np.hypot(*xy.T) < 2.0]
    assert len(xy) > 50
    # distance from a rectangle 2 x 1.5: r everywhere, rounded at the corners
    d = np.hypot(np.maximum(np.abs(xy[:, 0]) - 1.0, 0), np.maximum(np.abs(xy[:, 1]) - 0.75, 0))
    assert np.abs(d - R).max() < 2e-5


def test_round_trip_of_the_program_reader(stepped):
    _, tp = stepped
    ops, start, units = read_gcode(tp.to_gcode())
    assert units == "mm" and len(ops) == len(tp.operations)
    ours, _ = parse(tp.to_gcode())
    ends = np.array([m[1:4] for _, moves in ops for m in moves])
    theirs = np.array([m["end"] for m in ours])
    assert np.allclose(ends, theirs, atol=1e-4)


def test_refuses_a_hole_narrower_than_the_tool_and_says_where():
    part = box((3.0, 3.0, 1.0)) - cylinder(0.3, 4, center=(0.5, -0.25, 0.0))
    with pytest.raises(ValueError, match=r"narrower than the tool diameter 0\.8") as info:
        toolpath(part, 0.4, resolution=48)
    near = re.search(r"near \(([-0-9.e]+), ([-0-9.e]+)\)", str(info.value))
    assert abs(float(near.group(1)) - 0.5) < 0.05 and abs(float(near.group(2)) + 0.25) < 0.05
    toolpath(part, 0.2, resolution=48)              # a smaller tool fits


@pytest.mark.parametrize("kwargs, match", [({"stepover": 0.8}, "stepover"), ({"direction": "up"}, "direction"),
                                           ({"units": "cm"}, "units"), ({"resolution": 4}, "resolution"),
                                           ({"safe_height": -1.0}, "safe_height")])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        toolpath(box(1.0), 0.1, **kwargs)
