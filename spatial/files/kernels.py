"""Compiled passes over triangle arrays: a binary STL's records and the edges' count.

`stl_records` fills the 50-byte records of a binary STL (an 80-byte header,
a little-endian uint32 count, then per triangle the unit normal and the
three corners as float32 and a zero uint16).  The numpy form of this fill
gathered every corner as float64, took the cross products, their lengths and
the quotients in six whole-array passes with their temporaries, and copied
the results into a structured array field by field (0.1 s of ``implicad
mesh -o part.stl`` at 924,020 triangles); the kernel does it in one pass,
without the interpreter's lock, and computes exactly what that code did: the
normal ``(c1 - c0) x (c2 - c0)`` in float64, divided by its length, zero
where the length is zero, rounded to float32 with the corners
(`tests/files/test_stl.py` compares the bytes with the numpy form's).

`edges_twice` tells whether every edge of a triangle list is shared by
exactly two triangles (no open edge, none of three or more): the edges are
bucketed by their lower vertex in two counting passes and each bucket (a
vertex's few neighbours) checked on its own, linear in the triangles where
sorting all the edge keys was not (0.07 s at 924,020 triangles).

Examples
--------
>>> import numpy as np
>>> out = np.zeros(50, dtype=np.uint8)
>>> stl_records(np.eye(3), np.array([[0, 1, 2]]), 0, 1, out)
>>> [round(float(v), 4) for v in np.frombuffer(out[:12].tobytes(), dtype="<f4")]
[0.5774, 0.5774, 0.5774]
>>> tetrahedron = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]])
>>> bool(edges_twice(tetrahedron, 4)), bool(edges_twice(tetrahedron[:3], 4))
(True, False)
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["RECORD", "stl_records", "edges_twice"]

#: Bytes of one triangle's record.
RECORD = 50


@numba.njit(cache=True, nogil=True)
def stl_records(points, tri, a, b, out):
    """Fill `out` (uint8, at least ``50 * (b - a)`` bytes) with the records of triangles ``a:b``.

    `points` (n, 3) float64, `tri` (m, 3) integer indices into it.  The
    attribute bytes of each record are written as zero.
    """
    scratch = np.empty(12, dtype=np.float32)
    raw = scratch.view(np.uint8)
    for k in range(b - a):
        t = a + k
        i, j, m = tri[t, 0], tri[t, 1], tri[t, 2]
        e0, e1, e2 = points[j, 0] - points[i, 0], points[j, 1] - points[i, 1], points[j, 2] - points[i, 2]
        f0, f1, f2 = points[m, 0] - points[i, 0], points[m, 1] - points[i, 1], points[m, 2] - points[i, 2]
        # numpy's cross: each component a product minus a product, in this order
        n0 = e1 * f2 - e2 * f1
        n1 = e2 * f0 - e0 * f2
        n2 = e0 * f1 - e1 * f0
        length = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        if length > 0:
            n0, n1, n2 = n0 / length, n1 / length, n2 / length
        elif length == 0:
            n0, n1, n2 = 0.0, 0.0, 0.0
        scratch[0], scratch[1], scratch[2] = n0, n1, n2
        for c in range(3):
            v = tri[t, c]
            scratch[3 + 3 * c] = points[v, 0]
            scratch[4 + 3 * c] = points[v, 1]
            scratch[5 + 3 * c] = points[v, 2]
        base = RECORD * k
        for q in range(48):
            out[base + q] = raw[q]
        out[base + 48] = 0
        out[base + 49] = 0


@numba.njit(cache=True, nogil=True)
def edges_twice(tri, n_points):
    """True when every edge of the triangles `tri` (m, 3), vertex ids below `n_points`, is in exactly two."""
    m = tri.shape[0]
    start = np.zeros(n_points + 1, dtype=np.int64)
    for t in range(m):
        for c in range(3):
            a, b = tri[t, c], tri[t, (c + 1) % 3]
            start[min(a, b) + 1] += 1
    for v in range(n_points):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    upper = np.empty(3 * m, dtype=np.int64)
    for t in range(m):
        for c in range(3):
            a, b = tri[t, c], tri[t, (c + 1) % 3]
            lo = min(a, b)
            upper[fill[lo]] = max(a, b)
            fill[lo] += 1
    for v in range(n_points):
        s, e = start[v], start[v + 1]
        if (e - s) % 2:
            return False
        # a vertex has a few neighbours: insertion sort of its bucket, then pairs of equal ids
        for i in range(s + 1, e):
            x = upper[i]
            j = i - 1
            while j >= s and upper[j] > x:
                upper[j + 1] = upper[j]
                j -= 1
            upper[j + 1] = x
        for i in range(s, e, 2):
            if upper[i] != upper[i + 1] or (i + 2 < e and upper[i + 2] == upper[i]):
                return False
    return True
