"""The surface size of a tetrahedral mesh: the target size, smaller where the part is narrower.

A surface of edge length `size` cannot follow a gap narrower than `size`
(the space between two gear teeth): it bridges the gap or folds onto itself.
The size asked is a target, as in gmsh: a part with narrower places gets a
finer surface, while the volume inside keeps elements of the size asked
(TetGen grades from the surface).  The narrowness is measured on the
solid's own field at points of its surface: a ray leaves each point along
the outward normal (sphere tracing: steps of the field's value, which bounds
the distance to the surface) and the distance at which it meets the solid
again is the gap there; a ray along the inward normal meets the far side of
a thin wall.  The surface size is `GAP_FRACTION` of the narrowest width,
never above `size` nor below `SMALLEST_FRACTION` of it.

Triangles graded over the surface (small in the gaps only, weighted
clustering) would be cheaper; pyacvd's weighted clusters come out
non-manifold on the gear, so the surface is uniform at the size found.
"""

from __future__ import annotations

import numpy as np

__all__ = ["narrow_widths", "surface_size", "curvature_size", "GAP_FRACTION", "SMALLEST_FRACTION", "CURVED_FRACTION"]

#: Element edge over the width of the gap or wall it must follow (the 20-tooth gear of
#: examples/gear.py, gap 2.22, meshes free of self-intersections at 2.0: 0.9 of it).
GAP_FRACTION = 0.8
#: Smallest local size, as a fraction of the size asked (the acute corners of a slot would
#: otherwise ask for sizes going to zero).
SMALLEST_FRACTION = 0.2
#: Sphere-tracing steps of each ray, and the shortest step as a fraction of the size.
RAY_STEPS = 40
_MIN_STEP = 0.02


def narrow_widths(solid, points, size, normals=None):
    """Widths ``(n,)`` of the gap outside and the wall inside at surface `points` of `solid`
    (the smaller of the two, inf where both are wider than ``size / GAP_FRACTION``).

    Parameters
    ----------
    solid : Solid
    points : (n, 3) array_like
        Points on (or next to) the surface.
    size : float
        The target size: widths beyond ``size / GAP_FRACTION`` are not looked for.
    normals : (n, 3) array_like, optional
        Outward unit normals (default: the solid's gradient).

    Examples
    --------
    >>> from implicit import box
    >>> slot = box((10.0, 4.0, 4.0)) - box((1.0, 6.0, 6.0))       # a cut 1 wide across a bar
    >>> narrow_widths(slot, [[0.5, 0.0, 0.0], [5.0, 0.0, 0.0]], 2.0).round(3).tolist()
    [1.0, inf]
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if normals is None:
        g = solid.gradient(p)
    else:
        g = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    nrm = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    reach = size / GAP_FRACTION
    out = np.full(p.shape[0], np.inf)
    for side in (1.0, -1.0):
        out = np.minimum(out, _trace(solid, p, side * nrm, side, reach, size))
    return out


def _trace(solid, p, d, side, reach, size):
    """Distance along `d` from `p` to the next crossing of the surface (inf beyond `reach`)."""
    eps = 1e-4 * size
    t = np.full(p.shape[0], 2.0 * _MIN_STEP * size)
    hit = np.full(p.shape[0], np.inf)
    live = np.ones(p.shape[0], dtype=bool)
    for _ in range(RAY_STEPS):
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        f = side * solid(p[idx] + t[idx, None] * d[idx])      # > 0 on the ray's own side
        crossed = f < eps
        hit[idx[crossed]] = t[idx[crossed]] + np.minimum(f[crossed], 0.0)
        t[idx] += np.maximum(f, _MIN_STEP * size)
        live[idx[crossed]] = False
        live &= t < reach
    return hit


def surface_size(solid, size, voxel=None):
    """The edge length of a surface of `solid` that follows its narrowest gap and thinnest wall:
    `size`, or ``GAP_FRACTION`` of the narrowest width `narrow_widths` finds under it (at least
    ``SMALLEST_FRACTION * size``), measured at the vertices of a mesh of voxel `voxel`
    (default ``size / 4``, the surface's own).

    Examples
    --------
    >>> from implicit import box
    >>> slot = box((10.0, 4.0, 4.0)) - box((1.0, 6.0, 6.0))       # a cut 1 wide across a bar
    >>> round(surface_size(slot, 2.0), 3), surface_size(box(4.0), 2.0)
    (0.8, 2.0)
    """
    from ..meshing.boundary import mesh

    m = mesh(solid, voxel_size=voxel or size / 4.0, progress=False, features=False)
    if m.n_points == 0:
        return float(size)
    w = narrow_widths(solid, np.asarray(m.points, dtype=np.float64), size)
    return float(np.clip(GAP_FRACTION * w.min(initial=np.inf), SMALLEST_FRACTION * size, size))


#: Largest surface edge over the smallest radius of a curved face, for 10-node elements: an edge
#: spanning much of a hole's rim folds the element capping the rim when its mid node goes onto
#: the arc (a plate with two holes of radius 3 at size 3: 13 of 1054 boundary nodes left off the
#: surface with edges of 3, none with edges of 1.5).
CURVED_FRACTION = 0.5


def curvature_size(solid, size):
    """The surface edge for curved (10-node) elements: `size`, or ``CURVED_FRACTION`` of the
    smallest radius of a sphere, cylinder, capsule, torus or cone of the tree (scaled by the
    transforms above it), at least ``SMALLEST_FRACTION * size``.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> curvature_size(box((40, 20, 4)) - cylinder(3.0, 10.0), 3.0), curvature_size(box(2.0), 3.0)
    (1.5, 3.0)
    """
    radii = []
    stack = [(solid, 1.0)]
    while stack:
        node, scale = stack.pop()
        kind = node.kind
        if kind == "affine":
            scale *= float(node._factor)
        if kind in ("sphere", "cylinder", "capsule", "torus"):
            radii.append(scale * float(node._r))
        elif kind == "cone":
            radii.extend(scale * r for r in (float(node._r1), float(node._r2)) if r > 0)
        stack.extend((c, scale) for c in node.children)
    if not radii:
        return float(size)
    return float(np.clip(CURVED_FRACTION * min(radii), SMALLEST_FRACTION * size, size))
