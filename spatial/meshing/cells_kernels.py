"""Compiled bookkeeping of `cells`: rows bucketed by slab or plane, each slab's share cut out, the vertex stage.

The boundary cells, the uniform cells around them and the nodes the classification sampled
come in the octree's order.  Sorting them along x and gathering the sorted copies (numpy's
``argsort`` and fancy indexing over every row, several passes and whole-array temporaries each)
cost more than the surface's growth at N=2048; a counting sort by the row's slab or x plane is
one pass over the keys, and each slab's share is gathered straight into its own array, with the
samples nudged off the level (`arrays._nudge`) and made single precision on the way.  The
vertex stage after the merge reads each vertex once for its edge fraction, whether its end
values certify it (`refine._certified`) and whether it lies beside a tie, where numpy held
several vertex-sized temporaries at the peak of memory.

Module-level ``@njit(cache=True)`` functions; every result equals the numpy expression it
replaces, bit for bit.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = []


@numba.njit(cache=True, nogil=True)
def min_max(x):
    """The smallest and largest entry of an integer array of one axis (at least one entry)."""
    lo = np.int64(x[0])
    hi = lo
    for i in range(x.shape[0]):
        v = np.int64(x[i])
        if v < lo:
            lo = v
        elif v > hi:
            hi = v
    return lo, hi


@numba.njit(cache=True, nogil=True)
def min_max_rows(rows):
    """The smallest and largest entry of (k, 3) integer rows (at least one row)."""
    lo = np.int64(rows[0, 0])
    hi = lo
    for i in range(rows.shape[0]):
        for c in range(rows.shape[1]):
            v = np.int64(rows[i, c])
            if v < lo:
                lo = v
            elif v > hi:
                hi = v
    return lo, hi


@numba.njit(cache=True, nogil=True)
def order_by_key(x, div, lo, n):
    """Rows in order of their key ``x // div - lo`` (``0 .. n - 1``; a stable counting sort, the order
    of ``np.argsort(keys, kind="stable")``) and where each key starts in that order, ``(n + 1,)``.
    A `div` that is a power of two (the slabs' 16 cells, the planes' 1) is an arithmetic shift: the
    same floor division, without a 64-bit divide per row and pass."""
    start = np.zeros(n + 1, np.int64)
    order = np.empty(x.shape[0], np.int64)
    if div > 0 and div & (div - 1) == 0:
        s = np.int64(0)
        while (np.int64(1) << s) < div:
            s += 1
        for i in range(x.shape[0]):
            start[(np.int64(x[i]) >> s) - lo + 1] += 1
        for k in range(n):
            start[k + 1] += start[k]
        at = start[:n].copy()
        for i in range(x.shape[0]):
            k = (np.int64(x[i]) >> s) - lo
            order[at[k]] = i
            at[k] += 1
        return order, start
    for i in range(x.shape[0]):
        start[np.int64(x[i]) // div - lo + 1] += 1
    for k in range(n):
        start[k + 1] += start[k]
    at = start[:n].copy()
    for i in range(x.shape[0]):
        k = np.int64(x[i]) // div - lo
        order[at[k]] = i
        at[k] += 1
    return order, start


@numba.njit(cache=True, nogil=True)
def take_rows(src, order, a, b, out):
    """``out[:] = src[order[a:b]]`` for (k, 3) rows (cast to `out`'s type)."""
    for r in range(a, b):
        i = order[r]
        for c in range(3):
            out[r - a, c] = src[i, c]


@numba.njit(cache=True, nogil=True)
def take_entries(src, order, a, b, out):
    """``out[:] = src[order[a:b]]`` (cast to `out`'s type)."""
    for r in range(a, b):
        out[r - a] = src[order[r]]


@numba.njit(cache=True, nogil=True)
def take_nudged(src, order, a, b, eps, out):
    """``out[:] = _nudge(src[order[a:b]], h)`` in single precision: a value within `eps` of the level
    (NaN included) pushed to ``-eps`` if negative, else ``+eps``, then rounded to float32."""
    for r in range(a, b):
        v = src[order[r]]
        if not abs(v) >= eps:
            v = -eps if v < 0 else eps
        out[r - a] = np.float32(v)


@numba.njit(cache=True, nogil=True)
def ties(values, limit):
    """Indices (increasing) of the values within `limit` of 0: ``np.flatnonzero(np.abs(values) <= limit)``."""
    n = 0
    for i in range(values.shape[0]):
        if abs(values[i]) <= limit:
            n += 1
    out = np.empty(n, np.int64)
    n = 0
    for i in range(values.shape[0]):
        if abs(values[i]) <= limit:
            out[n] = i
            n += 1
    return out


@numba.njit(cache=True, nogil=True)
def tie_probes(values, pts, lo, hi, limit, eps, offsets):
    """The first half of `arrays._settle_ties` in one pass: the ties (``|v| <= limit``) on or beyond the
    bounds' faces (``pts <= lo`` or ``pts >= hi`` on an axis) set to `eps` in place; returns the other
    ties' indices (increasing) and their probes, ``pts[tie][:, None, :] + offsets`` as ``(6 k, 3)`` rows."""
    n = 0
    for i in range(values.shape[0]):
        if abs(values[i]) <= limit:
            face = False
            for j in range(3):
                if pts[i, j] <= lo[j] or pts[i, j] >= hi[j]:
                    face = True
            if face:
                values[i] = eps
            else:
                n += 1
    tie = np.empty(n, np.int64)
    probe = np.empty((6 * n, 3), np.float64)
    k = 0
    for i in range(values.shape[0]):
        if abs(values[i]) <= limit:
            tie[k] = i
            for d in range(6):
                for j in range(3):
                    probe[6 * k + d, j] = pts[i, j] + offsets[d, j]
            k += 1
    return tie, probe


@numba.njit(cache=True, nogil=True)
def settle_probed(values, tie, near, limit, eps):
    """The second half of `arrays._settle_ties`: a tie is outside (`eps`) when one of its six probes
    `near` is above `limit` or NaN, else inside (``-eps``), in place."""
    for k in range(tie.shape[0]):
        outside = False
        for d in range(6):
            v = near[6 * k + d]
            if v > limit or v != v:
                outside = True
        values[tie[k]] = eps if outside else -eps


@numba.njit(cache=True, nogil=True, inline="always")
def _free_and_tied(f0, f1, i, refine, certify, floor, least, split):
    # `refine._certified`, negated: float32 throughout, as numpy computes it there; bitwise `&` and
    # `|` (no short cut), so that the loops below run without branches on the values
    a = abs(f0[i])
    b = abs(f1[i])
    trusted = certify & (a > floor) & (b > floor) & (b + a >= least)
    free = refine & (not trusted)
    tied = free & split & ((a <= floor) | (b <= floor))
    return free, tied


@numba.njit(cache=True, nogil=True)
def stage_counts(f0, f1, axis, interior, refine, certify, floor, least, split, a, b):
    """The vertex stage's counts over the vertices ``a .. b-1``: ``(inside a cube, tied, rest)``.

    The vertex stage (`cells._vertex_stage`, in chunks): a vertex inside a cube (axis `interior`)
    gets ``f1 = -f0`` and axis 0, in place; ``t = f0 / (f0 - f1)`` in double precision.  With
    `refine`, the vertices neither inside a cube nor certified (`certify`: the Lipschitz test of
    `refine._certified` with its `floor` and its ``L h - REFINE_ACCEPT h`` bound `least`, both
    float32) are listed in increasing order; with `split`, those with an end within `floor` of the
    level (beside a tie) apart from the others.
    """
    n_inner = 0
    n_tied = 0
    n_rest = 0
    for i in range(a, b):
        if axis[i] == interior:
            n_inner += 1
        else:
            free, tied = _free_and_tied(f0, f1, i, refine, certify, floor, least, split)
            n_tied += tied
            n_rest += free & (not tied)
    return n_inner, n_tied, n_rest


@numba.njit(cache=True, nogil=True)
def stage_fill(f0, f1, axis, interior, refine, certify, floor, least, split, a, b, t, inner, tied_rows, rest_rows,
               at_inner, at_tied, at_rest):
    """The vertex stage over the vertices ``a .. b-1``, written into `t` and into the lists from the
    given slots (`stage_counts` of the vertices before `a`: several ranges fill the lists at once,
    so nothing is written past a range's own slots); returns whether every ``t`` is finite."""
    finite = True
    for i in range(a, b):
        if axis[i] == interior:
            f1[i] = -f0[i]
            axis[i] = 0
            inner[at_inner] = i
            at_inner += 1
        else:
            free, tied = _free_and_tied(f0, f1, i, refine, certify, floor, least, split)
            if tied:
                tied_rows[at_tied] = i
                at_tied += 1
            elif free:
                rest_rows[at_rest] = i
                at_rest += 1
        v0 = np.float64(f0[i])
        v = v0 / (v0 - np.float64(f1[i]))
        t[i] = v
        finite &= np.isfinite(v)
    return finite
