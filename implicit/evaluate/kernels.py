"""The numba interpreter that runs tapes: kernels compiled once per process, and their calls.

numba is optional: without it `numba_available` is False and `implicit.evaluate.compile`
falls back to numpy.
"""

from __future__ import annotations

import math
import threading
import time

import numpy as np

from . import prune
from ..csg import Difference, Union
from ..primitives import Box, Cone, Sphere, Torus
from .tape import (OPS, PRUNE_MODES, RULES, KernelSource, Tape, Unsupported,  # noqa: F401
                   _numpy_evaluate, register_rule)

__all__ = ["numba_available", "COMPILE_SECONDS"]


# ---------------------------------------------------------------------------
# numba, optional
# ---------------------------------------------------------------------------

def _load_numba():
    """Return the numba module, or None when it cannot be imported."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return None
    return numba


def numba_available() -> bool:
    """True when numba can be imported (the compiled path is possible)."""
    return _load_numba() is not None


# ---------------------------------------------------------------------------
# the interpreter (numba, compiled once for every tree)
# ---------------------------------------------------------------------------

_KERNELS: dict = {}
_KERNEL_LOCK = threading.Lock()
#: Seconds spent compiling each kernel ("serial", "parallel", "bin").
COMPILE_SECONDS: dict[str, float] = {}


def _build_kernels(numba):
    njit = numba.njit

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

    def make_run(parallel):
        loop = numba.prange if parallel else range

        @njit(fastmath=False, cache=True, nogil=True, parallel=parallel)
        def run(code, K, nreg, result, pts, starts, flags, out, block, nthreads, rec, X):
            # Bin c holds points starts[c]:starts[c + 1]; its flags row says
            # which operands run.  Tasks take contiguous runs of bins, several
            # per thread so that the scheduler spreads them over the threads.
            nbins = starts.shape[0] - 1
            ntasks = max(1, min(nbins, 8 * nthreads))
            per = (nbins + ntasks - 1) // ntasks
            for t in loop(ntasks):
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
        return run

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

    return make_run, bin_points, bounds_of, unsort


def _kernel(name: str):
    """The compiled kernel `name` ("serial", "parallel", "bin", "bounds" or
    "unsort"), or None when numba is not importable."""
    kernel = _KERNELS.get(name)
    if kernel is not None:
        return kernel
    numba = _load_numba()
    if numba is None:
        return None
    with _KERNEL_LOCK:
        if "factory" not in _KERNELS:
            _KERNELS["factory"] = _build_kernels(numba)
        make_run, bin_points, bounds_of, unsort = _KERNELS["factory"]
        if name not in _KERNELS:
            start = time.perf_counter()
            if name == "bin":
                kernel = bin_points
                kernel(np.zeros((1, 3)), np.zeros(3), np.ones(3), np.ones(3, np.int64), np.zeros(1, np.int32),
                       np.zeros(1, np.int32), np.zeros((1, 3)))
            elif name == "unsort":
                kernel = unsort
                kernel(np.zeros(1), np.zeros(1, np.int32), np.zeros(1))
            elif name == "bounds":
                kernel = bounds_of
                kernel(np.zeros((1, 3)))
            else:
                kernel = make_run(name == "parallel")
                tape = Tape(Difference(Sphere(1.0), Cone(1.0, 1.0), Union(Box(), Torus(1.0, 0.5))))
                _call(kernel, tape, np.zeros((4, 3)))
                _call(kernel, tape, np.zeros((4, 3)), record=True)
            COMPILE_SECONDS[name] = time.perf_counter() - start
            _KERNELS[name] = kernel
    return _KERNELS[name]


#: Points per block of the interpreter (registers stay in the L1/L2 cache).
BLOCK = 256


def _call(kernel, tape: Tape, flat, starts=None, flags=None, nthreads=1, *, record=False, out=None,
          inputs=None):
    """Run `tape` on the contiguous points `flat` (n, 3).

    Without `starts` the points are cut into equal bins with every flag set.
    Returns the values (n,), or with `record` the stored operand values
    ``(tape.nstore, n)`` of the recording tape.
    """
    n = flat.shape[0]
    if inputs is None:
        inputs = tape.inputs(flat)
    if starts is None:
        nb = max(1, min(nthreads * 64, -(-n // BLOCK)))
        starts = np.linspace(0, n, nb + 1).astype(np.int64)
        flags = np.ones((nb, max(1, len(tape.flags))), dtype=np.bool_)
    if out is None:
        out = np.empty(n)
    if record:
        rec = np.empty((tape.nstore, n))
        kernel(tape.record, tape.consts, tape.nreg, tape.result, flat, starts, flags, out, BLOCK, nthreads, rec, inputs)
        return rec
    kernel(tape.code, tape.consts, tape.nreg, tape.result, flat, starts, flags, out, BLOCK, nthreads, _NO_RECORD, inputs)
    return out


_NO_RECORD = np.empty((0, 0))


def _flags(tape: Tape, lo: np.ndarray, hi: np.ndarray, kernel) -> np.ndarray:
    """Pruning flags ``(m, len(tape.flags))`` of the boxes `lo`..`hi`, the
    operand values at their centres from one run of the recording tape."""
    return prune.operand_flags(tape, lo, hi, lambda centres: _call(kernel, tape, centres, record=True))
