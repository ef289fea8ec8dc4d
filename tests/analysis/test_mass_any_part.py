"""Mass properties with no options on any part: thin plates, bosses, the benchmark part, a bracket.

The levels `mass_properties` chooses itself are meshed with their sharp edges
rebuilt; every bound is held against closed forms (boxes, cylinders, a
sphere) for volume, centroid and inertia.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import implicit as I
from spatial.analysis.mass import ToleranceError, mass_properties

BENCH = ((I.sphere(1.0) & I.box(1.5)) - I.cylinder(0.5, 4, axis=(1, 0, 0)) - I.cylinder(0.5, 4, axis=(0, 1, 0))
         - I.cylinder(0.5, 4, axis=(0, 0, 1)))
BENCH_VOLUME = 0.988789504774
BENCH_PRINCIPAL = 0.507545233


class Exact:
    """Volume, first and second moments about the origin of signed boxes and cylinders."""

    def __init__(self):
        self.V, self.m1, self.M2 = 0.0, np.zeros(3), np.zeros((3, 3))

    def _add(self, V, centre, own, sign):
        c = np.asarray(centre, dtype=float)
        self.V += sign * V
        self.m1 += sign * V * c
        self.M2 += sign * (V * np.outer(c, c) + own)

    def box(self, sides, centre=(0.0, 0.0, 0.0), rotation=None, sign=1.0):
        rotation = np.eye(3) if rotation is None else rotation
        s = np.asarray(sides, dtype=float)
        V = float(np.prod(s))
        self._add(V, centre, rotation @ np.diag(V * s * s / 12.0) @ rotation.T, sign)
        return self

    def cylinder(self, r, length, centre, axis, sign=1.0):
        a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
        V = np.pi * r * r * length
        own = V * (r * r / 4.0) * (np.eye(3) - np.outer(a, a)) + V * length ** 2 / 12.0 * np.outer(a, a)
        self._add(V, centre, own, sign)
        return self

    def centroid(self):
        return self.m1 / self.V

    def inertia(self):
        c = self.centroid()
        C = self.M2 - self.V * np.outer(c, c)
        return np.trace(C) * np.eye(3) - C


def rotation(ax, ay):
    return I.rotation_matrix(ay, (0.0, 1.0, 0.0)) @ I.rotation_matrix(ax, (1.0, 0.0, 0.0))


def placed_box(sides, ax, ay, shift):
    solid = I.translate(I.rotate(I.rotate(I.box(tuple(sides)), ax, (1, 0, 0)), ay, (0, 1, 0)), tuple(shift))
    return solid, Exact().box(sides, shift, rotation(ax, ay))


def bracket():
    from examples.bracket import solid

    ex = Exact().box((50, 30, 4), (25, 15, 2)).box((4, 30, 40), (2, 15, 20)).box((4, 30, 4), (2, 15, 2), sign=-1)
    for x in (4 + 46 / 3, 4 + 92 / 3):
        ex.cylinder(3.0, 4.0, (x, 15.0, 2.0), (0, 0, 1), sign=-1)
    for z in (16.0, 28.0):
        ex.cylinder(3.0, 4.0, (2.0, 15.0, z), (1, 0, 0), sign=-1)
    return solid, ex


def assert_brackets(p, ex, tolerance):
    """Every bound holds the exact value, and the volume's meets the tolerance."""
    assert abs(p.volume - ex.V) <= p.error.volume, (p.volume, ex.V, p.error.volume)
    assert p.error.volume <= tolerance * ex.V
    err_c = np.abs(p.centroid - ex.centroid())
    assert np.all(err_c <= p.error.centroid), (err_c, p.error.centroid)
    err_i = np.abs(p.inertia - ex.inertia())
    assert np.all(err_i <= p.error.inertia), (err_i, p.error.inertia)


def test_the_100_by_100_by_1_plate_with_no_options():
    solid, ex = placed_box((100.0, 100.0, 1.0), 0.0, 0.0, (0.0, 0.0, 0.0))
    p = mass_properties(solid)
    assert_brackets(p, ex, 1e-4)
    assert abs(p.volume - 1e4) < 1e-5 * 1e4          # 1.1e-6 measured: the plain mesh's bevels gave 1.6e-4
    assert "sharp edges rebuilt" in p.method and "480 cells" in p.method


def test_a_tilted_plate_far_from_the_origin():
    solid, ex = placed_box((40.0, 40.0, 0.8), 30.0, 30.0, (1000.0, -500.0, 200.0))
    assert_brackets(mass_properties(solid, tolerance=1e-3), ex, 1e-3)


@pytest.mark.parametrize("name", ["boss", "benchmark", "sphere", "bracket"])
def test_reference_parts_with_no_options(name):
    if name == "boss":
        solid = I.box((4.0, 4.0, 1.0)) | I.box((1.0, 1.0, 1.0), center=(0.0, 0.0, 1.0))
        ex = Exact().box((4, 4, 1)).box((1, 1, 1), (0, 0, 1))
    elif name == "sphere":
        solid = I.sphere(1.0)
        ex = Exact()
        ex.V, ex.M2 = 4 * np.pi / 3, np.eye(3) * 4 * np.pi / 15
    elif name == "bracket":
        solid, ex = bracket()
    else:
        p = mass_properties(BENCH)
        assert abs(p.volume - BENCH_VOLUME) <= p.error.volume <= 1e-4 * BENCH_VOLUME
        assert np.all(np.abs(p.principal_moments - BENCH_PRINCIPAL) <= p.error.principal_moments)
        assert np.all(np.abs(p.centroid) <= p.error.centroid)
        return
    assert_brackets(mass_properties(solid), ex, 1e-4)


def test_a_resolution_or_a_tight_tolerance_keeps_the_plain_extrapolation():
    p = mass_properties(I.box((1.0, 0.7, 0.4)), resolution=32)
    assert "Richardson" in p.method and abs(p.volume - 0.28) <= p.error.volume
    p = mass_properties(I.sphere(1.0), tolerance=1e-5)     # below the feature levels' floor
    assert "Richardson" in p.method and abs(p.volume - 4 * np.pi / 3) <= p.error.volume <= 1e-5 * p.volume
    with pytest.raises(TypeError, match="progress"):
        mass_properties(I.sphere(1.0), progress="yes")


def test_a_thin_part_may_take_levels_beyond_the_cells_allowed_while_they_fit(monkeypatch):
    import spatial.analysis.mass_solid as ms

    plate = I.box((10.0, 10.0, 0.5))               # its wall sets the levels: 24, 48, 96 cells
    monkeypatch.setattr(ms, "MAX_CELLS", 32)
    monkeypatch.setattr(ms, "FEATURE_FLOOR", 0.0)
    monkeypatch.setattr(ms, "FEATURE_TRIANGLES", 500_000)     # 192 cells: 0.28 M estimated, 384: 1.1 M
    with pytest.raises(ToleranceError, match="at 192 cells") as info:
        mass_properties(plate, tolerance=1e-12)
    assert info.value.estimate < 1e-4
    monkeypatch.setattr(ms, "FEATURE_TRIANGLES", 100_000)
    with pytest.raises(ToleranceError, match="at 96 cells"):
        mass_properties(plate, tolerance=1e-12)


@settings(max_examples=8, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(thin=st.floats(0.0, 2.0), wide=st.floats(0.0, 1.0), ax=st.floats(0.0, 90.0), ay=st.floats(0.0, 90.0),
       shift=st.tuples(*[st.floats(-50.0, 50.0)] * 3), scale=st.floats(0.05, 20.0))
def test_boxes_and_thin_plates_are_bracketed(thin, wide, ax, ay, shift, scale):
    """Aspect 1:1 to 100:1, any rotation and offset: the interval holds the exact volume, and the
    centroid and inertia theirs, at the tolerance asked for."""
    c = scale
    a = c * 10.0 ** thin                       # up to 100 times the thickness
    b = c + (a - c) * wide
    solid, ex = placed_box((a, b, c), ax, ay, np.array(shift) * scale)
    assert_brackets(mass_properties(solid, tolerance=1e-3), ex, 1e-3)


def test_the_mass_command_measures_at_the_chosen_levels(tmp_path, capsys):
    import json

    from spatial.cli import main

    model = tmp_path / "boss.py"
    model.write_text("from implicit import box\nsolid = box((4.0, 4.0, 1.0)) | box((1.0, 1.0, 1.0), "
                     "center=(0.0, 0.0, 1.0))\n")
    assert main(["mass", str(model), "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "sharp edges rebuilt" in out["method"]
    assert abs(out["volume"] - 17.0) <= out["error"]["volume"] <= 1e-4 * 17.0
    assert main(["mass", str(model), "--json", "--quiet", "--resolution", "32"]) == 0
    assert "Richardson" in json.loads(capsys.readouterr().out)["method"]
