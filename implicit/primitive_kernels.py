"""Compiled loops of the primitives evaluated most often by numpy: a capsule's distance and gradient.

The feature pass of a part of many capsules (a lattice's struts) evaluates
each capsule near every point it may decide (`implicit.facet_prune`), a few
thousand points a call: numpy's nine passes over them cost about 150 ns a
point, one loop 5.  Module-level ``njit(cache=True)`` functions, loaded from
numba's on-disk cache; imported on first use only (numba is not imported with
`implicit`), by `implicit.primitives.capsule_kernels`.
"""

from __future__ import annotations

import math

import numba

__all__ = ["capsule_distance", "capsule_gradient"]



@numba.njit(cache=True, nogil=True, inline="always")
def _from_segment(p, i, a, ab, ab2):  # pragma: no cover - compiled
    """The vector to ``p[i]`` from its nearest point on the segment ``a .. a + ab``."""
    wx, wy, wz = p[i, 0] - a[0], p[i, 1] - a[1], p[i, 2] - a[2]
    if ab2 > 0.0:
        t = (wx * ab[0] + wy * ab[1] + wz * ab[2]) / ab2
        t = min(max(t, 0.0), 1.0)
        wx, wy, wz = wx - t * ab[0], wy - t * ab[1], wz - t * ab[2]
    return wx, wy, wz

@numba.njit(cache=True, nogil=True)
def capsule_distance(p, a, ab, ab2, r, out):  # pragma: no cover - compiled
    """``out[i]``: distance of ``p[i]`` to the segment ``a .. a + ab`` (``ab2 = ab . ab``) minus `r`."""
    for i in range(p.shape[0]):
        wx, wy, wz = _from_segment(p, i, a, ab, ab2)
        out[i] = math.sqrt(wx * wx + wy * wy + wz * wz) - r


@numba.njit(cache=True, nogil=True)
def capsule_gradient(p, a, ab, ab2, r, out, grad):  # pragma: no cover - compiled
    """`capsule_distance` and its gradient ``grad[i]``: the unit vector from the segment's nearest
    point (zero on the segment)."""
    for i in range(p.shape[0]):
        wx, wy, wz = _from_segment(p, i, a, ab, ab2)
        d = math.sqrt(wx * wx + wy * wy + wz * wz)
        out[i] = d - r
        if d > 0.0:
            grad[i, 0], grad[i, 1], grad[i, 2] = wx / d, wy / d, wz / d
        else:
            grad[i, 0], grad[i, 1], grad[i, 2] = 0.0, 0.0, 0.0
