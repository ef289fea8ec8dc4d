"""Mass properties one can sign: tolerance met or refused, thin walls resolved, bounds that bracket."""

import numpy as np
import pytest

import implicit as I
from spatial.analysis.mass import ToleranceError, mass_properties
from spatial.cells.thickness import min_feature_size
from spatial.cli import main

BENCH = ((I.sphere(1.0) & I.box(1.5)) - I.cylinder(0.5, 4, axis=(1, 0, 0)) - I.cylinder(0.5, 4, axis=(0, 1, 0))
         - I.cylinder(0.5, 4, axis=(0, 0, 1)))
BENCH_AREA = 12.327770219


def test_min_feature_size_from_the_tree():
    assert min_feature_size(I.box((100.0, 100.0, 1.0))) == 1.0
    assert min_feature_size(I.shell(I.sphere(1.0), 0.05)) == pytest.approx(0.05)
    assert min_feature_size(I.scale(I.box(1.0), (1.0, 1.0, 0.1))) == pytest.approx(0.1)
    assert min_feature_size(I.offset(I.box(1.0), -0.2)) == pytest.approx(0.6)
    assert min_feature_size(I.cylinder(0.1, 5.0) | I.box(3.0)) == pytest.approx(0.2)


def test_thin_plate_is_measured_right():
    plate = I.box((20.0, 20.0, 0.5))       # 40:1, like 100 x 100 x 1 at a fifth of the cost
    p = mass_properties(plate, resolution=32)
    assert "raised" in p.method
    assert abs(p.volume - 200.0) <= p.error.volume and p.error.volume < 1e-3 * 200.0
    area = 2 * 400.0 + 4 * 20.0 * 0.5
    assert abs(p.area - area) <= p.error.area and abs(p.area - area) < 1e-3 * area
    np.testing.assert_array_less(np.abs(p.centroid), p.error.centroid + 1e-300)
    Izz = 200.0 * (400.0 + 400.0) / 12
    assert abs(p.inertia[2, 2] - Izz) <= p.error.inertia[2, 2]


def test_tolerance_is_met_or_refused(monkeypatch):
    import spatial.analysis.mass_solid as ms

    monkeypatch.setattr(ms, "MAX_CELLS", 32)
    with pytest.raises(ToleranceError, match="tolerance 1e-09 not reached") as info:
        mass_properties(I.box((1.0, 0.7, 0.4)), tolerance=1e-9)
    assert info.value.cells == 32 and info.value.estimate > 1e-9
    p = mass_properties(I.sphere(1.0), tolerance=1e-3)
    assert p.error.volume <= 1e-3 * p.volume and abs(p.volume - 4 * np.pi / 3) <= p.error.volume


def test_mass_command_exits_1_when_the_tolerance_is_not_met(tmp_path, capsys, monkeypatch):
    import spatial.analysis.mass_solid as ms

    monkeypatch.setattr(ms, "MAX_CELLS", 32)
    model = tmp_path / "part.py"
    model.write_text("from implicit import box\nsolid = box((1.0, 0.7, 0.4))\n")
    assert main(["mass", str(model), "--tolerance", "1e-9"]) == 1
    cap = capsys.readouterr()
    assert cap.out == "" and cap.err.count("\n") == 1 and "not reached" in cap.err


@pytest.mark.parametrize("name, solid, area, n", [
    ("box", I.box((1.0, 0.7, 0.4)), 2 * (0.7 + 0.28 + 0.4), 128),
    ("box - cylinder", I.box((2.0, 1.0, 0.5)) - I.cylinder(0.25, 1.0),
     7.0 - 2 * np.pi * 0.0625 + 2 * np.pi * 0.25 * 0.5, 128),
    ("benchmark", BENCH, BENCH_AREA, 128),
])
def test_area_of_sharp_parts_within_a_thousandth(name, solid, area, n):
    p = mass_properties(solid, resolution=n)
    err = abs(p.area - area)
    assert err < 1e-3 * area, (name, err / area)
    assert err <= p.error.area, (name, err, p.error.area)
    assert p.error.area < 2e-3 * area


@pytest.mark.parametrize("solid, centroid", [
    (I.box((1.0, 0.6, 0.3), center=(0.31, -0.2, 0.05)), [0.31, -0.2, 0.05]),
    (I.translate(BENCH, (0.123, 0.0, -0.07)), [0.123, 0.0, -0.07]),
    (I.sphere(0.7, center=(1.0, 2.0, 3.0)) | I.sphere(0.7, center=(2.0, 2.0, 3.0)), [1.5, 2.0, 3.0]),
])
def test_centroid_bounds_bracket(solid, centroid):
    for n in (24, 64):
        p = mass_properties(solid, resolution=n)
        err = np.abs(p.centroid - centroid)
        assert np.all(err <= p.error.centroid), (n, err, p.error.centroid)
    # the floor follows the volume's error over the half-extent: not absurdly wide
    assert np.all(p.error.centroid < 2e-3)
