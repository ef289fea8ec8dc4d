"""Material-removal verification: a correct program, a gouging one, and a slot of known volume."""

import numpy as np
import pytest

from implicit import box, cylinder
from spatial.manufacturing import removal_picture, toolpath, toolpath_picture, verify

R = 0.25


@pytest.fixture(scope="module")
def stepped():
    part = (box((4.0, 3.0, 1.0)) | box((2.0, 1.5, 1.0), center=(0, 0, 1.0))) - cylinder(0.4, 6)
    return part, toolpath(part, R, resolution=48)


def test_a_correct_program_leaves_the_design(stepped):
    part, tp = stepped
    v = verify(part, tp, resolution=96)
    assert v.gouge_volume < 1e-3
    assert v.rapid_volume == 0.0
    # to remove: the ring around the boss (12 - 3) x 1 and the hole 0.16 pi x 2
    assert v.removed_volume == pytest.approx(9.0 + 0.32 * np.pi, rel=0.01)
    assert v.excess_volume < 0.01
    assert sum(o["removed"] for o in v.operations) == pytest.approx(v.removed_volume, rel=1e-12)
    assert all(o["gouge"] < 1e-3 for o in v.operations)


def test_a_tool_larger_than_programmed_gouges_the_walls(stepped):
    part, tp = stepped
    v = verify(part, tp, tool_radius=R + 0.1, resolution=192, tolerance=0.0)
    # walls pushed in by 0.1: boss perimeter 7 x height 1 and hole 2 pi 0.4 x 2 (measured 1.198)
    expected = 0.1 * (7.0 * 1.0 + 2 * np.pi * 0.4 * 2.0)
    assert v.gouge_volume == pytest.approx(expected, rel=0.03)
    worst = max(v.operations, key=lambda o: o["gouge"])
    assert "profile" in worst["name"]


def test_a_slot_through_a_block_is_a_gouge_of_known_volume():
    part = box((2.0, 1.0, 1.0))
    program = "\n".join(["G21 G90", "S8000 M3", "G0 X-1.5 Y0 Z1", "(operation 1: slot across the top)",
                         "G0 X-1.5 Y0 Z0.6", "G1 X-1.5 Y0 Z0.3 F100", "G1 X1.5 Y0 Z0.3 F300",
                         "G0 X1.5 Y0 Z1", "M5", "M2"])
    v = verify(part, program, tool_radius=0.1, stock=part.bounds, resolution=100)
    h = v.tolerance
    # the part shrunk by the tolerance, cut by a slot 0.2 wide from z=0.3 up
    expected = (2.0 - 2 * h) * 0.2 * (0.5 - h - 0.3)
    assert v.gouge_volume == pytest.approx(expected, rel=0.02)
    assert v.removed_volume == pytest.approx(2.0 * 0.2 * 0.2, rel=0.02)
    assert v.excess_volume == pytest.approx(0.0, abs=1e-9)
    assert [o["name"] for o in v.operations] == ["operation 1: slot across the top"]


def test_a_rapid_through_the_stock_is_reported():
    part = box((2.0, 1.0, 1.0))
    program = "G21 G90\nG0 X-1.5 Y0 Z1\n(operation 1: crash)\nG0 X-1.5 Y0 Z0.4\nG0 X1.5 Y0 Z0.4\nG0 X1.5 Y0 Z1\n"
    v = verify(part, program, tool_radius=0.1, stock=part.bounds, resolution=100)
    assert v.rapid_volume == pytest.approx(2.0 * 0.2 * 0.1, rel=0.02)


def test_pictures(stepped, tmp_path):
    part, tp = stepped
    v = verify(part, tp, tool_radius=R + 0.1, resolution=64)
    p1 = toolpath_picture(tp, tmp_path / "tp.png")
    p2 = removal_picture(v, part, tmp_path / "rm.png", resolution=48, window_size=(400, 300))
    from PIL import Image

    assert Image.open(p1).size[0] > 500
    img = np.asarray(Image.open(p2).convert("RGB")).astype(int)
    assert img.shape == (300, 400, 3)
    blue = (img[..., 2] - img[..., 0] > 60).sum()
    assert blue > 200                                    # the gouged walls are blue


def test_bad_input():
    with pytest.raises(ValueError, match="tool_radius"):
        verify(box(1.0), "G0 X0 Y0 Z1\n", stock=box(1.0).bounds)
    with pytest.raises(TypeError, match="program"):
        verify(box(1.0), 3.0)
    with pytest.raises(ValueError, match="G-code line 1"):
        verify(box(1.0), "hello\n", tool_radius=0.1, stock=box(1.0).bounds)


def test_the_milled_plate_example():
    import os
    import runpy

    ns = runpy.run_path(os.path.join(os.path.dirname(__file__), "..", "..", "examples", "milled_plate.py"))
    v = ns["main"](resolution=64)
    exact = 86400.0 - (48000 + 9600 - 1600 - np.pi * 16 * 18 - np.pi * 25 * 10)
    assert v.gouge_volume == 0.0 and v.rapid_volume == 0.0
    assert v.removed_volume == pytest.approx(exact, rel=0.02)
