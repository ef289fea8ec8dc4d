"""The CSG leaves of a solid in world coordinates, and the planes of polyhedral leaves.

A *leaf* is a node the comparison does not look inside: a primitive, a sweep,
a grid, ...  Booleans, complements, smooth Booleans, family instances and
affine maps are looked through; every leaf comes back wrapped in the affine
maps above it, so its field can be evaluated at world points.
"""

from __future__ import annotations

import numpy as np

from implicit.transforms import affine

__all__ = ["THROUGH", "world_leaves", "leaf_planes", "leaf_records"]

#: Node kinds the walk looks through.
THROUGH = {"union", "intersection", "difference", "complement", "smooth_union", "smooth_intersection",
           "smooth_difference", "family"}


def world_leaves(solid) -> list:
    """``[(label, world_solid), ...]`` for every leaf of `solid`, depth first.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> [label for label, _ in world_leaves(box(2) - cylinder(0.5, 3).translate((0.2, 0, 0)))]
    ['box#0', 'cylinder#1']
    """
    out = []
    for node, matrix, offset in leaf_records(solid):
        plain = np.allclose(matrix, np.eye(3)) and not np.any(offset)
        out.append((f"{node.kind}#{len(out)}", node if plain else affine(node, matrix, offset)))
    return out


def leaf_records(solid):
    """``[(leaf node, matrix, offset), ...]``: the leaves and the affine map above each."""
    recs = []

    def walk(node, matrix, offset):
        if node.kind == "affine":
            a = np.asarray(node.params["matrix"], dtype=np.float64)
            t = np.asarray(node.params["offset"], dtype=np.float64)
            walk(node.children[0], matrix @ a, matrix @ t + offset)
        elif node.kind in THROUGH:
            for child in node.children:
                walk(child, matrix, offset)
        else:
            recs.append((node, matrix, offset))

    walk(solid, np.eye(3), np.zeros(3))
    return recs


def _local_planes(node):
    """Planes ``(normals (k, 3), offsets (k,))`` with ``n . p <= d`` inside, or None."""
    kind, P = node.kind, node.params
    if kind == "box":
        c, h = np.asarray(P["center"], float), np.asarray(P["size"], float) / 2
        n = np.vstack([np.eye(3), -np.eye(3)])
        return n, np.concatenate([c + h, -(c - h)])
    if kind == "halfspace":
        n = np.asarray(P["normal"], float)
        n = n / np.linalg.norm(n)
        return n[None], np.array([n @ np.asarray(P["point"], float)])
    if kind == "convex_polyhedron" and "normals" in P:
        n = np.asarray(P["normals"], float)
        n = n / np.linalg.norm(n, axis=1, keepdims=True)
        pts = np.asarray(P["points"], float)
        return n, np.einsum("ij,ij->i", n, pts)
    if kind == "extrude" and P["profile"].get("kind") == "polygon":
        from implicit.sweeps import rotation_to_axis
        R = rotation_to_axis(P["axis"])
        c = np.asarray(P["center"], float)
        hh = P["height"] / 2
        out = []
        for n2, d2 in trapezoids(np.asarray(P["profile"]["vertices"], float)):
            n = np.vstack([np.column_stack([n2, np.zeros(len(n2))]), [[0, 0, 1.0], [0, 0, -1.0]]])
            d = np.concatenate([d2, [hh, hh]])
            nw = n @ R.T
            out.append((nw, d + nw @ c))
        return out
    return None


def trapezoids(vertices) -> list:
    """Convex pieces of a simple polygon: its slabs between vertex heights cut into trapezoids.

    Returns ``[(normals (4, 2), offsets (4,)), ...]`` with ``n . p <= d`` inside.

    Examples
    --------
    >>> len(trapezoids(np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]], float)))   # an L: two
    2
    """
    v = np.asarray(vertices, dtype=np.float64)
    a, b = v, np.roll(v, -1, axis=0)
    levels = np.unique(v[:, 1])
    pieces = []
    for y0, y1 in zip(levels[:-1], levels[1:]):
        ym = 0.5 * (y0 + y1)
        span = (np.minimum(a[:, 1], b[:, 1]) < ym) & (np.maximum(a[:, 1], b[:, 1]) > ym)
        ea, eb = a[span], b[span]

        def x_at(y):
            return ea[:, 0] + (y - ea[:, 1]) * (eb[:, 0] - ea[:, 0]) / (eb[:, 1] - ea[:, 1])

        order = np.argsort(x_at(ym))
        xs0, xs1 = x_at(y0)[order], x_at(y1)[order]
        for k in range(0, len(order) - 1, 2):  # even-odd: material between crossings 2k and 2k+1
            left = (np.array([xs0[k], y0]), np.array([xs1[k], y1]))
            right = (np.array([xs0[k + 1], y0]), np.array([xs1[k + 1], y1]))
            nl = np.array([-(left[1][1] - left[0][1]), left[1][0] - left[0][0]])   # outward: to the left
            nr = np.array([right[1][1] - right[0][1], -(right[1][0] - right[0][0])])
            nl, nr = nl / np.linalg.norm(nl), nr / np.linalg.norm(nr)
            n = np.array([[0.0, -1.0], [0.0, 1.0], nl, nr])
            d = np.array([-y0, y1, nl @ left[0], nr @ right[0]])
            pieces.append((n, d))
    return pieces


def leaf_planes(node, matrix=np.eye(3), offset=np.zeros(3)):
    """Convex pieces ``[(normals, offsets), ...]`` of a polyhedral leaf under ``p -> matrix p + offset``, or None."""
    local = _local_planes(node)
    if local is None:
        return None
    inv = np.linalg.inv(matrix)
    out = []
    for n, d in (local if isinstance(local, list) else [local]):
        # n . q <= d with q = inv (p - t)  ->  (inv^T n) . p <= d + (inv^T n) . t
        nw = n @ inv
        off = d + nw @ offset
        scale = np.linalg.norm(nw, axis=1)
        out.append((nw / scale[:, None], off / scale))
    return out
