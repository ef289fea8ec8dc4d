"""Shafts with DIN 6885 keyways, and pillow-block bearing housings.

The shaft's axis is z (centred), the keyway on its +y side, centred along
the shaft.  The housing's bore axis is x at height `centre_height`, its base
on z = 0.

Examples
--------
>>> from implicit.library import keyed_shaft
>>> keyed_shaft(diameter=25, length=100).params["params"]["key_width"]
8.0
"""

from __future__ import annotations

import math

from ..csg import difference, union
from ..families import Parameter, instance, label
from ..primitives import box, cylinder
from .common import define, fail, plane, pos, round_face
from .gears import keyway_area
from .tables import key_for_shaft

__all__ = ["keyed_shaft", "bearing_housing", "shaft_volume", "housing_volume"]


def shaft_volume(diameter, length, key_width, keyway_depth, keyway_length, rounded_ends=False):
    """Closed-form volume of a square-ended keyway shaft (`rounded_ends` False).

    The keyway removes, over ``|x| < b/2``, the circle's cap above ``y = r - t1``.
    """
    if rounded_ends:
        raise ValueError("rounded_ends: the closed form covers square-ended keyways only")
    r = diameter / 2
    cap = -keyway_area(r, key_width, r - keyway_depth)  # (arc - chord line) over |x| < b/2
    return math.pi * r * r * length - cap * keyway_length


def _shaft_check(diameter, length, key_width, key_height, keyway_depth, keyway_length, rounded_ends):
    name = "keyed_shaft"
    if key_width >= diameter:
        fail(name, f"key_width ({key_width:g}) must be less than the diameter ({diameter:g})")
    if keyway_depth >= diameter / 2:
        fail(name, f"keyway_depth ({keyway_depth:g}) must be less than the radius ({diameter / 2:g})")
    if keyway_length > length:
        fail(name, f"keyway_length ({keyway_length:g}) must not exceed the length ({length:g})")
    if rounded_ends and keyway_length < key_width:
        fail(name, f"a rounded keyway ({keyway_length:g} long) must be at least key_width ({key_width:g}) long")


def _shaft(diameter, length, key_width, key_height, keyway_depth, keyway_length, rounded_ends):
    r = diameter / 2
    y0 = r - keyway_depth
    deep = keyway_depth + r  # reaches past the surface
    if rounded_ends:
        straight = keyway_length - key_width
        pieces = [cylinder(key_width / 2, deep, center=(0.0, y0 + deep / 2, z), axis=(0.0, 1.0, 0.0))
                  for z in (-straight / 2, straight / 2)]
        if straight > 0:
            pieces.append(box((key_width, deep, straight), center=(0.0, y0 + deep / 2, 0.0)))
        slot = union(*pieces) if len(pieces) > 1 else pieces[0]
    else:
        slot = box((key_width, deep, keyway_length), center=(0.0, y0 + deep / 2, 0.0))
    slot = label(slot, "keyway", {"-y": "floor", "bottom": "floor", "+x": "side_2", "-x": "side_1", "+z": "end_2", "-z": "end_1",
                                  "wall": "end"})
    return difference(label(cylinder(r, length), "shaft", {"wall": "journal", "top": "end_2", "bottom": "end_1"}),
                      slot)


def _shaft_faces(diameter, length, key_width, key_height, keyway_depth, keyway_length, rounded_ends):
    r = diameter / 2
    return {"journal": round_face(r), "end_1": plane((0, 0, -1), (0, 0, -length / 2)),
            "end_2": plane((0, 0, 1), (0, 0, length / 2)),
            "keyway_floor": plane((0, 1, 0), (0, r - keyway_depth, 0)),
            "keyway_side_1": plane((1, 0, 0), (-key_width / 2, 0, 0)),
            "keyway_side_2": plane((-1, 0, 0), (key_width / 2, 0, 0))}


define("keyed_shaft", "Shaft along z (centred) with a DIN 6885-1 keyway on its +y side.",
       (pos("diameter", 25.0, "shaft diameter d"),
        pos("length", 100.0, "shaft length"),
        pos("key_width", 8.0, "key width b (DIN 6885-1)"),
        pos("key_height", 7.0, "key height h (DIN 6885-1; the key itself is not modelled)"),
        pos("keyway_depth", 4.0, "shaft keyway depth t1 (DIN 6885-1)"),
        pos("keyway_length", 40.0, "keyway length"),
        Parameter("rounded_ends", bool, True, "", description="form A (rounded ends) or square ends")),
       _shaft, _shaft_check, _shaft_faces)


def keyed_shaft(*, diameter=25.0, length=100.0, keyway_length=None, **params):
    """A keyed shaft; key width, height and keyway depth default to DIN 6885-1 for `diameter`."""
    key = key_for_shaft(diameter)
    key.update(params)
    if keyway_length is None:
        keyway_length = min(length, max(2.0 * diameter, key["key_width"]))
    return instance("keyed_shaft", diameter=diameter, length=length, keyway_length=keyway_length, **key)


# bearing housing ----------------------------------------------------------------

def housing_volume(bore, outer_radius, centre_height, width, base_length, base_height, hole_diameter, **_):
    """Closed-form volume of `bearing_housing` (inclusion-exclusion of base, riser, boss, bore, holes)."""
    ro = outer_radius
    body = (width * base_length * base_height + width * 2 * ro * (centre_height - base_height)
            + math.pi * ro * ro * width / 2)
    return body - math.pi * (bore / 2) ** 2 * width - 2 * math.pi * (hole_diameter / 2) ** 2 * base_height


def _housing_check(bore, outer_radius, centre_height, width, base_length, base_height, hole_diameter,
                   hole_spacing):
    name = "bearing_housing"
    if bore / 2 >= outer_radius:
        fail(name, f"bore ({bore:g}) must be less than the boss diameter ({2 * outer_radius:g})")
    if centre_height - outer_radius < base_height:
        fail(name, f"the boss (radius {outer_radius:g} at height {centre_height:g}) must clear the base "
                   f"({base_height:g} high)")
    if hole_spacing / 2 - hole_diameter / 2 <= outer_radius:
        fail(name, f"bolt holes at spacing {hole_spacing:g} cut into the riser (half width {outer_radius:g})")
    if hole_spacing / 2 + hole_diameter / 2 >= base_length / 2:
        fail(name, f"bolt holes at spacing {hole_spacing:g} break out of the base ({base_length:g} long)")
    if hole_diameter >= width:
        fail(name, f"hole_diameter ({hole_diameter:g}) must be less than the width ({width:g})")


def _housing(bore, outer_radius, centre_height, width, base_length, base_height, hole_diameter, hole_spacing):
    x = (1.0, 0.0, 0.0)
    sides = {"+x": "side_2", "-x": "side_1"}
    base = label(box((width, base_length, base_height), center=(0.0, 0.0, base_height / 2)), "housing",
                 {**sides, "-z": "base_bottom", "+z": "base_top", "+y": "base_end_2", "-y": "base_end_1"})
    riser = label(box((width, 2 * outer_radius, centre_height), center=(0.0, 0.0, centre_height / 2)), "housing",
                  {**sides, "-z": "base_bottom", "+y": "riser_2", "-y": "riser_1", "+z": "riser_top"})
    boss = label(cylinder(outer_radius, width, center=(0.0, 0.0, centre_height), axis=x), "housing",
                 {"wall": "boss", "top": "side_2", "bottom": "side_1"})
    tools = [label(cylinder(bore / 2, 3 * width, center=(0.0, 0.0, centre_height), axis=x), "housing",
                   {"wall": "bore"})]
    tools += [label(cylinder(hole_diameter / 2, 3 * base_height, center=(0.0, s * hole_spacing / 2, base_height / 2)),
                    f"hole_{i + 1}") for i, s in enumerate((-1, 1))]
    return difference(union(base, riser, boss), *tools)


def _housing_faces(bore, outer_radius, centre_height, width, base_length, base_height, hole_diameter,
                   hole_spacing):
    x = (1.0, 0.0, 0.0)
    return {"bore": round_face(bore / 2, center=(0, 0, centre_height), axis=x),
            "boss": round_face(outer_radius, center=(0, 0, centre_height), axis=x),
            "base_bottom": plane((0, 0, -1), (0, 0, 0)), "base_top": plane((0, 0, 1), (0, 0, base_height)),
            "side_1": plane((-1, 0, 0), (-width / 2, 0, 0)), "side_2": plane((1, 0, 0), (width / 2, 0, 0)),
            "riser_1": plane((0, -1, 0), (0, -outer_radius, 0)), "riser_2": plane((0, 1, 0), (0, outer_radius, 0)),
            "base_end_1": plane((0, -1, 0), (0, -base_length / 2, 0)),
            "base_end_2": plane((0, 1, 0), (0, base_length / 2, 0)),
            "bolt_hole_1": round_face(hole_diameter / 2, center=(0, -hole_spacing / 2, 0)),
            "bolt_hole_2": round_face(hole_diameter / 2, center=(0, hole_spacing / 2, 0))}


define("bearing_housing", "Pillow-block bearing housing: bore along x at centre_height, base on z = 0.",
       (pos("bore", 52.0, "bore diameter (bearing outside diameter)"),
        pos("outer_radius", 40.0, "boss outer radius"),
        pos("centre_height", 60.0, "bore axis height above the base"),
        pos("width", 40.0, "housing width along the bore"),
        pos("base_length", 200.0, "base length across the bore"),
        pos("base_height", 18.0, "base thickness"),
        pos("hole_diameter", 14.0, "bolt hole diameter"),
        pos("hole_spacing", 150.0, "distance between the bolt holes")),
       _housing, _housing_check, _housing_faces)


def bearing_housing(**params):
    """A pillow-block housing; see the family's parameters."""
    return instance("bearing_housing", **params)
