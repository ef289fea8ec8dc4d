"""Shared pieces of the library families: parameters, named faces, standard sizes.

Every family of the library is registered with `implicit.families` (so
`instance(name, ...)`, `implicad families` and the JSON form know it) and
names its faces: `named_faces(part)` gives, for each face name, a solid whose
zero set carries that face (a plane or a cylinder in world coordinates), and
`face_names(part, points)` tells which named face each surface point lies on.
"""

from __future__ import annotations

import math

import numpy as np

from ..families import Family, FamilyInstance, Parameter, family, instance, register_family
from ..primitives import cylinder, halfspace
from ..solid import Solid

__all__ = ["pos", "count", "fail", "define", "named_faces", "face_names", "standard_instance",
           "plane", "round_face", "hexagon"]

#: Face builders by family name: ``builder(**params) -> {face name: carrier solid}``.
FACES: dict = {}
#: Standard-size tables by family name: ``{designation: {param: value}}``.
SIZES: dict = {}


def pos(name, default, description, unit="mm"):
    """A positive float parameter."""
    return Parameter(name, float, default, unit, 0.0, None, True, description)


def count(name, default, description, minimum=1, maximum=256):
    """An integer count parameter."""
    return Parameter(name, int, default, "count", minimum, maximum, False, description)


def fail(family_name, message):
    """Raise the ValueError of a geometry check, naming the family."""
    raise ValueError(f"{family_name}: {message}")


def define(name, description, parameters, build, check=None, faces=None, sizes=None):
    """Register a family, its face builder and its table of standard sizes."""
    register_family(Family(name, description, tuple(parameters), build, check))
    if faces is not None:
        FACES[name] = faces
    if sizes is not None:
        SIZES[name] = sizes


def plane(normal, point):
    """Carrier of a planar face: the half-space whose boundary holds it."""
    return halfspace(normal, point)


def round_face(radius, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), length=1e6):
    """Carrier of a cylindrical face (a long cylinder)."""
    return cylinder(radius, length, center=center, axis=axis)


def hexagon(across_flats):
    """Vertices (6, 2) of a regular hexagon with the given width across flats (flats parallel to x)."""
    circum = across_flats / math.sqrt(3.0)
    angles = np.radians(np.arange(6) * 60.0)
    return np.column_stack([circum * np.cos(angles), circum * np.sin(angles)])


def named_faces(part) -> dict:
    """The named faces of a library part: ``{name: carrier solid}``.

    Examples
    --------
    >>> from implicit.library import iso_nut
    >>> sorted(named_faces(iso_nut("M10")))[:3]
    ['bearing_face', 'bore', 'flat_1']
    """
    if not isinstance(part, FamilyInstance):
        raise TypeError(f"part: expected a family instance, got {type(part).__name__}")
    name = part.params["family"]
    if name not in FACES:
        raise ValueError(f"part: family {name!r} names no faces")
    return FACES[name](**part.params["params"])


def face_names(part, points, *, tolerance=None) -> np.ndarray:
    """Name of the face each surface point lies on (``""`` where none is within `tolerance`).

    Parameters
    ----------
    part : FamilyInstance
    points : (n, 3) float
    tolerance : float, optional
        Largest distance from a face's carrier; default 1e-3 of the part's size.
    """
    faces = named_faces(part)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    names = list(faces)
    dist = np.abs(np.stack([faces[n](p) for n in names], axis=0))
    best = np.argmin(dist, axis=0)
    lo, hi = part.bounds
    tol = 1e-3 * float(np.max(hi - lo)) if tolerance is None else float(tolerance)
    out = np.array(names, dtype=object)[best]
    out[dist[best, np.arange(p.shape[0])] > tol] = ""
    return out


def standard_instance(family_name: str, size: str, **overrides) -> Solid:
    """An instance of `family_name` at a standard `size`, with `overrides` on top."""
    from .tables import lookup
    fam = family(family_name)
    row = lookup(SIZES[family_name], size, f"{family_name} size")
    known = {p.name for p in fam.parameters}
    row = {k: v for k, v in row.items() if k in known}
    row.update(overrides)
    return instance(family_name, **row)
