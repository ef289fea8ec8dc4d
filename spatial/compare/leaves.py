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
        v = np.asarray(P["profile"]["vertices"], float)
        d = np.roll(v, -1, axis=0) - v
        cross = v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]
        if cross.sum() < 0:  # make it counter-clockwise
            v, d = v[::-1], -d[::-1]
            d = np.roll(v, -1, axis=0) - v
        turn = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
        if np.any(turn < -1e-12):
            return None  # not convex
        n2 = np.column_stack([d[:, 1], -d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
        n = np.vstack([np.column_stack([n2, np.zeros(len(v))]), [[0, 0, 1.0], [0, 0, -1.0]]])
        off = np.concatenate([np.einsum("ij,ij->i", n2, v), [P["height"] / 2, P["height"] / 2]])
        R = rotation_to_axis(P["axis"])
        c = np.asarray(P["center"], float)
        nw = n @ R.T
        return nw, off + nw @ c
    return None


def leaf_planes(node, matrix=np.eye(3), offset=np.zeros(3)):
    """World planes of a polyhedral leaf under ``p -> matrix p + offset``, or None."""
    local = _local_planes(node)
    if local is None:
        return None
    n, d = local
    inv = np.linalg.inv(matrix)
    # n . q <= d with q = inv (p - t)  ->  (inv^T n) . p <= d + (inv^T n) . t
    nw = n @ inv
    off = d + nw @ offset
    scale = np.linalg.norm(nw, axis=1)
    return nw / scale[:, None], off / scale
