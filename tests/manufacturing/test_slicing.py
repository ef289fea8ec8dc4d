"""Layer slices: contours, orientation, and layer areas summed against closed-form volumes."""

import json

import numpy as np
import pytest

from implicit import box, cylinder, sphere
from spatial.manufacturing import slice

#: Accuracy of one section's area at the resolutions used here (fourth order on smooth outlines).
SECTION_TOL = 1e-5


def _signed_area(loop):
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def benchmark_part():
    return (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))


def test_sphere_layers_sum_to_the_midpoint_rule_of_its_volume():
    H = 0.05
    s = slice(sphere(1.0), layer=H, resolution=64)
    assert len(s.layers) == 40
    assert s.z_bottom == pytest.approx(-1.0, abs=1e-9)
    # midpoint rule of pi (1 - z^2) on [-1, 1]: error exactly +pi H^2 / 6
    assert s.volume == pytest.approx(4 * np.pi / 3 + np.pi * H * H / 6, abs=40 * H * SECTION_TOL)
    for ly in s.layers:
        assert ly.area == pytest.approx(np.pi * (1 - ly.z ** 2), abs=SECTION_TOL)


def test_box_with_hole_is_exact_and_loops_are_oriented():
    part = box(1.0) - cylinder(0.2, 4)
    s = slice(part, layer=0.1, resolution=64)
    assert len(s.layers) == 10
    assert s.volume == pytest.approx(1 - 0.04 * np.pi, abs=10 * 0.1 * SECTION_TOL)
    for ly in s.layers:
        assert sorted(ly.holes) == [False, True]
        for lp, hole in zip(ly.loops, ly.holes):
            a = _signed_area(lp)
            if hole:                                  # clockwise
                assert a == pytest.approx(-0.04 * np.pi, rel=2e-3)       # chords inside the circle
            else:                                     # counter-clockwise
                assert a == pytest.approx(1.0, rel=1e-6)


def test_benchmark_part_volume_within_the_layer_model_error():
    H = 0.01
    s = slice(benchmark_part(), layer=H, resolution=64)
    assert len(s.layers) == 150
    # the holes along x and y make the area a sqrt-kinked function of z: the
    # midpoint rule's error is ~3.5 H^2 here (measured 2.4e-3, 3.5e-4, 8.3e-5 at H = 0.02, 0.01, 0.005)
    assert abs(s.volume - 0.988789504774) < 4 * H * H
    mid = min(s.layers, key=lambda ly: abs(ly.z))
    assert len(mid.loops) == 4 and not any(mid.holes)          # the x and y holes cut it in four
    upper = min(s.layers, key=lambda ly: abs(ly.z - 0.6))
    assert len(upper.loops) == 2 and sum(upper.holes) == 1      # the z hole through the cap


def test_json_csv_and_svg_forms():
    s = slice(box(1.0) - cylinder(0.2, 4), layer=0.25, resolution=32)
    d = json.loads(s.to_json())
    assert [round(ly["z"], 9) for ly in d["layers"]] == [-0.375, -0.125, 0.125, 0.375]
    first = d["layers"][0]
    assert {lp["orientation"] for lp in first["loops"]} == {"ccw", "cw"}
    assert first["area"] == pytest.approx(1 - 0.04 * np.pi, rel=1e-5)
    rows = s.to_csv().splitlines()
    assert rows[0] == "layer,z,loop,hole,x,y"
    assert len(rows) - 1 == sum(len(lp) for ly in s.layers for lp in ly.loops)
    svg = s.to_svg()
    assert svg.count("<path") == 4 and "fill-rule=\"evenodd\"" in svg


@pytest.mark.parametrize("kwargs, match", [({"layer": -1.0}, "layer"), ({"layer": 0.1, "resolution": 3}, "resolution"),
                                           ({"layer": 0.1, "z_range": (1.0, 0.0)}, "z_range")])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        slice(sphere(1.0), **kwargs)


def test_not_a_solid():
    with pytest.raises(TypeError, match="solid"):
        slice("sphere", layer=0.1)
