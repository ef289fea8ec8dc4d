"""Fasteners: ISO 4014 hexagon head bolts, ISO 4032 nuts, ISO 7089 plain washers.

The bolt's bearing face lies on z = 0, its head above, the shank along -z;
nuts and washers sit on z = 0 with their axis along z.  Threads are drawn at
their nominal diameter.

Examples
--------
>>> from implicit.library import iso_bolt
>>> bolt = iso_bolt("M10", length=40)
>>> bolt.params["params"]["across_flats"]
16.0
"""

from __future__ import annotations

import math

import numpy as np

from ..csg import difference, union
from ..families import label
from ..polyhedra import prism
from ..primitives import cylinder
from .common import count, define, fail, hexagon, plane, pos, round_face, standard_instance  # noqa: F401
from .tables import ISO4014_BOLTS, ISO4032_NUTS, ISO7089_WASHERS

__all__ = ["iso_bolt", "iso_nut", "iso_washer", "hexagon_area"]


def hexagon_area(across_flats: float) -> float:
    """Area of a regular hexagon of width `across_flats`: sqrt(3)/2 s^2."""
    return math.sqrt(3.0) / 2.0 * across_flats ** 2


def _hex_faces(across_flats, z0, z1, prefix="flat"):
    faces = {}
    for i, a in enumerate(np.radians(np.arange(6) * 60.0 + 30.0)):
        n = (math.cos(a), math.sin(a), 0.0)
        faces[f"{prefix}_{i + 1}"] = plane(n, (across_flats / 2 * n[0], across_flats / 2 * n[1], 0.0))
    return faces


# ISO 4014 bolt ---------------------------------------------------------------

def _bolt_check(diameter, length, head_height, across_flats):
    if across_flats <= diameter:
        fail("iso4014_bolt", f"across_flats ({across_flats:g}) must exceed the diameter ({diameter:g})")


def _bolt(diameter, length, head_height, across_flats):
    head = label(prism(hexagon(across_flats), head_height, center=(0.0, 0.0, head_height / 2)), "bolt",
                 {"top": "head_top", "bottom": "bearing_face", "side": "head_flats"})
    shank = label(cylinder(diameter / 2, length, center=(0.0, 0.0, -length / 2)), "bolt",
                  {"wall": "shank", "bottom": "end", "top": "shank_top"})
    return union(head, shank)


def _bolt_faces(diameter, length, head_height, across_flats):
    faces = {"head_top": plane((0, 0, 1), (0, 0, head_height)),
             "bearing_face": plane((0, 0, -1), (0, 0, 0)),
             "shank": round_face(diameter / 2),
             "end": plane((0, 0, -1), (0, 0, -length))}
    faces.update(_hex_faces(across_flats, 0.0, head_height))
    return faces


define("iso4014_bolt", "ISO 4014 hexagon head bolt: bearing face on z = 0, head above, shank along -z.",
       (pos("diameter", 10.0, "nominal diameter d"),
        pos("length", 40.0, "nominal length l under the head"),
        pos("head_height", 6.4, "head height k"),
        pos("across_flats", 16.0, "width across flats s")),
       _bolt, _bolt_check, _bolt_faces, ISO4014_BOLTS)


def iso_bolt(size: str = "M10", **params):
    """An ISO 4014 bolt of a standard `size` (``"M3"`` ... ``"M36"``); `length` etc. on top."""
    return standard_instance("iso4014_bolt", size, **params)


# ISO 4032 nut ------------------------------------------------------------------

def _nut_check(diameter, height, across_flats):
    if across_flats <= diameter:
        fail("iso4032_nut", f"across_flats ({across_flats:g}) must exceed the diameter ({diameter:g})")


def _nut(diameter, height, across_flats):
    body = label(prism(hexagon(across_flats), height, center=(0.0, 0.0, height / 2)), "nut",
                 {"top": "top", "bottom": "bearing_face", "side": "flats"})
    bore = label(cylinder(diameter / 2, 3 * height, center=(0.0, 0.0, height / 2)), "nut", {"wall": "bore"})
    return difference(body, bore)


def _nut_faces(diameter, height, across_flats):
    faces = {"bearing_face": plane((0, 0, -1), (0, 0, 0)), "top": plane((0, 0, 1), (0, 0, height)),
             "bore": round_face(diameter / 2)}
    faces.update(_hex_faces(across_flats, 0.0, height))
    return faces


define("iso4032_nut", "ISO 4032 hexagon nut (style 1) on z = 0, axis z, bore at the nominal diameter.",
       (pos("diameter", 10.0, "nominal diameter d"),
        pos("height", 8.4, "nut height m"),
        pos("across_flats", 16.0, "width across flats s")),
       _nut, _nut_check, _nut_faces, ISO4032_NUTS)


def iso_nut(size: str = "M10", **params):
    """An ISO 4032 nut of a standard `size`."""
    return standard_instance("iso4032_nut", size, **params)


# ISO 7089 washer ----------------------------------------------------------------

def _washer_check(inner_diameter, outer_diameter, thickness):
    if inner_diameter >= outer_diameter:
        fail("iso7089_washer", f"inner_diameter ({inner_diameter:g}) must be less than outer_diameter "
                               f"({outer_diameter:g})")


def _washer(inner_diameter, outer_diameter, thickness):
    ring = label(cylinder(outer_diameter / 2, thickness, center=(0.0, 0.0, thickness / 2)), "washer",
                 {"wall": "outside"})
    hole = label(cylinder(inner_diameter / 2, 3 * thickness, center=(0.0, 0.0, thickness / 2)), "washer",
                 {"wall": "bore"})
    return difference(ring, hole)


def _washer_faces(inner_diameter, outer_diameter, thickness):
    return {"bottom": plane((0, 0, -1), (0, 0, 0)), "top": plane((0, 0, 1), (0, 0, thickness)),
            "bore": round_face(inner_diameter / 2), "rim": round_face(outer_diameter / 2)}


define("iso7089_washer", "ISO 7089 plain washer (normal series) on z = 0, axis z.",
       (pos("inner_diameter", 10.5, "inner diameter d1"),
        pos("outer_diameter", 20.0, "outer diameter d2"),
        pos("thickness", 2.0, "thickness h")),
       _washer, _washer_check, _washer_faces, ISO7089_WASHERS)


def iso_washer(size: str = "M10", **params):
    """An ISO 7089 washer for a bolt of standard `size`."""
    return standard_instance("iso7089_washer", size, **params)
