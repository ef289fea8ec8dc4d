"""Compiled kernels of `spatial.cells.specks`: the known values of the shell on a grid, and its local extrema.

Module-level ``@njit(cache=True)`` functions (compiled once per machine): one pass over the
cells each, where numpy needed a fancy-indexed scatter or gather per offset.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = []


@numba.njit(cache=True, nogil=True)
def fill(grid, dims, cells, signs, k, far):
    """Write ``+-far`` (by sign) into `grid` (flat, C order over `dims`) at every cell of edge 2h that
    a uniform cell of edge ``k * 2h`` holds (`cells` on its own lattice, already shifted by the box)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    for i in range(cells.shape[0]):
        v = -far if signs[i] < 0 else far
        for a in range(k):
            x = cells[i, 0] * k + a
            if x < 0 or x >= dims[0]:
                continue
            for b in range(k):
                y = cells[i, 1] * k + b
                if y < 0 or y >= dims[1]:
                    continue
                for c in range(k):
                    z = cells[i, 2] * k + c
                    if z < 0 or z >= dims[2]:
                        continue
                    grid[x * s0 + y * s1 + z] = v


@numba.njit(cache=True, nogil=True)
def put(grid, dims, cells, values):
    """Write `values` into `grid` at `cells`; returns the values as stored (float32)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    out = np.empty(cells.shape[0], np.float32)
    for i in range(cells.shape[0]):
        f = cells[i, 0] * s0 + cells[i, 1] * s1 + cells[i, 2]
        grid[f] = values[i]
        out[i] = grid[f]
    return out


@numba.njit(cache=True, nogil=True)
def extrema(grid, dims, cells, which, deltas):
    """For the cells `which`: 1 where the value is a minimum of the 26 neighbours', -1 a maximum, 0
    neither (or all equal), 2 undecided (a neighbour is NaN: unknown).  `deltas` are the
    neighbours' flat offsets, the six faces first (they decide most cells)."""
    s0, s1 = dims[1] * dims[2], dims[2]
    out = np.zeros(which.shape[0], np.int8)
    for j in range(which.shape[0]):
        i = which[j]
        f = cells[i, 0] * s0 + cells[i, 1] * s1 + cells[i, 2]
        v = grid[f]
        lower = True
        upper = True
        differs = False
        unknown = False
        for d in deltas:
            w = grid[f + d]
            if np.isnan(w):
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
        elif not differs:
            out[j] = 0
        else:
            out[j] = 1 if lower else -1
    return out
