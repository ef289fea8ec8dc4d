"""The thinnest feature of a solid, from its CSG tree or, failing that, from samples.

A lattice whose cells are thicker than a wall can miss the wall entirely (a
plate 1 thick has no lattice node inside it at cells of 1.6), and every
measure built on the mesh then goes wrong.  `min_feature_size` estimates the
thinnest wall a solid can have before anything is sampled: each primitive
knows its sizes (a box its shortest side, a sphere its diameter, a shell its
thickness), transforms scale them by their smallest stretch, offsets grow or
shrink them and Booleans keep the smallest of their operands.  A leaf the
walk does not know falls back on its bounds, and a tree that gives nothing
finite on samples of the field (twice the deepest inside value: the
thickness of its thickest wall, a sane upper value).

The estimate is a property of the tree, not a proof: a difference can leave
a wall thinner than either operand (a hole drilled near a face), which no
walk of the tree sees.
"""

from __future__ import annotations

import numpy as np

__all__ = ["min_feature_size"]

#: Samples per axis of the fallback estimate.
SAMPLES = 48


def _extent_min(solid) -> float:
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    d = hi - lo
    d = d[np.isfinite(d) & (d > 0)]
    return float(d.min()) if d.size else np.inf


def _profile_min(profile) -> float:
    if not isinstance(profile, dict):
        return np.inf
    kind = profile.get("kind")
    if kind == "rectangle":
        return float(min(profile["size"]))
    if kind == "circle":
        return 2.0 * float(profile["radius"])
    inner = [_profile_min(p) for p in profile.get("children", ()) if isinstance(p, dict)]
    return min(inner) if inner else np.inf


def _walk(solid) -> float:
    kind = solid.kind
    p = solid.params
    kids = solid.children
    if kind == "halfspace":
        return np.inf
    if kind == "box":
        return float(min(p["size"]))
    if kind in ("sphere", "capsule"):
        return 2.0 * float(p["radius"])
    if kind == "cylinder":
        return min(2.0 * float(p["radius"]), float(p["height"]))
    if kind == "cone":
        return min(2.0 * max(float(p["radius"]), float(p.get("top_radius", 0.0))), float(p["height"]))
    if kind == "torus":
        return 2.0 * float(p["minor_radius"])
    if kind == "ellipsoid":
        return 2.0 * float(min(p["radii"]))
    if kind == "shell":
        return min(float(p["thickness"]), _walk(kids[0]))
    if kind == "offset":
        child = _walk(kids[0])
        return max(child + 2.0 * float(p["distance"]), 0.0) if np.isfinite(child) else child
    if kind == "affine":
        stretch = float(np.linalg.svd(np.asarray(p["matrix"], dtype=np.float64), compute_uv=False).min())
        return _walk(kids[0]) * stretch
    if kind == "extrude":
        return min(float(p["height"]), _profile_min(p.get("profile")))
    if kind == "revolve":
        return _profile_min(p.get("profile"))
    if kids:
        return min((_walk(c) for c in kids), default=np.inf)
    return _extent_min(solid)


def _sampled(solid) -> float:
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    axes = [np.linspace(lo[i], hi[i], SAMPLES) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    deepest = float(-np.min(solid(grid)))
    step = float(np.max(hi - lo)) / (SAMPLES - 1)
    # no sample inside: the solid is thinner than the sampling step
    return 2.0 * deepest if deepest > 0 else step


def min_feature_size(solid) -> float:
    """Thickness of the thinnest wall of `solid`, estimated from its tree.

    Parameters
    ----------
    solid : Solid
        A bounded solid.

    Returns
    -------
    float
        A length > 0 (the tree's smallest primitive size, transforms and
        offsets applied; the sampled fallback when the tree tells nothing).

    Examples
    --------
    >>> from implicit import box, sphere
    >>> min_feature_size(box((100.0, 100.0, 1.0)) | sphere(3.0))
    1.0
    """
    from implicit import Solid

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if not solid.is_bounded or solid.is_empty_bounds:
        raise ValueError("solid: expected a bounded solid with non-empty bounds")
    t = _walk(solid)
    if not (np.isfinite(t) and t > 0):
        t = _sampled(solid)
    return float(min(t, max(_extent_min(solid), 0.0) or np.inf))
