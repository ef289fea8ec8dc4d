"""Part families: typed parameters, geometry checks, the built parts."""

import math

import numpy as np
import pytest

from implicit.families import Family, FamilyInstance, Parameter, families, family, instance, register_family
from implicit.serialize import from_json, to_dict, to_json


def test_registry_lists_the_families_with_typed_parameters():
    fams = families()
    assert list(fams)[:4] == ["hex_bolt", "flanged_pipe", "l_bracket", "hole_plate"]
    for fam in fams.values():
        assert fam.parameters
        for p in fam.parameters:
            assert p.type in (float, int, bool) and p.unit is not None and p.description
            assert p.validate(fam.name, p.default) == p.default
    plate = {p.name: p for p in fams["hole_plate"].parameters}
    assert plate["rows"].type is int and plate["rows"].describe()["range"] == "[1, 64]"
    assert plate["hole_diameter"].describe() == {
        "name": "hole_diameter", "type": "float", "default": 8.0, "unit": "mm", "range": "> 0",
        "description": "hole diameter"}


@pytest.mark.parametrize("name", ["hex_bolt", "flanged_pipe", "l_bracket", "hole_plate"])
def test_every_family_builds_with_its_defaults(name):
    part = instance(name)
    assert isinstance(part, FamilyInstance) and part.family_name == name
    assert part.is_bounded and part.count_primitives() >= 2
    assert part.params["params"] == {p.name: p.default for p in family(name).parameters}
    lo, hi = part.bounds
    pts = np.random.default_rng(0).uniform(lo, hi, (20000, 3))
    assert (part(pts) < 0).any()


def test_hole_plate_geometry():
    plate = instance("hole_plate", length=100, width=60, thickness=5, hole_diameter=8, rows=2, cols=3, margin=12)
    centres = [(-38, -18), (0, -18), (38, -18), (-38, 18), (0, 18), (38, 18)]
    pts = np.array([(x, y, 0.0) for x, y in centres])
    np.testing.assert_allclose(plate(pts), 4.0, atol=1e-12)                # hole axis: radius 4 from the wall
    np.testing.assert_allclose(plate([[-19, 0, 0], [0, 0, 2.5], [50, 0, 0]]), [-2.5, 0, 0], atol=1e-12)
    np.testing.assert_allclose(plate.bounds[0], [-50, -30, -2.5])


def test_hex_bolt_geometry():
    bolt = instance("hex_bolt", diameter=8, length=30, head_height=5, across_flats=13)
    # Across flats: the head's flat faces at y = +-6.5; the shank radius 4.
    np.testing.assert_allclose(bolt([[0, 7.5, 2.5], [0, 0, -15], [0, 0, -31], [0, 0, 6]]), [1, -4, 1, 1], atol=1e-12)
    lo, hi = bolt.bounds
    np.testing.assert_allclose(hi, [13 / math.sqrt(3), 6.5, 5], atol=1e-12)
    np.testing.assert_allclose(lo[2], -30)


def test_flanged_pipe_geometry():
    pipe = instance("flanged_pipe", outer_diameter=60, wall=5, length=200, flange_diameter=120,
                    flange_thickness=12, bolt_holes=4, hole_diameter=10, bolt_circle=90)
    # In the wall, in the bore, in a bolt hole, in the flange.
    vals = pipe([[27.5, 0, 0], [0, 0, 0], [45, 0, 95], [35, 35, 95], [50, 0, 0]])
    np.testing.assert_allclose(vals[:3], [-2.5, 25, 5], atol=1e-12)
    assert vals[3] < 0 and vals[4] > 0


def test_l_bracket_holes_are_through():
    b = instance("l_bracket", width=40, leg_a=60, leg_b=50, thickness=5, hole_diameter=6, holes_per_leg=2)
    # Holes in leg a at x = 5 + 55 k / 3, y = 20; in leg b at z = 5 + 45 k / 3.
    assert b([[5 + 55 / 3, 20, 2.5]])[0] == pytest.approx(3.0)
    assert b([[2.5, 20, 5 + 45 / 3]])[0] == pytest.approx(3.0)
    assert b([[30, 5, 2.5]])[0] < 0
    none = instance("l_bracket", holes_per_leg=0)
    assert none.count_primitives() == 2


@pytest.mark.parametrize("params, error, match", [
    ({"hole_diameter": -2}, ValueError, r"^hole_plate\.hole_diameter: expected a positive number, got -2$"),
    ({"hole_diameter": 0}, ValueError, r"hole_plate\.hole_diameter: expected a positive number, got 0"),
    ({"hole_diameter": float("nan")}, ValueError, r"hole_plate\.hole_diameter: expected a positive number, got nan"),
    ({"length": float("inf")}, ValueError, r"hole_plate\.length: expected a positive number, got inf"),
    ({"rows": 0}, ValueError, r"hole_plate\.rows: expected an integer in \[1, 64\], got 0"),
    ({"rows": 2.5}, ValueError, r"hole_plate\.rows: expected an integer in \[1, 64\], got 2\.5"),
    ({"cols": 100}, ValueError, r"hole_plate\.cols: expected an integer in \[1, 64\], got 100"),
    ({"width": "wide"}, TypeError, r"hole_plate\.width: expected a positive number, got 'wide'"),
    ({"width": True}, TypeError, r"hole_plate\.width: expected a positive number, got True"),
    ({"colour": 1}, ValueError, r"hole_plate: unknown parameter 'colour'; parameters: length, width"),
])
def test_bad_parameters_name_family_and_parameter(params, error, match):
    with pytest.raises(error, match=match):
        instance("hole_plate", **params)


@pytest.mark.parametrize("name, params, match", [
    ("hole_plate", {"hole_diameter": 30}, r"hole_plate: holes of diameter 30 at margin 12 break through the edge"),
    ("hole_plate", {"cols": 20}, r"hole_plate: 20 holes of diameter 8 overlap along the length \(pitch 4\)"),
    ("hole_plate", {"rows": 1, "cols": 1, "hole_diameter": 70}, r"hole_diameter \(70\) does not fit in the width"),
    ("hole_plate", {"margin": 60}, r"margin \(60\) leaves no room along the length"),
    ("hex_bolt", {"across_flats": 9}, r"hex_bolt: across_flats \(9\) must exceed the shank diameter \(10\)"),
    ("flanged_pipe", {"wall": 30}, r"flanged_pipe: wall \(30\) must be less than half the outer_diameter"),
    ("flanged_pipe", {"bolt_circle": 62}, r"bolt holes .* cut into the pipe"),
    ("flanged_pipe", {"bolt_circle": 115}, r"do not fit in the flange"),
    ("flanged_pipe", {"bolt_holes": 40}, r"40 bolt holes of diameter 10 overlap"),
    ("flanged_pipe", {"flange_thickness": 150}, r"two flanges \(300\) do not fit in length 200"),
    ("l_bracket", {"hole_diameter": 45}, r"l_bracket: hole_diameter \(45\) must be less than width"),
    ("l_bracket", {"holes_per_leg": 10}, r"10 holes of diameter 6 do not fit on leg_a"),
    ("l_bracket", {"thickness": 55}, r"thickness \(55\) must be less than both legs"),
])
def test_geometry_checks(name, params, match):
    with pytest.raises(ValueError, match=match):
        instance(name, **params)


def test_unknown_family_lists_the_known_ones():
    with pytest.raises(ValueError, match=r"unknown family 'gear'; known: hex_bolt, flanged_pipe, l_bracket, hole_plate"):
        instance("gear")
    with pytest.raises(TypeError, match="expected a family name"):
        family(3)


def test_instance_json_stores_only_the_family_call():
    part = instance("hole_plate", rows=1, cols=2)
    data = to_dict(part)
    assert data == {"kind": "family", "family": "hole_plate",
                    "params": {"length": 100.0, "width": 60.0, "thickness": 5.0, "hole_diameter": 8.0,
                               "rows": 1, "cols": 2, "margin": 12.0}}
    again = from_json(to_json(part))
    pts = np.random.default_rng(1).uniform(-60, 60, (2000, 3))
    np.testing.assert_array_equal(again(pts), part(pts))
    with pytest.raises(ValueError, match=r"^\$: hole_plate\.hole_diameter: expected a positive number, got -2$"):
        from_json({"kind": "family", "family": "hole_plate", "params": {"hole_diameter": -2}})
    with pytest.raises(ValueError, match=r"\$\.children: a family node is rebuilt from its parameters"):
        from_json({"kind": "family", "family": "hole_plate", "children": [{"kind": "sphere"}]})


def test_instance_label_and_repr():
    part = instance("hex_bolt", diameter=8)
    assert part.tree().splitlines()[0] == "family hex_bolt(diameter=8, length=40, head_height=7, across_flats=17)"
    assert repr(part).startswith("instance('hex_bolt', diameter=8.0, length=40.0")


def test_register_a_new_family():
    from implicit import sphere
    name = "test_ball_family"
    if name not in families():
        register_family(Family(name, "a ball", (Parameter("radius", float, 1.0, "mm", 0.0, None, True, "radius"),),
                               lambda radius: sphere(radius)))
    assert instance(name, radius=2.0)([[3.0, 0, 0]])[0] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="already registered"):
        register_family(families()[name])
