"""Structural sections: L (equal angle), T, U (channel) and I (beam) profiles.

Each is its cross-section polygon (in the xy plane, corner or web at the
origin, see each family) extruded along z over `length`, centred on z = 0.
Root and toe radii are left out, so the volume is the polygon's area times
the length.  Every face is named after its side of the section.

Examples
--------
>>> from implicit.library import i_beam
>>> i_beam("IPE200", length=1000).params["params"]["flange"]
8.5
"""

from __future__ import annotations

import numpy as np

from ..families import label
from ..sweeps import extrude, polygon
from .common import define, fail, plane, pos, standard_instance
from .tables import EN10055_TEES, EN10056_ANGLES, IPE_BEAMS, UPN_CHANNELS

__all__ = ["angle_section", "tee_section", "channel_section", "i_beam", "section_outline", "SECTION_SIDES"]

#: Names of the sides of each outline, in vertex order (side i runs from vertex i to i + 1).
SECTION_SIDES = {
    "angle_section": ["bottom", "leg_end_x", "leg_inner_x", "leg_inner_y", "leg_end_y", "back"],
    "tee_section": ["stem_end", "stem_side_1", "flange_under_1", "flange_end_1", "flange_top", "flange_end_2",
                    "flange_under_2", "stem_side_2"],
    "channel_section": ["flange_outer_1", "flange_end_1", "flange_inner_1", "web_inner", "flange_inner_2",
                        "flange_end_2", "flange_outer_2", "web_back"],
    "i_beam": ["bottom", "flange_end_1", "flange_top_1", "web_1", "flange_under_1", "flange_end_2", "top",
               "flange_end_3", "flange_under_2", "web_2", "flange_top_2", "flange_end_4"],
}


def section_outline(family_name, **p) -> np.ndarray:
    """The counter-clockwise outline (m, 2) of a section family with parameters `p`."""
    if family_name == "angle_section":
        a, t = p["leg"], p["thickness"]
        v = [(0, 0), (a, 0), (a, t), (t, t), (t, a), (0, a)]
    elif family_name == "tee_section":
        b, h, t = p["width"], p["height"], p["thickness"]
        v = [(-t / 2, 0), (t / 2, 0), (t / 2, h - t), (b / 2, h - t), (b / 2, h), (-b / 2, h), (-b / 2, h - t),
             (-t / 2, h - t)]
    elif family_name == "channel_section":
        h, b, tw, tf = p["height"], p["width"], p["web"], p["flange"]
        v = [(0, 0), (b, 0), (b, tf), (tw, tf), (tw, h - tf), (b, h - tf), (b, h), (0, h)]
    elif family_name == "i_beam":
        h, b, tw, tf = p["height"], p["width"], p["web"], p["flange"]
        v = [(-b / 2, 0), (b / 2, 0), (b / 2, tf), (tw / 2, tf), (tw / 2, h - tf), (b / 2, h - tf), (b / 2, h),
             (-b / 2, h), (-b / 2, h - tf), (-tw / 2, h - tf), (-tw / 2, tf), (-b / 2, tf)]
    else:
        raise ValueError(f"family_name: expected one of {sorted(SECTION_SIDES)}, got {family_name!r}")
    return np.asarray(v, dtype=np.float64)


def _faces_of(family_name):
    def faces(length, **p):
        v = section_outline(family_name, **p)
        out = {}
        for name, a, b in zip(SECTION_SIDES[family_name], v, np.roll(v, -1, axis=0)):
            d = b - a
            n = np.array([d[1], -d[0], 0.0]) / np.hypot(*d)   # outward for a counter-clockwise outline
            out[name] = plane(n, (a[0], a[1], 0.0))
        out["end_1"] = plane((0, 0, -1), (0, 0, -length / 2))
        out["end_2"] = plane((0, 0, 1), (0, 0, length / 2))
        return out
    return faces


def _builder(family_name):
    def build(length, **p):
        return label(extrude(polygon(section_outline(family_name, **p)), length), "section",
                     {"side": "outside", "top": "end_2", "bottom": "end_1"})
    return build


def _thin(family_name, **dims):
    def check(length, **p):
        for thin, thick in dims.items():
            if p[thin] >= p[thick]:
                fail(family_name, f"{thin} ({p[thin]:g}) must be less than {thick} ({p[thick]:g})")
        if family_name in ("channel_section", "i_beam") and 2 * p["flange"] >= p["height"]:
            fail(family_name, f"two flanges ({2 * p['flange']:g}) do not fit in the height ({p['height']:g})")
    return check


_LEN = pos("length", 1000.0, "length along z")

define("angle_section", "Equal-leg angle (EN 10056-1): corner at the origin, legs along +x and +y.",
       (pos("leg", 50.0, "leg length a"), pos("thickness", 5.0, "thickness t"), _LEN),
       _builder("angle_section"), _thin("angle_section", thickness="leg"), _faces_of("angle_section"),
       EN10056_ANGLES)

define("tee_section", "Equal-flange tee (EN 10055): stem along +y from the origin, flange on top.",
       (pos("width", 50.0, "flange width b"), pos("height", 50.0, "height h"),
        pos("thickness", 6.0, "flange and stem thickness t"), _LEN),
       _builder("tee_section"), _thin("tee_section", thickness="height"), _faces_of("tee_section"), EN10055_TEES)

define("channel_section", "Channel (UPN, DIN 1026-1, flanges parallel): web back on x = 0, flanges along +x.",
       (pos("height", 100.0, "height h"), pos("width", 50.0, "flange width b"),
        pos("web", 6.0, "web thickness tw"), pos("flange", 8.5, "flange thickness tf"), _LEN),
       _builder("channel_section"), _thin("channel_section", web="width"), _faces_of("channel_section"),
       UPN_CHANNELS)

define("i_beam", "I beam (IPE, EN 10365): web on x = 0, bottom flange on y = 0.",
       (pos("height", 200.0, "height h"), pos("width", 100.0, "flange width b"),
        pos("web", 5.6, "web thickness tw"), pos("flange", 8.5, "flange thickness tf"), _LEN),
       _builder("i_beam"), _thin("i_beam", web="width"), _faces_of("i_beam"), IPE_BEAMS)


def angle_section(size: str = "L50x5", **params):
    """An equal-leg angle of a standard `size` (``"L20x3"`` ... ``"L120x12"``)."""
    return standard_instance("angle_section", size, **params)


def tee_section(size: str = "T50", **params):
    """An equal-flange tee of a standard `size` (``"T30"`` ... ``"T120"``)."""
    return standard_instance("tee_section", size, **params)


def channel_section(size: str = "UPN100", **params):
    """A UPN channel of a standard `size` (``"UPN80"`` ... ``"UPN260"``)."""
    return standard_instance("channel_section", size, **params)


def i_beam(size: str = "IPE200", **params):
    """An IPE beam of a standard `size` (``"IPE80"`` ... ``"IPE300"``)."""
    return standard_instance("i_beam", size, **params)
