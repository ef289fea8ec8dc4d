"""A compiled proof that a closed triangle surface crosses nowhere, before pymeshfix's test.

`self_intersections` counts the triangles that cross another with pymeshfix, whose loading of the
mesh alone takes 11-17 ms for the benchmark part's FEA surface of 4,500 triangles (the test 14 ms
more).  Almost every surface it sees crosses nowhere: `surely_apart` proves that in one pass, or
gives up, and only then is pymeshfix asked.  It never counts: every pair it cannot separate with a
margin far above the rounding of its arithmetic (a pair that crosses, touches or comes within
``MARGIN`` of its size) sends the whole surface to pymeshfix, so the count is always pymeshfix's.

Pairs are found on a grid of cells about as large as the triangles.  A pair that shares no vertex is
apart when one of the 17 axes of the separating-axis test for triangles (the two normals, the nine
cross products of their edges, the six in-plane normals of their edges) leaves a gap between the
projections; two sharing a vertex are apart (but for it) when each edge opposite it is apart from
the other triangle (the intersection of two triangles through a point, beyond the point, reaches one
of the edges opposite it); two sharing an edge when the fourth vertex is off the first's plane, or
on the other side of the edge in it.

References
----------
S. Gottschalk, M. C. Lin, D. Manocha, "OBBTree: a hierarchical structure for rapid interference
detection", SIGGRAPH 1996, doi:10.1145/237170.237244 (the separating-axis test).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["surely_apart", "MARGIN"]

#: Least gap, relative to a pair's size, that counts as apart: some 10^6 times the rounding of the
#: projections (a few units of 1e-16), so that no rounding can hide a crossing.
MARGIN = 1e-9

#: Most cells of the pair grid along an axis (cells no smaller than the longest edge otherwise).
GRID_CELLS = 1024


@numba.njit(cache=True, inline="always")
def _cross(a, b, out):  # pragma: no cover - compiled
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@numba.njit(cache=True, inline="always")
def _dot(a, b):  # pragma: no cover - compiled
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(cache=True)
def _gap(axis, p, np_, q, nq, scale):  # pragma: no cover - compiled
    """Whether `axis` separates the points p[:np_] from q[:nq] by more than MARGIN (1: yes)."""
    norm = np.sqrt(_dot(axis, axis))
    if norm <= 1e-12 * scale * scale:  # (near) parallel edges: no axis
        return False
    lo1 = hi1 = _dot(axis, p[0])
    for i in range(1, np_):
        s = _dot(axis, p[i])
        lo1 = min(lo1, s)
        hi1 = max(hi1, s)
    lo2 = hi2 = _dot(axis, q[0])
    for i in range(1, nq):
        s = _dot(axis, q[i])
        lo2 = min(lo2, s)
        hi2 = max(hi2, s)
    tol = MARGIN * norm * scale
    return lo2 - hi1 > tol or lo1 - hi2 > tol


@numba.njit(cache=True)
def _apart(p, np_, q, nq, scale, work):  # pragma: no cover - compiled
    """Separating-axis test of two convex sets of 3 (a triangle) or 2 (a segment) points,
    relative to a local origin: True only when some axis leaves a gap above MARGIN.
    `work` is (9, 3) scratch."""
    ep = work[0:3]
    eq = work[3:6]
    mp = 3 if np_ == 3 else 1
    mq = 3 if nq == 3 else 1
    for i in range(mp):
        for k in range(3):
            ep[i, k] = p[(i + 1) % np_, k] - p[i, k]
    for i in range(mq):
        for k in range(3):
            eq[i, k] = q[(i + 1) % nq, k] - q[i, k]
    axis = work[6]
    n1 = work[7]
    n2 = work[8]
    if np_ == 3:
        _cross(ep[0], ep[1], n1)
        if _gap(n1, p, np_, q, nq, scale):
            return True
    if nq == 3:
        _cross(eq[0], eq[1], n2)
        if _gap(n2, p, np_, q, nq, scale):
            return True
    for i in range(mp):
        for j in range(mq):
            _cross(ep[i], eq[j], axis)
            if _gap(axis, p, np_, q, nq, scale):
                return True
    # coplanar sets: the in-plane normals of the edges
    if np_ == 3:
        for i in range(mp):
            _cross(n1, ep[i], axis)
            if _gap(axis, p, np_, q, nq, scale):
                return True
        for j in range(mq):
            _cross(n1, eq[j], axis)
            if _gap(axis, p, np_, q, nq, scale):
                return True
    if nq == 3:
        for j in range(mq):
            _cross(n2, eq[j], axis)
            if _gap(axis, p, np_, q, nq, scale):
                return True
        for i in range(mp):
            _cross(n2, ep[i], axis)
            if _gap(axis, p, np_, q, nq, scale):
                return True
    return False


@numba.njit(cache=True)
def _pair_apart(pts, f, g, p, q, seg, work):  # pragma: no cover - compiled
    """Whether triangles f and g (vertex indices) surely meet at most in their shared vertices
    (`p`, `q` (3, 3), `seg` (2, 3), `work` (9, 3): scratch)."""
    shared = 0
    sf = -1
    sg = -1
    for i in range(3):
        for j in range(3):
            if f[i] == g[j]:
                shared += 1
                sf, sg = i, j
    o = pts[f[0]]
    scale = 0.0
    for i in range(3):
        for k in range(3):
            p[i, k] = pts[f[i], k] - o[k]
            q[i, k] = pts[g[i], k] - o[k]
            scale = max(scale, abs(p[i, k]), abs(q[i, k]))
    if scale == 0.0:
        return False
    if shared == 0:
        return _apart(p, 3, q, 3, scale, work)
    if shared == 1:
        # each edge opposite the shared vertex apart from the other triangle
        for k in range(3):
            seg[0, k] = p[(sf + 1) % 3, k]
            seg[1, k] = p[(sf + 2) % 3, k]
        if not _apart(seg, 2, q, 3, scale, work):
            return False
        for k in range(3):
            seg[0, k] = q[(sg + 1) % 3, k]
            seg[1, k] = q[(sg + 2) % 3, k]
        return _apart(p, 3, seg, 2, scale, work)
    if shared == 2:
        # the edge (a, b), c of f and d of g not on it
        c = -1
        for i in range(3):
            if f[i] != g[0] and f[i] != g[1] and f[i] != g[2]:
                c = i
        d = -1
        for j in range(3):
            if g[j] != f[0] and g[j] != f[1] and g[j] != f[2]:
                d = j
        a = (c + 1) % 3
        b = (c + 2) % 3
        ab = work[0]
        ac = work[1]
        ad = work[2]
        for k in range(3):
            ab[k] = p[b, k] - p[a, k]
            ac[k] = p[c, k] - p[a, k]
            ad[k] = q[d, k] - p[a, k]
        n = work[3]
        _cross(ab, ac, n)
        m = work[4]
        _cross(ab, ad, m)
        nn = np.sqrt(_dot(n, n))
        mm = np.sqrt(_dot(m, m))
        if nn <= 1e-12 * scale * scale or mm <= 1e-12 * scale * scale:
            return False  # a sliver triangle: pymeshfix decides
        # d off the plane of f: the two meet only on the edge
        if abs(_dot(n, ad)) > MARGIN * nn * scale:
            return True
        # in (nearly) one plane: apart when c and d lie on either side of the edge
        return _dot(n, m) < -MARGIN * nn * mm
    return False  # the same triangle twice


@numba.njit(cache=True)
def surely_apart(pts, faces):  # pragma: no cover - compiled
    """True when no two triangles of `faces` meet beyond the vertices they share, proved with a
    margin; False when some pair could not be told apart (then ask pymeshfix).

    pts : (n, 3) float64; faces : (m, 3) int64.
    """
    m = faces.shape[0]
    if m < 2:
        return True
    lo = np.empty(3)
    hi = np.empty(3)
    for k in range(3):
        lo[k] = np.inf
        hi[k] = -np.inf
    longest = 0.0
    for t in range(m):
        for i in range(3):
            for k in range(3):
                v = pts[faces[t, i], k]
                if not np.isfinite(v):
                    return False
                lo[k] = min(lo[k], v)
                hi[k] = max(hi[k], v)
            for k in range(3):
                longest = max(longest, abs(pts[faces[t, i], k] - pts[faces[t, (i + 1) % 3], k]))
    cell = longest
    for k in range(3):
        cell = max(cell, (hi[k] - lo[k]) / GRID_CELLS)
    if not cell > 0.0 or not np.isfinite(cell):
        return False
    dims = np.empty(3, dtype=np.int64)
    for k in range(3):
        dims[k] = int((hi[k] - lo[k]) / cell) + 1
    box = np.empty((m, 6), dtype=np.int64)
    span = np.empty((m, 6))
    for t in range(m):
        for k in range(3):
            a = pts[faces[t, 0], k]
            b = pts[faces[t, 1], k]
            c = pts[faces[t, 2], k]
            span[t, k] = min(a, b, c)
            span[t, 3 + k] = max(a, b, c)
            box[t, k] = min(int((span[t, k] - lo[k]) / cell), dims[k] - 1)
            box[t, 3 + k] = min(int((span[t, 3 + k] - lo[k]) / cell), dims[k] - 1)
    # (cell, triangle) entries sorted by cell: memory as the entries, whatever the grid's size
    total = 0
    for t in range(m):
        total += (box[t, 3] - box[t, 0] + 1) * (box[t, 4] - box[t, 1] + 1) * (box[t, 5] - box[t, 2] + 1)
    keys = np.empty(total, dtype=np.int64)
    owner = np.empty(total, dtype=np.int64)
    e = 0
    for t in range(m):
        for x in range(box[t, 0], box[t, 3] + 1):
            for y in range(box[t, 1], box[t, 4] + 1):
                for z in range(box[t, 2], box[t, 5] + 1):
                    keys[e] = (x * dims[1] + y) * dims[2] + z
                    owner[e] = t
                    e += 1
    order = np.argsort(keys, kind="mergesort")
    p = np.empty((3, 3))
    q = np.empty((3, 3))
    seg = np.empty((2, 3))
    work = np.empty((9, 3))
    start = 0
    while start < total:
        key = keys[order[start]]
        stop = start + 1
        while stop < total and keys[order[stop]] == key:
            stop += 1
        z = key % dims[2]
        y = (key // dims[2]) % dims[1]
        x = key // (dims[1] * dims[2])
        for i in range(start, stop):
            s = owner[order[i]]
            for j in range(i + 1, stop):
                t = owner[order[j]]
                # each pair once: in the first cell both boxes share
                if max(box[s, 0], box[t, 0]) != x or max(box[s, 1], box[t, 1]) != y \
                        or max(box[s, 2], box[t, 2]) != z:
                    continue
                # boxes apart (the coordinates compared as they are: no rounding)
                if span[s, 3] < span[t, 0] or span[t, 3] < span[s, 0] or span[s, 4] < span[t, 1] \
                        or span[t, 4] < span[s, 1] or span[s, 5] < span[t, 2] or span[t, 5] < span[s, 2]:
                    continue
                if not _pair_apart(pts, faces[s], faces[t], p, q, seg, work):
                    return False
        start = stop
    return True
