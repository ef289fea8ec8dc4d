"""Pipework: EN 1092-1 PN 16 plate flanges, equal tees and bends.

The flange lies on z = 0 with its axis along z; the tee's run is along x and
its branch along +z from the run's axis; the bend turns about the z axis in
the xy plane from +x towards +y.

Examples
--------
>>> from implicit.library import pipe_flange
>>> pipe_flange("DN50").params["params"]["bolt_holes"]
4
"""

from __future__ import annotations

import math

import numpy as np

from ..csg import difference, union
from ..families import Parameter, instance, label
from ..primitives import cylinder
from ..sweeps import circle, revolve
from .common import count, define, fail, plane, pos, round_face, standard_instance
from .tables import EN1092_PN16

__all__ = ["pipe_flange", "pipe_tee", "pipe_bend", "tee_volume", "bend_volume"]


# EN 1092-1 flange ---------------------------------------------------------------

def _flange_check(flange_diameter, bolt_circle, hole_diameter, bolt_holes, thickness, bore):
    name = "en1092_flange"
    if bore >= flange_diameter:
        fail(name, f"bore ({bore:g}) must be less than flange_diameter ({flange_diameter:g})")
    if bolt_circle / 2 - hole_diameter / 2 <= bore / 2:
        fail(name, f"bolt holes (diameter {hole_diameter:g} on bolt_circle {bolt_circle:g}) cut into the bore")
    if bolt_circle / 2 + hole_diameter / 2 >= flange_diameter / 2:
        fail(name, f"bolt holes (diameter {hole_diameter:g} on bolt_circle {bolt_circle:g}) break out of the rim")
    if bolt_circle * math.sin(math.pi / bolt_holes) <= hole_diameter:
        fail(name, f"{bolt_holes} holes of diameter {hole_diameter:g} overlap on bolt_circle {bolt_circle:g}")


def _hole_centres(bolt_circle, n):
    a = 2 * np.pi * (np.arange(n) + 0.5) / n  # holes straddle the axes (EN 1092-1 drawing)
    return np.column_stack([bolt_circle / 2 * np.cos(a), bolt_circle / 2 * np.sin(a)])


def _flange(flange_diameter, bolt_circle, hole_diameter, bolt_holes, thickness, bore):
    c = (0.0, 0.0, thickness / 2)
    disc = label(cylinder(flange_diameter / 2, thickness, center=c), "flange", {"wall": "rim"})
    tools = [label(cylinder(bore / 2, 3 * thickness, center=c), "flange", {"wall": "bore"})]
    tools += [label(cylinder(hole_diameter / 2, 3 * thickness, center=(x, y, thickness / 2)), f"hole_{i + 1}")
              for i, (x, y) in enumerate(_hole_centres(bolt_circle, bolt_holes))]
    return difference(disc, *tools)


def _flange_faces(flange_diameter, bolt_circle, hole_diameter, bolt_holes, thickness, bore):
    faces = {"raised_face": plane((0, 0, 1), (0, 0, thickness)), "back": plane((0, 0, -1), (0, 0, 0)),
             "rim": round_face(flange_diameter / 2), "bore": round_face(bore / 2)}
    for i, (x, y) in enumerate(_hole_centres(bolt_circle, bolt_holes)):
        faces[f"bolt_hole_{i + 1}"] = round_face(hole_diameter / 2, center=(x, y, 0.0))
    return faces


define("en1092_flange", "EN 1092-1 PN 16 plate flange (type 01) on z = 0, axis z.",
       (pos("flange_diameter", 165.0, "outside diameter D"),
        pos("bolt_circle", 125.0, "bolt circle diameter K"),
        pos("hole_diameter", 18.0, "bolt hole diameter L"),
        count("bolt_holes", 4, "number of bolt holes", minimum=3, maximum=64),
        pos("thickness", 20.0, "flange thickness C"),
        pos("bore", 61.1, "bore B1")),
       _flange, _flange_check, _flange_faces, EN1092_PN16)


def pipe_flange(size: str = "DN50", **params):
    """An EN 1092-1 PN 16 flange of nominal size `size` (``"DN15"`` ... ``"DN200"``)."""
    return standard_instance("en1092_flange", size, **params)


# equal tee -----------------------------------------------------------------------

def tee_volume(outer_diameter, wall, run_length, branch_length):
    """Closed-form volume of `pipe_tee`: pi (R^2 - r^2)(L_run + L_branch) - 8 (R^3 - r^3) / 3.

    The branch's part inside the run is half of a Steinmetz bicylinder (16 R^3 / 3).
    """
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    return math.pi * (R * R - r * r) * (run_length + branch_length) - 8.0 * (R ** 3 - r ** 3) / 3.0


def _tee_check(outer_diameter, wall, run_length, branch_length):
    if wall >= outer_diameter / 2:
        fail("pipe_tee", f"wall ({wall:g}) must be less than half the outer_diameter ({outer_diameter / 2:g})")
    if run_length <= outer_diameter:
        fail("pipe_tee", f"run_length ({run_length:g}) must exceed outer_diameter ({outer_diameter:g})")
    if branch_length <= outer_diameter / 2:
        fail("pipe_tee", f"branch_length ({branch_length:g}) must exceed the outer radius ({outer_diameter / 2:g})")


def _tee(outer_diameter, wall, run_length, branch_length):
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    x = (1.0, 0.0, 0.0)
    outer = union(label(cylinder(R, run_length, axis=x), "run", {"wall": "outside", "top": "end_2", "bottom": "end_1"}),
                  label(cylinder(R, branch_length, center=(0.0, 0.0, branch_length / 2)), "branch",
                        {"wall": "outside", "top": "end", "bottom": "root"}))
    # bores end exactly at the faces so the closed form holds; the run bore covers the branch's root
    inner = union(label(cylinder(r, run_length, axis=x), "run", {"wall": "bore", "top": "end_2", "bottom": "end_1"}),
                  label(cylinder(r, branch_length, center=(0.0, 0.0, branch_length / 2)), "branch",
                        {"wall": "bore", "top": "end", "bottom": "root"}))
    return difference(outer, inner)


def _tee_faces(outer_diameter, wall, run_length, branch_length):
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    x = (1.0, 0.0, 0.0)
    return {"run_outside": round_face(R, axis=x), "run_bore": round_face(r, axis=x),
            "branch_outside": round_face(R), "branch_bore": round_face(r),
            "run_end_1": plane((-1, 0, 0), (-run_length / 2, 0, 0)), "run_end_2": plane((1, 0, 0), (run_length / 2, 0, 0)),
            "branch_end": plane((0, 0, 1), (0, 0, branch_length))}


define("pipe_tee", "Equal pipe tee: run along x (centred), branch along +z.",
       (pos("outer_diameter", 60.3, "pipe outside diameter"),
        pos("wall", 3.6, "wall thickness"),
        pos("run_length", 150.0, "run length"),
        pos("branch_length", 75.0, "branch length from the run's axis")),
       _tee, _tee_check, _tee_faces)


def pipe_tee(**params):
    """An equal tee; see the family's parameters."""
    return instance("pipe_tee", **params)


# bend ------------------------------------------------------------------------------

def bend_volume(outer_diameter, wall, bend_radius, angle):
    """Pappus: pi (R^2 - r^2) * bend_radius * angle (radians)."""
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    return math.pi * (R * R - r * r) * bend_radius * math.radians(angle)


def _bend_check(outer_diameter, wall, bend_radius, angle):
    if wall >= outer_diameter / 2:
        fail("pipe_bend", f"wall ({wall:g}) must be less than half the outer_diameter ({outer_diameter / 2:g})")
    if bend_radius <= outer_diameter / 2:
        fail("pipe_bend", f"bend_radius ({bend_radius:g}) must exceed the outer radius ({outer_diameter / 2:g})")


def _bend(outer_diameter, wall, bend_radius, angle):
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    ring = circle(R, center=(bend_radius, 0.0)) - circle(r, center=(bend_radius, 0.0))
    return label(revolve(ring, angle), "bend")


def _bend_faces(outer_diameter, wall, bend_radius, angle):
    from ..primitives import torus
    R, r = outer_diameter / 2, outer_diameter / 2 - wall
    a = math.radians(angle)
    return {"outside": torus(bend_radius, R), "bore": torus(bend_radius, r),
            "end_1": plane((0, -1, 0), (0, 0, 0)), "end_2": plane((-math.sin(a), math.cos(a), 0), (0, 0, 0))}


define("pipe_bend", "Pipe bend (elbow) about the z axis, from +x towards +y.",
       (pos("outer_diameter", 60.3, "pipe outside diameter"),
        pos("wall", 3.6, "wall thickness"),
        pos("bend_radius", 76.2, "centre-line bend radius (1.5 D for a long-radius elbow)"),
        Parameter("angle", float, 90.0, "deg", 0.0, 360.0, True, "bend angle")),
       _bend, _bend_check, _bend_faces)


def pipe_bend(**params):
    """A pipe bend (elbow); see the family's parameters."""
    return instance("pipe_bend", **params)
