"""Compiled kernels of the lattice's last two levels: children of BOUNDARY cells, and their split by value.

The classification of `spatial.meshing.boundary` samples the centres of the children of the
BOUNDARY cells of one level and keeps those within reach of the surface.  Listing every child
first (12 bytes each) and splitting it with numpy masks and copies held several arrays of all the
children at once; these kernels read a child from its parent when it is needed, so only the
values sampled and the cells kept are whole arrays.

The children are numbered as the classification lists them: the eight children of each parent
of `inner` in `CHILD_OFFSETS` order, then the rows of `outer` (the children inside the region of
the parents on its upper edge).  Module-level ``@njit(cache=True)`` functions.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = []


@numba.njit(cache=True, nogil=True)
def _child(parents, inner, outer, offsets, t, out, row):
    n_inner = 8 * inner.shape[0]
    if t < n_inner:
        p = inner[t >> 3]
        o = t & 7
        for a in range(3):
            out[row, a] = 2 * parents[p, a] + offsets[o, a]
    else:
        for a in range(3):
            out[row, a] = outer[t - n_inner, a]


@numba.njit(cache=True, nogil=True)
def children(parents, inner, outer, offsets, a, b):
    """The children numbered ``a`` to ``b - 1`` (int32, ``(b - a, 3)``)."""
    out = np.empty((b - a, 3), np.int32)
    for t in range(a, b):
        _child(parents, inner, outer, offsets, t, out, t - a)
    return out


@numba.njit(cache=True, nogil=True)
def centres(parents, inner, outer, offsets, a, b, origin, size, h):
    """The centres of the children numbered ``a`` to ``b - 1``, cells of `size` voxels of edge `h`:
    ``origin + (size * child + size // 2) * h``, the same floating-point operations as numpy's."""
    c = np.empty((1, 3), np.int32)
    out = np.empty((b - a, 3), np.float64)
    half = size // 2
    for t in range(a, b):
        _child(parents, inner, outer, offsets, t, c, 0)
        for k in range(3):
            out[t - a, k] = origin[k] + np.float64(np.int32(size * c[0, k] + half)) * h
    return out


@numba.njit(cache=True, nogil=True)
def split(parents, inner, outer, offsets, values, bound, beyond):
    """The children whose ``|value| <= bound`` (they may hold boundary) with their values, and the
    others with their signs (-1 where the value is negative, else +1; a NaN is +1), followed by the
    cells `beyond` (+1: outside the region), each in the children's order.

    Returns ``(kept (k, 3) int32, kept values (k,), uniform (j, 3) int32, signs (j,) int8)``.
    """
    total = values.shape[0]
    k = 0
    for t in range(total):
        if abs(values[t]) <= bound:
            k += 1
    kept = np.empty((k, 3), np.int32)
    kept_values = np.empty(k, values.dtype)
    j = total - k + beyond.shape[0]
    uniform = np.empty((j, 3), np.int32)
    signs = np.empty(j, np.int8)
    ik = 0
    iu = 0
    for t in range(total):
        v = values[t]
        if abs(v) <= bound:
            _child(parents, inner, outer, offsets, t, kept, ik)
            kept_values[ik] = v
            ik += 1
        else:
            _child(parents, inner, outer, offsets, t, uniform, iu)
            signs[iu] = -1 if v < 0 else 1
            iu += 1
    for r in range(beyond.shape[0]):
        for a in range(3):
            uniform[iu, a] = beyond[r, a]
        signs[iu] = 1
        iu += 1
    return kept, kept_values, uniform, signs


@numba.njit(cache=True, nogil=True)
def at_upper_edge(parents, limit):
    """The parents whose children all lie inside the region (``2 * parent + 1 < limit`` on every axis)
    and the others, each as increasing row indices: ``np.flatnonzero(~edge)`` and ``np.flatnonzero(edge)``
    of ``edge = (2 * parents + 1 >= limit).any(axis=1)``, without its whole-array temporaries."""
    n = parents.shape[0]
    n_edge = 0
    for i in range(n):
        for a in range(3):
            if 2 * parents[i, a] + 1 >= limit[a]:
                n_edge += 1
                break
    inner = np.empty(n - n_edge, np.int64)
    edge = np.empty(n_edge, np.int64)
    ki = 0
    ke = 0
    for i in range(n):
        out = False
        for a in range(3):
            if 2 * parents[i, a] + 1 >= limit[a]:
                out = True
                break
        if out:
            edge[ke] = i
            ke += 1
        else:
            inner[ki] = i
            ki += 1
    return inner, edge


@numba.njit(cache=True, nogil=True)
def centre_nodes(parents, inner, outer, offsets, a, b, size):
    """The lattice nodes at the centres of the children numbered ``a`` to ``b - 1``, cells of `size`
    voxels: ``size * child + size // 2`` (int32, ``(b - a, 3)``; `children` scaled in place)."""
    out = children(parents, inner, outer, offsets, a, b)
    half = size // 2
    for r in range(out.shape[0]):
        for k in range(3):
            out[r, k] = size * out[r, k] + half
    return out
