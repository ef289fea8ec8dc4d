"""The part library: volumes against closed forms, sizes from the tables, named faces, bad input."""

import math

import numpy as np
import pytest

import implicit.library as lib
from implicit.families import families, instance
from implicit.library.fasteners import hexagon_area
from implicit.library.gears import gear_outline, keyway_area, polygon_area
from implicit.library.pipes import bend_volume, tee_volume
from implicit.library.sections import section_outline
from implicit.library.shafts import housing_volume, shaft_volume
from implicit.library.springs import spring_volume
from implicit.serialize import from_json, to_json
from spatial import mass_properties

#: Relative volume error accepted from the extrapolated mesh integral at resolution 96.
VOLUME_RTOL = 2e-3


def _vol(part, resolution=96):
    return mass_properties(part, resolution=resolution).volume


def _p(part):
    return part.params["params"]


CASES = [
    (lambda: lib.iso_bolt("M10", length=40),
     lambda p: hexagon_area(p["across_flats"]) * p["head_height"] + math.pi * p["diameter"] ** 2 / 4 * p["length"]),
    (lambda: lib.iso_nut("M12"),
     lambda p: (hexagon_area(p["across_flats"]) - math.pi * p["diameter"] ** 2 / 4) * p["height"]),
    (lambda: lib.iso_washer("M16"),
     lambda p: math.pi / 4 * (p["outer_diameter"] ** 2 - p["inner_diameter"] ** 2) * p["thickness"]),
    (lambda: lib.spur_gear(module=2, teeth=18, face_width=12, bore=12, keyway_width=4, keyway_depth=1.8),
     lambda p: p["face_width"] * (polygon_area(gear_outline(p["module"], p["teeth"], p["pressure_angle"]))
                                  - math.pi * p["bore"] ** 2 / 4
                                  - keyway_area(p["bore"] / 2, p["keyway_width"], p["bore"] / 2 + p["keyway_depth"]))),
    (lambda: lib.pipe_flange("DN50"),
     lambda p: math.pi / 4 * (p["flange_diameter"] ** 2 - p["bore"] ** 2 - p["bolt_holes"] * p["hole_diameter"] ** 2)
     * p["thickness"]),
    (lambda: lib.pipe_tee(outer_diameter=60, wall=8, run_length=150, branch_length=80),
     lambda p: tee_volume(**p)),
    (lambda: lib.pipe_bend(outer_diameter=40, wall=6, bend_radius=60, angle=90),
     lambda p: bend_volume(**p)),
    (lambda: lib.keyed_shaft(diameter=25, length=100, rounded_ends=False),
     lambda p: shaft_volume(p["diameter"], p["length"], p["key_width"], p["keyway_depth"], p["keyway_length"])),
    (lambda: lib.bearing_housing(), lambda p: housing_volume(**p)),
] + [
    (lambda f=f, s=s: f(s, length=200), lambda p, n=n: polygon_area(section_outline(n, **p)) * p["length"])
    for f, s, n in ((lib.angle_section, "L50x5", "angle_section"), (lib.tee_section, "T60", "tee_section"),
                    (lib.channel_section, "UPN100", "channel_section"), (lib.i_beam, "IPE120", "i_beam"))
]


@pytest.mark.parametrize("make, closed_form", CASES, ids=lambda x: "")
def test_volume_matches_closed_form(make, closed_form):
    part = make()
    exact = closed_form(_p(part))
    assert _vol(part) == pytest.approx(exact, rel=VOLUME_RTOL)


def test_spring_volume_is_wire_area_times_helix_length():
    part = lib.helical_spring(coil_diameter=20, wire_diameter=3, pitch=8, coils=2)
    exact = spring_volume(**_p(part))
    assert _vol(part, resolution=64) == pytest.approx(exact, rel=2e-2)


def test_at_least_twelve_families_all_registered_and_round_trip_json():
    assert len(lib.LIBRARY_FAMILIES) >= 12
    for name in lib.LIBRARY_FAMILIES:
        assert name in families()
        part = instance(name)
        back = from_json(to_json(part))
        pts = np.random.default_rng(0).uniform(*part.bounds, size=(200, 3))
        np.testing.assert_allclose(back(pts), part(pts), atol=1e-12)


def test_standard_sizes_come_from_the_tables():
    bolt = lib.iso_bolt("M20", length=80)
    assert (_p(bolt)["across_flats"], _p(bolt)["head_height"]) == (30.0, 12.5)
    assert _p(lib.iso_nut("M8"))["height"] == 6.8
    assert _p(lib.iso_washer("M10"))["outer_diameter"] == 20.0
    flange = lib.pipe_flange("DN100")
    assert (_p(flange)["flange_diameter"], _p(flange)["bolt_circle"], _p(flange)["bolt_holes"]) == (220.0, 180.0, 8)
    assert _p(lib.keyed_shaft(diameter=40))["key_width"] == 12.0
    assert _p(lib.i_beam("IPE300"))["flange"] == 10.7
    assert lib.standard_sizes("iso4014_bolt")[0] == "M3"


def test_gear_outline_lies_between_root_and_tip_circles_and_has_the_pitch_thickness():
    m, z = 3.0, 24
    v = gear_outline(m, z, 20.0)
    r = np.hypot(v[:, 0], v[:, 1])
    assert r.min() == pytest.approx(m * z / 2 - 1.25 * m)
    assert r.max() == pytest.approx(m * z / 2 + m)
    # area between the root and tip disks
    assert math.pi * r.min() ** 2 < polygon_area(v) < math.pi * r.max() ** 2


def test_named_faces_hold_the_surface_points():
    part = lib.iso_nut("M10")
    faces = lib.named_faces(part)
    assert {"bore", "top", "bearing_face", "flat_1"} <= set(faces)
    p = _p(part)
    pts = np.array([[p["diameter"] / 2, 0.0, 3.0], [0.0, -p["across_flats"] / 2 + 0, 4.0], [2.0 + p["diameter"] / 2, 2.0, p["height"]]])
    names = lib.face_names(part, pts)
    assert names[0] == "bore" and names[2] == "top" and names[1].startswith("flat_")


def test_every_library_family_names_its_faces():
    for name in lib.LIBRARY_FAMILIES:
        assert len(lib.named_faces(instance(name))) >= 2


@pytest.mark.parametrize("call, message", [
    (lambda: lib.iso_bolt("M7"), "unknown size 'M7'"),
    (lambda: lib.iso_bolt("M10", length=-4), "iso4014_bolt.length: expected a positive number"),
    (lambda: lib.spur_gear(teeth=4), "spur_gear.teeth"),
    (lambda: lib.spur_gear(module=1, teeth=12, bore=12), "leave no web"),
    (lambda: lib.pipe_flange("DN50", hole_diameter=40), "cut into the bore|overlap|break out"),
    (lambda: lib.keyed_shaft(diameter=200), "DIN 6885-1 covers"),
    (lambda: lib.helical_spring(wire_diameter=7, pitch=6), "coils would touch"),
    (lambda: lib.i_beam("IPE200", web=200), "web"),
    (lambda: lib.angle_section(leg=5, thickness=6), "thickness"),
])
def test_bad_parameters_are_refused_with_the_name(call, message):
    with pytest.raises((ValueError, TypeError), match=message):
        call()


#: The faces each family names on its boundary (what `implicad info` lists and FEA face sets are called).
FAMILY_FACES = {
    "en1092_flange": {"flange.top", "flange.bottom", "flange.rim", "flange.bore", "hole_1.wall", "hole_4.wall"},
    "l_bracket": {"bracket.base_bottom", "bracket.base_top", "bracket.upright_top", "bracket.back", "hole_1.wall",
                  "hole_4.wall"},
    "spur_gear": {"gear.front", "gear.back", "gear.teeth", "gear.bore"},
    "hole_plate": {"plate.top", "plate.bottom", "hole_1.wall", "hole_6.wall"},
    "iso4014_bolt": {"bolt.head_top", "bolt.bearing_face", "bolt.shank", "bolt.end"},
    "bearing_housing": {"housing.bore", "housing.base_bottom", "hole_1.wall", "hole_2.wall"},
}


@pytest.mark.parametrize("name", sorted(FAMILY_FACES))
def test_families_name_their_own_faces_and_the_names_survive_json(name):
    from spatial.fea.facets import FacetField, face_names

    part = instance(name)
    names = face_names(part, resolution=40)
    assert FAMILY_FACES[name] <= set(names), sorted(names)
    assert not any(n.split(".")[0].rsplit("_", 1)[0] in ("box", "cylinder", "extrude") for n in names), names
    back = from_json(to_json(part))
    assert FacetField(back).names == FacetField(part).names


def test_the_named_face_is_the_face_its_name_says():
    from spatial.fea.facets import FacetField

    part = instance("l_bracket", thickness=5.0)
    ff = FacetField(part)
    # points on the bottom of the base, the top of the base and the wall of the first hole
    hole_x = 5.0 + (60.0 - 5.0) / 3.0
    pts = np.array([[30.0, 5.0, 0.0], [30.0, 5.0, 5.0], [hole_x + 3.0, 20.0, 2.5]])
    _, dec, _ = ff(pts)
    assert [ff.names[i] for i in dec] == ["bracket.base_bottom", "bracket.base_top", "hole_1.wall"]


def test_plain_primitives_keep_the_tree_names_and_label_needs_a_family():
    from implicit import box, cylinder
    from implicit.families import label
    from spatial.fea.facets import FacetField

    assert "cylinder_1.wall" in FacetField(box(2.0) - cylinder(0.5, 4.0)).names
    with pytest.raises(ValueError, match="inside a family's builder"):
        label(box(1.0), "plate")
    with pytest.raises(ValueError, match="label"):
        label(box(1.0), "a.b")
