"""Helical compression springs: a round wire wound along a helix.

The spring's axis is z, its coils start at z = 0.  The wire is a tube about
the helix ``H(t) = (R cos t, R sin t, p t / 2 pi)``, ``0 <= t <= 2 pi n``,
with round ends; its field is the distance to the helix minus the wire's
radius: an exact distance while the wire is thinner than the helix's
curvature radius.  The closest helix parameter is found by Newton steps on
``|p - H(t)|^2`` from the three turns nearest the point's height at its
polar angle, vectorized over all points.

Examples
--------
>>> from implicit.library import helical_spring
>>> s = helical_spring(coil_diameter=20, wire_diameter=2, pitch=6, coils=3)
>>> round(float(s([[10.0, 0.0, 0.0]])[0]), 6)
-1.0
"""

from __future__ import annotations

import math

import numpy as np

from ..families import instance, label
from ..solid import Solid, as_positive
from .common import count, define, fail, pos, round_face

__all__ = ["HelicalCoil", "helical_spring", "spring_volume", "helix_length"]

NEWTON_STEPS = 8


class HelicalCoil(Solid):
    """A round wire of radius `wire_radius` along a helix of `radius`, `pitch` and `turns`."""

    kind = "helical_coil"
    __slots__ = ()

    def __init__(self, radius, pitch, turns, wire_radius):
        R, p = as_positive(radius, "radius"), as_positive(pitch, "pitch")
        n, a = as_positive(turns, "turns"), as_positive(wire_radius, "wire_radius")
        if a >= R:
            raise ValueError(f"wire_radius: expected less than the radius {R:g}, got {a:g}")
        lo = (-R - a, -R - a, -a)
        hi = (R + a, R + a, p * n + a)
        super().__init__((), {"radius": R, "pitch": p, "turns": n, "wire_radius": a}, (lo, hi),
                         exact=True, lipschitz=1.0)

    def _evaluate(self, q):
        P = self.params
        R, c, a = P["radius"], P["pitch"] / (2 * np.pi), P["wire_radius"]
        t_end = 2 * np.pi * P["turns"]
        x, y, z = q[:, 0:1], q[:, 1:2], q[:, 2:3]
        phi = np.arctan2(y, x)
        k = np.floor((z / c - phi) / (2 * np.pi)) + np.array([[-1.0, 0.0, 1.0, 2.0]])
        t = np.clip(phi + 2 * np.pi * k, 0.0, t_end)
        for _ in range(NEWTON_STEPS):  # minimise |q - H(t)|^2 / 2
            ct, st = np.cos(t), np.sin(t)
            g = R * (x * st - y * ct) + c * (c * t - z)
            h = R * (x * ct + y * st) + c * c
            t = np.clip(t - g / np.where(h > 1e-12, h, 1e-12), 0.0, t_end)
        d2 = (x - R * np.cos(t)) ** 2 + (y - R * np.sin(t)) ** 2 + (z - c * t) ** 2
        return np.sqrt(d2.min(axis=1)) - a



def helix_length(coil_diameter, pitch, coils):
    """Length of the centre line: n sqrt((pi D)^2 + p^2)."""
    return coils * math.hypot(math.pi * coil_diameter, pitch)


def spring_volume(coil_diameter, wire_diameter, pitch, coils):
    """Wire section area times centre-line length, plus the two half-ball ends (Pappus for a tube)."""
    a = wire_diameter / 2
    return math.pi * a * a * helix_length(coil_diameter, pitch, coils) + 4.0 / 3.0 * math.pi * a ** 3


def _check(coil_diameter, wire_diameter, pitch, coils):
    if wire_diameter >= pitch:
        fail("helical_spring", f"wire_diameter ({wire_diameter:g}) must be less than the pitch ({pitch:g}): "
                               "coils would touch")
    if wire_diameter >= coil_diameter / 2:
        fail("helical_spring", f"wire_diameter ({wire_diameter:g}) must be less than half the coil_diameter "
                               f"({coil_diameter / 2:g})")


def _spring(coil_diameter, wire_diameter, pitch, coils):
    return label(HelicalCoil(coil_diameter / 2, pitch, coils, wire_diameter / 2), "spring")


def _faces(coil_diameter, wire_diameter, pitch, coils):
    return {"coil_outside": round_face(coil_diameter / 2 + wire_diameter / 2),
            "coil_inside": round_face(coil_diameter / 2 - wire_diameter / 2)}


define("helical_spring", "Helical compression spring: round wire along a helix about z from z = 0.",
       (pos("coil_diameter", 20.0, "mean coil diameter D"),
        pos("wire_diameter", 2.0, "wire diameter d"),
        pos("pitch", 6.0, "axial pitch p"),
        count("coils", 5, "active coils n", minimum=1, maximum=50)),
       _spring, _check, _faces)


def helical_spring(**params):
    """A helical spring; see the family's parameters."""
    return instance("helical_spring", **params)
