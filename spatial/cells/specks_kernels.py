"""Compiled kernels of `spatial.cells.specks`: the known values of the shell on a grid, and its local extrema.

Module-level ``@njit(cache=True)`` functions (compiled once per machine): one pass over the
cells each, where numpy needed a fancy-indexed scatter or gather per offset.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = []


@numba.njit(cache=True, nogil=True)
def fill(grid, dims, cells, signs, which, k, shift, far):
    """Write ``+-far`` (by sign) into `grid` (flat, C order over `dims`) at every cell of edge 2h that
    the uniform cells `which` of edge ``k * 2h`` hold: ``k * cell + (0..k-1) + shift`` on every axis
    (a NaN `far` clears them)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    for j in range(which.shape[0]):
        i = which[j]
        v = -far if signs[i] < 0 else far
        for a in range(k):
            x = cells[i, 0] * k + a + shift[0]
            if x < 0 or x >= dims[0]:
                continue
            for b in range(k):
                y = cells[i, 1] * k + b + shift[1]
                if y < 0 or y >= dims[1]:
                    continue
                for c in range(k):
                    z = cells[i, 2] * k + c + shift[2]
                    if z < 0 or z >= dims[2]:
                        continue
                    grid[x * s0 + y * s1 + z] = v


@numba.njit(cache=True, nogil=True)
def by_plane(x, k, lo, n):
    """The cells in order of their plane ``k * x - lo`` along the first axis (clipped to ``0..n-1``; a
    counting sort, stable): the order and the start of every plane in it, ``(n + 1,)``."""
    count = np.zeros(n + 1, np.int64)
    for i in range(x.shape[0]):
        p = min(max(np.int64(x[i]) * k - lo, 0), n - 1)
        count[p + 1] += 1
    for p in range(n):
        count[p + 1] += count[p]
    starts = count.copy()
    order = np.empty(x.shape[0], np.int64)
    for i in range(x.shape[0]):
        p = min(max(np.int64(x[i]) * k - lo, 0), n - 1)
        order[count[p]] = i
        count[p] += 1
    return order, starts


@numba.njit(cache=True, nogil=True)
def box(cells):
    """The lower and upper corners (inclusive) of the cells."""
    lo = np.empty(3, np.int64)
    hi = np.empty(3, np.int64)
    for a in range(3):
        lo[a] = cells[0, a]
        hi[a] = cells[0, a]
    for i in range(cells.shape[0]):
        for a in range(3):
            v = np.int64(cells[i, a])
            if v < lo[a]:
                lo[a] = v
            if v > hi[a]:
                hi[a] = v
    return lo, hi


@numba.njit(cache=True, nogil=True)
def put(grid, dims, cells, which, shift, values):
    """Write ``values[i]`` into `grid` at ``cells[i] + shift`` for the cells `which` (float32: a tie
    stays a tie); a `values` of one element writes it at every cell (NaN clears them)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    one = values.shape[0] == 1
    for j in range(which.shape[0]):
        i = which[j]
        f = (cells[i, 0] + shift[0]) * s0 + (cells[i, 1] + shift[1]) * s1 + cells[i, 2] + shift[2]
        grid[f] = values[0] if one else values[i]


@numba.njit(cache=True, nogil=True)
def put_flat(grid, flat, values):
    """Write `values` into `grid` at the flat indices `flat`."""
    for i in range(flat.shape[0]):
        grid[flat[i]] = values[i]


@numba.njit(cache=True, nogil=True)
def extrema(grid, dims, cells, shift, which, deltas, mark):
    """For the cells `which` (at ``cells + shift`` in the grid): 1 where the value is a minimum of
    the 26 neighbours', -1 a maximum, 0 neither (or all equal), 2 undecided (a neighbour is NaN:
    unknown).  `deltas` are the neighbours' flat offsets, the six faces first (they decide most
    cells).  The unknown neighbours of the undecided cells are returned (flat indices, each once:
    they are marked in the grid with `mark` until their values are written)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    out = np.zeros(which.shape[0], np.int8)
    ask = np.empty(64, np.int64)
    n_ask = 0
    for j in range(which.shape[0]):
        i = which[j]
        f = (cells[i, 0] + shift[0]) * s0 + (cells[i, 1] + shift[1]) * s1 + cells[i, 2] + shift[2]
        v = grid[f]
        lower = True
        upper = True
        differs = False
        unknown = False
        for d in deltas:
            w = grid[f + d]
            if np.isnan(w) or w == mark:
                unknown = True
                continue
            if w < v:
                lower = False
            elif w > v:
                upper = False
            if w != v:
                differs = True
            if not lower and not upper:
                break
        if not lower and not upper:
            out[j] = 0
        elif unknown:
            out[j] = 2
            for d in deltas:
                if np.isnan(grid[f + d]):
                    grid[f + d] = mark
                    if n_ask == ask.shape[0]:
                        more = np.empty(2 * n_ask, np.int64)
                        more[:n_ask] = ask
                        ask = more
                    ask[n_ask] = f + d
                    n_ask += 1
        elif not differs:
            out[j] = 0
        else:
            out[j] = 1 if lower else -1
    return out, ask[:n_ask]
