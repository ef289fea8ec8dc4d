"""Values and exact gradients of the facets of one primitive leaf.

The facets of a leaf (`implicit.facets`) are planes, spheres, cylinder walls,
cones, tori...: closed forms whose gradients are closed forms too.  Computing
them in one pass replaces three (forward) or six (central) further
evaluations of every facet of the tree by finite differences, which is most
of the cost of exact normals on a mesh.  Leaves without a closed form here
(smooth blends, sweeps, sampled fields...) fall back to forward differences
of their own field.
"""

from __future__ import annotations

import numpy as np

from .primitives import capped_cone_parts, capsule_kernels

__all__ = ["leaf_facets_with_gradients"]


def _safe_div(a, b):
    return np.divide(a, b, out=np.zeros_like(a), where=b > 0)


def _axial(node, p):
    """Local coordinates ``q`` in the leaf's frame (axis = local z)."""
    return (p - node._c) @ node._frame.T


def _to_world(node, gq):
    """A gradient in the leaf's frame, back in the leaf's coordinates (the frame is orthonormal)."""
    return gq @ node._frame


def _forward(facets, node, p, v, step):
    """Forward differences ``(k, n, 3)`` of the leaf's facet values ``v`` (``facets(node, p)``): the fallback."""
    g = np.empty(v.shape + (3,))
    for j in range(3):
        q = p.copy()
        q[:, j] += step
        g[:, :, j] = (np.asarray(facets(node, q)[1], dtype=np.float64) - v) / step
    return g


def _cone(node, p):
    """Quilez's capped cone and its gradient: the unit vector from the nearest boundary point."""
    loc = _axial(node, p)
    qx = np.hypot(loc[:, 0], loc[:, 1])
    qy = loc[:, 2] - node._hh
    cax, cay, cbx, cby, sign = capped_cone_parts(qx, qy, node._hh, node._r1, node._r2)
    da, db = cax * cax + cay * cay, cbx * cbx + cby * cby
    use_a = da < db
    d = np.sqrt(np.minimum(da, db))
    # (d/dqx, d/dqy) of the distance: the nearest-point vector over its length (t clamped or not)
    gx = _safe_div(np.where(use_a, cax, cbx), d) * sign
    gy = _safe_div(np.where(use_a, cay * np.sign(qy), cby), d) * sign
    gq = np.stack([_safe_div(gx * loc[:, 0], qx), _safe_div(gx * loc[:, 1], qx), gy], axis=1)
    return sign * d, _to_world(node, gq)


def leaf_facets_with_gradients(node, p, step, facets=None):
    """Names, values ``(k, n)`` and gradients ``(k, n, 3)`` of a leaf's facets at `p`.

    `step` is the forward-difference step of the fallback (leaf coordinates);
    `facets(node, p) -> (names, values)` gives the facets of the leaves
    without closed forms here (default: the leaf as one facet).

    Examples
    --------
    >>> import numpy as np
    >>> from implicit import sphere
    >>> names, v, g = leaf_facets_with_gradients(sphere(1.0), np.array([[2.0, 0.0, 0.0]]), 1e-7)
    >>> v.tolist(), g[0].tolist()
    ([[1.0]], [[1.0, 0.0, 0.0]])
    """
    kind = node.kind
    n = p.shape[0]
    if kind == "box" and not getattr(node, "_rr", 0.0):
        q = p - node._c
        h = node._h
        vals = np.concatenate([q - h, -q - h], axis=1).T
        eye = np.concatenate([np.eye(3), -np.eye(3)])
        return ["+x", "+y", "+z", "-x", "-y", "-z"], vals, np.broadcast_to(eye[:, None, :], (6, n, 3))
    if kind == "cylinder":
        q = _axial(node, p)
        rho = np.hypot(q[:, 0], q[:, 1])
        vals = np.stack([rho - node._r, q[:, 2] - node._hh, -q[:, 2] - node._hh])
        wall = _to_world(node, np.stack([_safe_div(q[:, 0], rho), _safe_div(q[:, 1], rho), np.zeros(n)], axis=1))
        axis = node._frame[2]
        grads = np.stack([wall, np.broadcast_to(axis, (n, 3)), np.broadcast_to(-axis, (n, 3))])
        return ["wall", "top", "bottom"], vals, grads
    if kind == "sphere":
        d = p - node._c
        r = np.sqrt(np.einsum("ij,ij->i", d, d))
        return [""], (r - node._r)[None, :], _safe_div(d, r[:, None])[None]
    if kind == "halfspace":
        return [""], (p @ node._n - node._d)[None, :], np.broadcast_to(node._n, (1, n, 3))
    if kind == "torus":
        q = _axial(node, p)
        rho = np.hypot(q[:, 0], q[:, 1])
        a = rho - node._R
        s = np.hypot(a, q[:, 2])
        gq = np.stack([_safe_div(a * q[:, 0], rho * s), _safe_div(a * q[:, 1], rho * s), _safe_div(q[:, 2], s)], axis=1)
        return [""], (s - node._r)[None, :], _to_world(node, gq)[None]
    if kind == "cone":
        v, g = _cone(node, p)
        return [""], v[None, :], g[None]
    if kind == "capsule" and capsule_kernels() is not None:
        v, g = np.empty(n), np.empty((n, 3))
        capsule_kernels()[1](np.ascontiguousarray(p, dtype=np.float64), node._a, node._ab, node._ab2, node._r, v, g)
        return [""], v[None, :], g[None]
    if kind == "capsule":
        w = p - node._a
        if node._ab2 > 0.0:
            t = np.clip((w @ node._ab) / node._ab2, 0.0, 1.0)
            w = w - t[:, None] * node._ab
        r = np.sqrt(np.einsum("ij,ij->i", w, w))
        return [""], (r - node._r)[None, :], _safe_div(w, r[:, None])[None]
    if facets is None:
        facets = _whole_leaf
    names, v = facets(node, p)
    v = np.asarray(v, dtype=np.float64)
    return names, v, _forward(facets, node, p, v, step)


def _whole_leaf(node, p):
    return [""], np.asarray(node._evaluate(p), dtype=np.float64)[None, :]
