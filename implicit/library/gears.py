"""Involute spur gears: module, teeth, pressure angle, face width, bore, keyway.

The outline is sampled from the involute of the base circle (radius
``r_b = m z cos(alpha) / 2``): a flank point at radius ``rho`` lies at the
polar angle ``psi + inv(alpha) - inv(alpha_rho)`` from the tooth's centre
line, with ``inv(a) = tan(a) - a``, ``cos(alpha_rho) = r_b / rho`` and
``psi = pi / (2 z)`` the half tooth angle at the pitch circle (tooth
thickness ``pi m / 2``).  Addendum ``m``, dedendum ``1.25 m`` (ISO 53 basic
rack); below the base circle the flank runs radially to the root circle.
The gear is extruded along z, centred on the origin.

Examples
--------
>>> from implicit.library import spur_gear
>>> g = spur_gear(module=2, teeth=20, face_width=10, bore=10)
>>> round(g.params["params"]["module"] * 20 / 2, 3)     # pitch radius
20.0
"""

from __future__ import annotations

import math

import numpy as np

from ..csg import difference
from ..families import Parameter, instance, label
from ..primitives import box, cylinder
from ..sweeps import extrude, polygon
from .common import count, define, fail, plane, pos, round_face

__all__ = ["spur_gear", "gear_outline", "polygon_area", "keyway_area"]

FLANK_SAMPLES = 10
TIP_SAMPLES = 4
ROOT_SAMPLES = 4


def _inv(a):
    return np.tan(a) - a


def gear_outline(module, teeth, pressure_angle=20.0):
    """Vertices (m, 2) of the gear outline, counter-clockwise.

    Examples
    --------
    >>> gear_outline(2.0, 12).shape
    (264, 2)
    """
    alpha = math.radians(pressure_angle)
    r = module * teeth / 2
    rb, ra, rf = r * math.cos(alpha), r + module, r - 1.25 * module
    psi = math.pi / (2 * teeth)

    def theta(rho):
        a_rho = np.arccos(np.clip(rb / rho, -1.0, 1.0))
        return psi + _inv(alpha) - _inv(a_rho)

    rho = np.linspace(max(rb, rf), ra, FLANK_SAMPLES)
    th = theta(rho)
    if rf < rb:  # radial flank from the root circle up to the base circle
        rho = np.concatenate([[rf], rho])
        th = np.concatenate([[th[0]], th])
    tip = np.linspace(-th[-1], th[-1], TIP_SAMPLES + 2)[1:-1]
    pitch = 2 * math.pi / teeth
    root = np.linspace(th[0], pitch - th[0], ROOT_SAMPLES + 2)[1:-1]
    # one tooth, counter-clockwise: right flank out, tip, left flank in, root gap
    ang = np.concatenate([-th, tip, th[::-1], root])
    rad = np.concatenate([rho, np.full(tip.size, ra), rho[::-1], np.full(root.size, rf)])
    k = np.arange(teeth)[:, None] * pitch
    a = (ang[None, :] + k).ravel()
    rr = np.tile(rad, teeth)
    return np.column_stack([rr * np.cos(a), rr * np.sin(a)])


def polygon_area(vertices) -> float:
    """Shoelace area of a simple polygon (positive when counter-clockwise)."""
    v = np.asarray(vertices, dtype=np.float64)
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def keyway_area(radius, width, top):
    """Area of ``{|x| < width/2, y < top, x^2 + y^2 > radius^2 or y > 0 ...}`` cut by a keyway.

    The region between the circle of `radius` and the line ``y = top`` over
    ``|x| < width / 2`` (``top`` above the circle's chord): what a keyway of
    that width reaching ``y = top`` adds to a bore, or, with ``top`` measured
    below the circle, what it removes from a shaft (see `keyed_shaft`).
    """
    h = width / 2
    under_arc = h * math.sqrt(radius ** 2 - h ** 2) + radius ** 2 * math.asin(h / radius)
    return width * top - under_arc


def _gear_check(module, teeth, pressure_angle, face_width, bore, keyway_width, keyway_depth):
    name = "spur_gear"
    r = module * teeth / 2
    rf = r - 1.25 * module
    alpha = math.radians(pressure_angle)
    rb = r * math.cos(alpha)
    if rf <= 0:
        fail(name, f"{teeth} teeth of module {module:g} leave no root circle")
    ra = r + module
    a_ra = math.acos(rb / ra)
    if math.pi / (2 * teeth) + _inv(alpha) - _inv(a_ra) <= 0:
        fail(name, f"{teeth} teeth at pressure angle {pressure_angle:g} are pointed before the tip circle")
    if bore and bore / 2 + (keyway_depth if keyway_width else 0.0) >= 0.9 * rf:
        fail(name, f"bore ({bore:g}) and keyway leave no web inside the root circle (radius {rf:g})")
    if keyway_width and not bore:
        fail(name, "a keyway needs a bore")
    if keyway_width and keyway_width >= bore:
        fail(name, f"keyway_width ({keyway_width:g}) must be less than the bore ({bore:g})")


def _gear(module, teeth, pressure_angle, face_width, bore, keyway_width, keyway_depth):
    body = label(extrude(polygon(gear_outline(module, teeth, pressure_angle)), face_width), "gear",
                 {"top": "front", "bottom": "back", "side": "teeth"})
    tools = []
    if bore:
        tools.append(label(cylinder(bore / 2, 3 * face_width), "gear", {"wall": "bore"}))
    if keyway_width:
        top = bore / 2 + keyway_depth
        tools.append(label(box((keyway_width, top, 3 * face_width), center=(0.0, top / 2, 0.0)), "gear",
                           {"+y": "keyway_floor", "-x": "keyway_side_1", "+x": "keyway_side_2"}))
    return difference(body, *tools) if tools else body


def _gear_faces(module, teeth, pressure_angle, face_width, bore, keyway_width, keyway_depth):
    r = module * teeth / 2
    faces = {"front": plane((0, 0, 1), (0, 0, face_width / 2)), "back": plane((0, 0, -1), (0, 0, -face_width / 2)),
             "tip_circle": round_face(r + module), "root_circle": round_face(r - 1.25 * module)}
    if bore:
        faces["bore"] = round_face(bore / 2)
    if keyway_width:
        faces["keyway_floor"] = plane((0, -1, 0), (0, bore / 2 + keyway_depth, 0))
        faces["keyway_side_1"] = plane((1, 0, 0), (-keyway_width / 2, 0, 0))
        faces["keyway_side_2"] = plane((-1, 0, 0), (keyway_width / 2, 0, 0))
    return faces


define("spur_gear", "Involute spur gear (ISO 53 rack: addendum m, dedendum 1.25 m), axis z, centred.",
       (pos("module", 2.0, "module m"),
        count("teeth", 20, "number of teeth z", minimum=6, maximum=400),
        Parameter("pressure_angle", float, 20.0, "deg", 10.0, 35.0, False, "pressure angle alpha"),
        pos("face_width", 10.0, "face width b"),
        Parameter("bore", float, 10.0, "mm", 0.0, None, False, "bore diameter (0: none)"),
        Parameter("keyway_width", float, 0.0, "mm", 0.0, None, False, "hub keyway width (0: none)"),
        Parameter("keyway_depth", float, 0.0, "mm", 0.0, None, False, "hub keyway depth above the bore")),
       _gear, _gear_check, _gear_faces)


def spur_gear(**params):
    """A spur gear; see the family's parameters (`implicad families`)."""
    return instance("spur_gear", **params)
