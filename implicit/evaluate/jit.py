"""The numba kernels of the evaluator, at module level so that numba's on-disk cache serves them.

A kernel that closes over another compiled function gets a new cache key in every
process and is compiled again each time; these are plain module-level functions
(``cache=True``) that refer to each other as globals, so a second process loads
them from ``__pycache__`` instead of compiling.  Imported only when numba is
there (`implicit.evaluate.kernels`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit

__all__ = ["run_serial", "run_parallel", "bin_points", "bounds_of", "unsort"]


@njit(fastmath=False, cache=True, nogil=True)
def run_block(code, K, R, n, flags, c, rec, s, X):
    pc = 0
    ncode = code.shape[0]
    while pc < ncode:
        op = code[pc, 0]
        if op == 99:
            if not flags[c, code[pc, 2]]:
                pc = code[pc, 3]
                continue
            pc += 1
            continue
        d = code[pc, 1]
        a = code[pc, 2]
        b = code[pc, 3]
        e = code[pc, 4]
        g = code[pc, 5]
        k = K[code[pc, 6]]
        if op == 0:
            for j in range(n):
                R[d, j] = R[a, j] + R[b, j]
        elif op == 1:
            for j in range(n):
                R[d, j] = R[a, j] - R[b, j]
        elif op == 2:
            for j in range(n):
                R[d, j] = R[a, j] * R[b, j]
        elif op == 3:
            for j in range(n):
                R[d, j] = R[a, j] / R[b, j]
        elif op == 4:
            for j in range(n):
                R[d, j] = min(R[a, j], R[b, j])
        elif op == 5:
            for j in range(n):
                R[d, j] = max(R[a, j], R[b, j])
        elif op == 6:
            for j in range(n):
                R[d, j] = R[a, j] + k
        elif op == 7:
            for j in range(n):
                R[d, j] = R[a, j] - k
        elif op == 8:
            for j in range(n):
                R[d, j] = R[a, j] * k
        elif op == 9:
            for j in range(n):
                R[d, j] = R[a, j] / k
        elif op == 10:
            for j in range(n):
                R[d, j] = min(R[a, j], k)
        elif op == 11:
            for j in range(n):
                R[d, j] = max(R[a, j], k)
        elif op == 12:
            for j in range(n):
                R[d, j] = k - R[a, j]
        elif op == 13:
            for j in range(n):
                R[d, j] = -R[a, j]
        elif op == 14:
            for j in range(n):
                R[d, j] = abs(R[a, j])
        elif op == 15:
            for j in range(n):
                R[d, j] = math.sqrt(R[a, j])
        elif op == 16:
            for j in range(n):
                R[d, j] = R[a, j] * k + R[b, j]
        elif op == 17:
            for j in range(n):
                R[d, j] = math.sqrt(R[a, j] * R[a, j] + R[b, j] * R[b, j])
        elif op == 18:
            for j in range(n):
                R[d, j] = math.sqrt(R[a, j] * R[a, j] + R[b, j] * R[b, j] + R[e, j] * R[e, j])
        elif op == 19:
            for j in range(n):
                R[d, j] = k
        elif op == 20:
            k2 = K[code[pc, 6] + 1]
            for j in range(n):
                R[d, j] = k if R[a, j] < 0.0 else k2
        elif op == 21:
            for j in range(n):
                R[d, j] = -R[a, j] if (R[b, j] < 0.0) & (R[e, j] < 0.0) else R[a, j]
        elif op == 22:
            for j in range(n):
                R[d, j] = math.sqrt(min(R[a, j] * R[a, j] + R[b, j] * R[b, j], R[e, j] * R[e, j] + R[g, j] * R[g, j]))
        elif op == 23:
            for j in range(n):
                R[d, j] = max(R[a, j], -R[b, j])
        elif op == 24:
            for j in range(n):
                rec[b, s + j] = R[a, j]
        elif op == 27:
            for j in range(n):
                R[d, j] = X[b, s + j]
        elif op == 25:
            hh = K[code[pc, 6] + 1]
            for j in range(n):
                dr = math.sqrt(R[a, j] * R[a, j] + R[b, j] * R[b, j]) - k
                dz = abs(R[e, j]) - hh
                mr = max(dr, 0.0)
                mz = max(dz, 0.0)
                R[d, j] = math.sqrt(mr * mr + mz * mz) + min(max(dr, dz), 0.0)
        elif op == 26:
            k1 = K[code[pc, 6] + 1]
            k2 = K[code[pc, 6] + 2]
            k3 = K[code[pc, 6] + 3]
            for j in range(n):
                qx = abs(R[a, j]) - k
                qy = abs(R[b, j]) - k1
                qz = abs(R[e, j]) - k2
                mx = max(qx, 0.0)
                my = max(qy, 0.0)
                mz = max(qz, 0.0)
                R[d, j] = (math.sqrt(mx * mx + my * my + mz * mz) + min(max(qx, max(qy, qz)), 0.0)) - k3
        pc += 1

@njit(fastmath=False, cache=True, nogil=True)
def _run_task(t, per, nbins, code, K, nreg, result, pts, starts, flags, out, block, rec, X):
    # Task t runs bins t*per .. (t+1)*per; bin c holds points starts[c]:starts[c + 1], and its
    # flags row says which operands run.
    R = np.empty((nreg, block))
    for c in range(t * per, min(nbins, (t + 1) * per)):
        for s in range(starts[c], starts[c + 1], block):
            n = min(block, starts[c + 1] - s)
            for j in range(n):
                R[0, j] = pts[s + j, 0]
                R[1, j] = pts[s + j, 1]
                R[2, j] = pts[s + j, 2]
            run_block(code, K, R, n, flags, c, rec, s, X)
            for j in range(n):
                out[s + j] = R[result, j]


@njit(fastmath=False, cache=True, nogil=True)
def run_serial(code, K, nreg, result, pts, starts, flags, out, block, nthreads, rec, X):
    nbins = starts.shape[0] - 1
    for t in range(nbins):
        _run_task(t, 1, nbins, code, K, nreg, result, pts, starts, flags, out, block, rec, X)


@njit(fastmath=False, cache=True, nogil=True, parallel=True)
def run_parallel(code, K, nreg, result, pts, starts, flags, out, block, nthreads, rec, X):
    # Several tasks per thread, so that the scheduler spreads them over the threads.
    nbins = starts.shape[0] - 1
    ntasks = max(1, min(nbins, 8 * nthreads))
    per = (nbins + ntasks - 1) // ntasks
    for t in numba.prange(ntasks):
        _run_task(t, per, nbins, code, K, nreg, result, pts, starts, flags, out, block, rec, X)


@njit(cache=True, nogil=True)
def bounds_of(pts):
    lx = hx = pts[0, 0]
    ly = hy = pts[0, 1]
    lz = hz = pts[0, 2]
    for i in range(pts.shape[0]):
        x = pts[i, 0]
        y = pts[i, 1]
        z = pts[i, 2]
        lx = min(lx, x)
        hx = max(hx, x)
        ly = min(ly, y)
        hy = max(hy, y)
        lz = min(lz, z)
        hz = max(hz, z)
    return np.array([lx, ly, lz]), np.array([hx, hy, hz])

@njit(cache=True, nogil=True)
def unsort(values, order, out):
    for k in range(values.shape[0]):
        out[order[k]] = values[k]

@njit(cache=True, nogil=True)
def bin_points(pts, lo, scale, g, cell, order, sorted_pts):
    # Counting sort of the points by grid cell (g[0] x g[1] x g[2] cells)
    # into the buffers `order` (permutation) and `sorted_pts`; returns the
    # start of every non-empty bin and the tight box of its points.
    n = pts.shape[0]
    gx, gy, gz = g[0], g[1], g[2]
    total = gx * gy * gz
    counts = np.zeros(total + 1, np.int64)
    for i in range(n):
        ix = min(max(int((pts[i, 0] - lo[0]) * scale[0]), 0), gx - 1)
        iy = min(max(int((pts[i, 1] - lo[1]) * scale[1]), 0), gy - 1)
        iz = min(max(int((pts[i, 2] - lo[2]) * scale[2]), 0), gz - 1)
        c = (ix * gy + iy) * gz + iz
        cell[i] = c
        counts[c + 1] += 1
    nonempty = 0
    for c in range(total):
        if counts[c + 1] > 0:
            nonempty += 1
        counts[c + 1] += counts[c]
    starts = np.empty(nonempty + 1, np.int64)
    j = 0
    for c in range(total):
        if counts[c + 1] > counts[c]:
            starts[j] = counts[c]
            j += 1
    starts[nonempty] = n
    fill = counts[:-1].copy()
    for i in range(n):
        c = cell[i]
        k = fill[c]
        order[k] = i
        sorted_pts[k, 0] = pts[i, 0]
        sorted_pts[k, 1] = pts[i, 1]
        sorted_pts[k, 2] = pts[i, 2]
        fill[c] = k + 1
    lo_box = np.empty((nonempty, 3))
    hi_box = np.empty((nonempty, 3))
    for b in range(nonempty):
        for a in range(3):
            vmin = sorted_pts[starts[b], a]
            vmax = vmin
            for k in range(starts[b] + 1, starts[b + 1]):
                v = sorted_pts[k, a]
                vmin = min(vmin, v)
                vmax = max(vmax, v)
            lo_box[b, a] = vmin
            hi_box[b, a] = vmax
    return starts, lo_box, hi_box
