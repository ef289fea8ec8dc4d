"""The thinnest wall of a solid, and a voxel size that resolves it.

A lattice resolves a wall only with a few voxels through it: a plate one
unit thick and a hundred wide meshed at a hundred voxels across loses its
material between two sample planes.  `thinnest_wall` reads the CSG tree (its
primitives know their sizes: a box its sides, a cylinder its radius and
height, a shell its thickness, a transform scales what it holds) and, when
asked, adds the walls measured on the field itself (`spatial.cells.walls`:
rays from the surface inward to the opposite face) for what the tree cannot
tell -- a wall a difference, an intersection, an offset or a blend thinned.
`default_voxel_size` takes the voxel from the part's size and its thinnest
wall, capped so that the boundary stays within a memory budget.

Examples
--------
>>> from implicit import box
>>> t, what = thinnest_wall(box((100, 100, 1)))
>>> t, what
(1.0, 'box of sides [100.0, 100.0, 1.0]')
>>> round(default_voxel_size(box((100, 100, 1))), 2)   # four voxels through the plate
0.24
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["thinnest_wall", "sampled_thickness", "default_voxel_size", "min_feature_size", "DEFAULT_RESOLUTION", "WALL_VOXELS",
           "MAX_SURFACE_VOXELS"]

#: Voxels across the longest side of the part by default.
DEFAULT_RESOLUTION = 128
#: Voxels through the thinnest wall by default.
WALL_VOXELS = 4
#: The default voxel keeps the boundary below about this many voxels (the area of the bounds'
#: faces over h^2): a bound on the memory of a default mesh (about 1 GB).
MAX_SURFACE_VOXELS = 2e7


def thinnest_wall(solid, *, sample=False, bounds=None):
    """Thickness of the solid's thinnest wall as its CSG tree tells it: ``(t, feature)``.

    Parameters
    ----------
    solid : Solid
    sample : bool
        Also measure the walls on the field (`spatial.cells.walls.thin_wall`,
        about 30,000 evaluations on a 32**3 grid and rays from its surface
        samples; kept per solid) and keep the thinner.
    bounds : (lo, hi), optional
        Region of the sampled estimate (default the solid's bounds).

    Returns
    -------
    t : float
        Smallest extent of a primitive (scaled by the transforms above it),
        or ``inf`` when nothing in the tree has a size.
    feature : str
        What has that extent (``'box of sides [100.0, 100.0, 1.0]'``).
    """
    t, what = _walk(solid)
    if sample:
        from .walls import thin_wall

        w = thin_wall(solid, bounds=bounds)
        if w is not None and w.thickness < t:
            t, what = w.thickness, w.describe()
        # the ridge estimate too (it reads a wall a little under its thickness: a default voxel
        # a little finer than four through it, as before the walls were measured)
        r = _ridge_thickness(solid, bounds=bounds)
        if r is not None and r < t:
            t, what = r, "a sampled wall"
    return float(t), what


def _walk(node):
    kind = getattr(node, "kind", "")
    p = getattr(node, "_params", {})
    kids = getattr(node, "_children", ()) or ()
    own = _own(kind, p)
    if own is not None:
        return own
    if kind == "affine":
        t, what = _walk(kids[0])
        s = float(np.linalg.svd(np.asarray(p["matrix"], dtype=float), compute_uv=False).min())
        return t * s, what if s == 1 else f"{what}, scaled"
    if kind == "offset":
        t, what = _walk(kids[0])
        t2 = t + 2 * float(p["distance"])
        # an inward offset of a field that is not a distance (a shell of a shell, a scaled or blended
        # field) can leave a wall the arithmetic calls empty: the tree then tells nothing
        return (t2, f"{what}, offset") if t2 > 0 else (math.inf, "")
    if kind == "shell":
        t, what = _walk(kids[0])
        w = float(p["thickness"])
        return (w, f"shell of thickness {w:g}") if w <= t else (t, what)
    best = (math.inf, "")
    for kid in kids:
        cand = _walk(kid)
        if cand[0] < best[0]:
            best = cand
    return best


def _own(kind, p):
    """(extent, name) of a primitive, or None for a node that holds others."""
    def f(key):
        return float(p[key])

    if kind == "sphere":
        return 2 * f("radius"), f"sphere of radius {f('radius'):g}"
    if kind == "box":
        size = [float(v) for v in p["size"]]
        return min(size), f"box of sides {size}"
    if kind in ("cylinder", "cone"):
        t = min(2 * f("radius"), f("height"))
        return t, f"{kind} of radius {f('radius'):g} and height {f('height'):g}"
    if kind == "torus":
        return 2 * f("minor_radius"), f"torus of minor radius {f('minor_radius'):g}"
    if kind == "ellipsoid":
        return 2 * min(float(v) for v in p["radii"]), f"ellipsoid of radii {list(p['radii'])}"
    if kind == "capsule":
        return 2 * f("radius"), f"capsule of radius {f('radius'):g}"
    if kind == "wedge":
        return min(float(v) for v in p["size"]), f"wedge of sides {list(p['size'])}"
    if kind == "pyramid":
        base = np.asarray(p["base"], dtype=float)
        return min(f("height"), float((base.max(0) - base.min(0)).min())), "pyramid"
    if kind in ("extrude", "revolve"):
        prof = _profile_extent(p.get("profile", {}))
        t = min(prof, f("height")) if kind == "extrude" else prof
        return t, f"{kind} of a {p.get('profile', {}).get('kind', 'profile')} profile"
    return None


def _profile_extent(prof):
    kind = prof.get("kind")
    if kind == "circle":
        return 2 * float(prof["radius"])
    if kind == "rectangle":
        return min(float(v) for v in prof["size"])
    if kind == "polygon":
        v = np.asarray(prof["vertices"], dtype=float)
        return float((v.max(0) - v.min(0)).min())
    return math.inf


def sampled_thickness(solid, *, bounds=None, n=40):
    """The thinnest wall measured on the field (`spatial.cells.walls.thin_wall`), else twice the depth
    below the surface on the ridges of the field sampled at ``n**3`` points.

    A sample inside the solid where the depth ``-f`` stops growing (its
    gradient well below the typical slope) lies near the medial surface; twice
    its depth is the local wall thickness.  Returns the 10th percentile over those
    samples (the ridges run into the corners, where the depth goes to 0), or
    None when fewer than 8 samples lie inside (walls thinner than the sampling).
    """
    from .walls import thin_wall

    w = thin_wall(solid, bounds=bounds)
    if w is not None:
        return w.thickness
    return _ridge_thickness(solid, bounds=bounds, n=n)


def _ridge_thickness(solid, *, bounds=None, n=40):
    lo, hi = (np.asarray(b, dtype=np.float64) for b in (solid.bounds if bounds is None else bounds))
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi > lo)):
        return None
    axes = [np.linspace(lo[i], hi[i], n) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    depth = -np.asarray(solid(grid), dtype=np.float64).reshape(n, n, n)
    inside = depth > 0
    if np.count_nonzero(inside) < 8:
        return None
    # the medial surface is where the depth stops growing: its gradient (1 elsewhere, for a distance)
    # falls; measured against the typical slope, so a field that is not a distance works too
    slope = np.sqrt(sum(g * g for g in np.gradient(depth, *[a[1] - a[0] for a in axes])))
    typical = float(np.median(slope[inside]))
    ridge = inside & (slope < 0.5 * typical)
    if not ridge.any():
        return None
    return float(2 * np.percentile(depth[ridge], 10))


def default_voxel_size(solid, bounds=None):
    """The voxel size used when neither a voxel size nor a resolution is given.

    The smaller of the longest side over `DEFAULT_RESOLUTION` and the
    thinnest wall (`thinnest_wall`, sampled estimate included) over
    `WALL_VOXELS`, but no smaller than the size that keeps the boundary
    (the faces of the bounds, over ``h**2``) within `MAX_SURFACE_VOXELS`.

    Parameters
    ----------
    solid : Solid
    bounds : (lo, hi), optional
        Region (default the solid's bounds; needed for an unbounded solid).

    Returns
    -------
    float
    """
    lo, hi = (np.asarray(b, dtype=np.float64) for b in (solid.bounds if bounds is None else bounds))
    ext = hi - lo
    if not (np.all(np.isfinite(ext)) and np.all(ext >= 0) and ext.max() > 0):
        raise ValueError("bounds: a default voxel size needs finite bounds of positive extent "
                         f"(got {lo.tolist()} to {hi.tolist()}); pass bounds=, voxel_size= or resolution=")
    h = float(ext.max()) / DEFAULT_RESOLUTION
    t, _ = thinnest_wall(solid, sample=True, bounds=(lo, hi))
    if np.isfinite(t) and t > 0:
        h = min(h, t / WALL_VOXELS)
    area = 2.0 * float(ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0])
    return max(h, math.sqrt(area / MAX_SURFACE_VOXELS))


def min_feature_size(solid) -> float:
    """Thickness of the thinnest wall of `solid`: the tree's or the one measured on its field, else
    the sampled estimate.

    Parameters
    ----------
    solid : Solid
        A bounded solid.

    Returns
    -------
    float
        A length > 0: the thinner of `thinnest_wall` of the tree (its smallest
        primitive size, transforms and offsets applied) and the thinnest wall
        measured on the field (`spatial.cells.walls.thin_wall`: a wall a
        Boolean, an offset or a blend thinned, which the tree cannot tell),
        or `sampled_thickness` when neither tells anything; never more than
        the smallest side of the solid's bounds.

    Examples
    --------
    >>> from implicit import box, sphere
    >>> min_feature_size(box((100.0, 100.0, 1.0)) | sphere(3.0))
    1.0
    >>> round(min_feature_size(box(10) - box(10, center=(0.05, 0, 0))), 4)   # a wall the tree calls 10
    0.05
    """
    from implicit import Solid

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if not solid.is_bounded or solid.is_empty_bounds:
        raise ValueError("solid: expected a bounded solid with non-empty bounds")
    from .walls import thin_wall

    t = float(thinnest_wall(solid)[0])
    w = thin_wall(solid)
    if w is not None and w.thickness > 0:
        t = min(t, float(w.thickness))
    if not (np.isfinite(t) and t > 0):
        t = float(sampled_thickness(solid))
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    side = float(np.min(hi - lo))
    return min(t, side) if side > 0 else t
