"""Fast evaluation of CSG trees: a numba interpreter of a tape of elementary
operations, pruned per spatial bin of points.

The plain evaluation of a tree (``solid(points)`` in numpy) makes a temporary
array per operation per chunk; a 50-node tree runs at about 0.5 M points/s.
This module instead

1. **flattens** the tree into a *tape*: elementary operations (``sub``,
   ``hyp2`` = sqrt(a^2 + b^2), ``min``, ...; fused ones for boxes and
   cylinders) on registers, each register a block of 256 points, the nodes'
   parameters as constants.  Every node class has a *rule* in `RULES` that
   emits its operations; registers are reused after their last use (the
   50-node bench plate: 447 operations on 10 registers);
2. **interprets** the tape with one numba kernel compiled once per process
   for every tree (no compilation per tree: the tape of a 50-node tree takes
   about 5 ms to build); each operation is a short loop over the block,
   which the compiler turns into SIMD code;
3. **prunes** per bin: the points are sorted into a grid of bins (a counting
   sort), and for every bin the operands of unions, intersections and
   differences (sharp or smooth) that cannot change the result anywhere in
   the bin's box are skipped.  A bin near one hole evaluates that hole and the
   plate, not the 49 other nodes (about 43 of 447 operations a point).  The
   decision uses conservative bounds: an operand's value at the bin's centre
   (all centres in one run of the tape) plus or minus its Lipschitz constant
   times the half-diagonal, in the operand's own coordinates; a smooth operand
   is skipped only beyond the blend radius.  Pruned results equal the full
   evaluation up to rounding (1e-15 relative).

An earlier design generated one fused Python loop per tree for numba: it ran
the 50-node plate at 2.3 M points/s and took 11 s to compile per tree; the
tape runs it at 7.6 M/s unpruned and 21 M/s pruned (23 near the surface) on
one core, 33 on two (numpy: 0.60), after 3 s of compilation once per process
(``bench/bench_eval.py``).

Node kinds join the fast path by a rule, keyed by node class (see
`register_rule`).  A node of a kind without a rule (a polyhedron, a sweep, a
grid) is evaluated by its own numpy code as an *input column* of the tape, at
the coordinates numpy's evaluation gives it and only in the bins where the
tape reads it (the plate with a rotated wedge added: 0.47 -> 8.4 M/s); when a
rule above it maps coordinates without saying how numpy does it, the whole
tree is evaluated by plain numpy, as is every tree when numba is not
importable.  Which path ``solid(points)`` takes: `fast_evaluate`.

Modules: the tape and its rules are `implicit.tape` and
`implicit.tape_rules`, binning and pruning decisions `implicit.prune`; this
module holds the numba kernels and the public entry points.

Examples
--------
>>> from implicit import sphere, box
>>> from implicit.compile import compile_solid
>>> part = sphere(1.0) - box(0.5)
>>> fast = compile_solid(part)
>>> float(fast([[0.0, 0.0, 0.9]])[0])
-0.09999999999999998

References
----------
M. Keeter, "Massively Parallel Rendering of Complex Closed-Form Implicit
Surfaces", ACM Trans. Graph. 39(4), 2020, doi:10.1145/3386569.3392429
(a tape of the CSG expression, pruned per spatial region).
"""

from __future__ import annotations

import math
import threading
import time
import weakref

import numpy as np

from . import prune
from .csg import Difference, Union
from .primitives import Box, Cone, Sphere, Torus
from .solid import Solid, as_points
from .tape import (OPS, PRUNE_MODES, RULES, KernelSource, Tape, Unsupported,  # noqa: F401
                   _numpy_evaluate, register_rule)

__all__ = [
    "CompiledSolid",
    "KernelSource",
    "RULES",
    "register_rule",
    "compile_solid",
    "fast_evaluate",
    "supports",
    "numba_available",
    "AUTO_MIN_POINTS",
    "CACHED_MIN_POINTS",
    "PRUNE_MIN_POINTS",
]

#: ``solid(points)`` compiles the interpreter (2-3 s, once per process) for a
#: call of at least this many points.
AUTO_MIN_POINTS = 100_000
#: Once the interpreter is compiled, calls from this size take the fast path
#: (the tape beats numpy from a few hundred points).
CACHED_MIN_POINTS = 2048
#: Per-bin pruning (binning, bounds per bin) pays from about this size
#: (bin sizes: `implicit.prune.POINTS_PER_BIN`).
PRUNE_MIN_POINTS = 8192


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


# ---------------------------------------------------------------------------
# the compiled solid
# ---------------------------------------------------------------------------

class CompiledSolid:
    """A solid with a compiled, per-bin pruned evaluation.

    Call it like the solid: ``compiled(points) -> values``.  When numba is
    missing, or a node kind without a fast-path rule lies below coordinates
    that no rule maps for numpy, it evaluates with plain numpy (`backend`
    says which).

    Attributes
    ----------
    solid : Solid
        The tree.
    backend : {"numba", "numpy"}
    parallel : bool
        Use every core of numba's thread pool: a pruned evaluation gives
        each thread its share of the points to bin and evaluate, an unpruned
        one runs the interpreter with ``prange`` over blocks.
    tape : Tape or None
        Operations, constants and pruning flags of the tree.
    """

    def __init__(self, solid: Solid, *, parallel: bool = False):
        if not isinstance(solid, Solid):
            raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
        self.solid = solid
        self.parallel = bool(parallel)
        self.tape = None
        self.backend = "numpy"
        if _load_numba() is None:
            return
        try:
            self.tape = Tape(solid)
        except Unsupported:
            return
        self.backend = "numba"

    @property
    def nthreads(self) -> int:
        if not self.parallel:
            return 1
        return int(_load_numba().get_num_threads())

    def warm(self) -> "CompiledSolid":
        """Compile the interpreter and the binning kernel now; return self."""
        if self.backend == "numba":
            _kernel("serial")
            if self.parallel:
                _kernel("parallel")
            _kernel("bin")
            _kernel("bounds")
            _kernel("unsort")
        return self

    def __call__(self, points, *, prune: bool | None = None) -> np.ndarray:
        """Signed distances at `points` (..., 3) -> (...).

        `prune` forces per-bin pruning on or off; by default it is used from
        `PRUNE_MIN_POINTS` points.
        """
        pts = as_points(points)
        shape = pts.shape[:-1]
        flat = np.ascontiguousarray(pts.reshape(-1, 3))
        return self.evaluate_flat(flat, prune=prune).reshape(shape)

    def evaluate_flat(self, flat: np.ndarray, *, prune: bool | None = None) -> np.ndarray:
        """Values at a contiguous ``(n, 3)`` float64 array (no validation)."""
        n = flat.shape[0]
        if self.backend != "numba" or n == 0:
            return _numpy_evaluate(self.solid, flat)
        if prune is None:
            prune = n >= PRUNE_MIN_POINTS
        if not prune or not self.tape.flags or n >= 2**31:
            kernel = _kernel("parallel" if self.parallel else "serial")
            return _call(kernel, self.tape, flat, nthreads=self.nthreads)
        threads = self.nthreads
        if threads > 1 and n >= 2 * PRUNE_MIN_POINTS:
            # Every thread bins and evaluates its own share of the points
            # (the kernels release the GIL), so binning runs in parallel too.
            from concurrent.futures import ThreadPoolExecutor
            cuts = np.linspace(0, n, threads + 1).astype(np.int64)
            out = np.empty(n)

            def work(i):
                out[cuts[i]:cuts[i + 1]] = self._pruned(flat[cuts[i]:cuts[i + 1]])
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(work, range(threads)))
            return out
        return self._pruned(flat)

    def _pruned(self, flat: np.ndarray) -> np.ndarray:
        """Binned, pruned evaluation of `flat` on the calling thread."""
        n = flat.shape[0]
        kernel = _kernel("serial")
        lo, hi = _kernel("bounds")(flat)
        grid = prune.grid(lo, hi, n)
        if grid is None:
            return _call(kernel, self.tape, flat)
        g, scale = grid
        with prune.Workspace(n) as (cell, order, sorted_pts, values):
            starts, box_lo, box_hi = _kernel("bin")(flat, lo, scale, g, cell, order, sorted_pts)
            active = _flags(self.tape, box_lo, box_hi, kernel)
            inputs = self.tape.inputs(sorted_pts, starts, active)
            _call(kernel, self.tape, sorted_pts, starts, active, out=values, inputs=inputs)
            out = np.empty(n)
            _kernel("unsort")(values, order, out)
            return out

    def __repr__(self) -> str:
        return (f"CompiledSolid({self.solid.kind}, nodes={self.solid.count_nodes()}, "
                f"backend={self.backend!r}, parallel={self.parallel})")


def supports(solid: Solid) -> bool:
    """True when every node of `solid` has a fast-path rule."""
    return all(type(node) in RULES for node in solid.walk())


# Compiled trees by (id of the solid, parallel); entries leave with their solid.
# (Solids refuse ==, so they cannot key a WeakKeyDictionary.)
_COMPILED: dict[tuple[int, bool], tuple[weakref.ref, "CompiledSolid"]] = {}


def _cached(solid: Solid, parallel: bool):
    entry = _COMPILED.get((id(solid), parallel))
    if entry is not None and entry[0]() is solid:
        return entry[1]
    return None


def _store(solid: Solid, parallel: bool, compiled: "CompiledSolid") -> None:
    key = (id(solid), parallel)

    def forget(_ref, key=key, table=_COMPILED):
        entry = table.get(key)
        if entry is not None and entry[0] is _ref:
            del table[key]
    _COMPILED[key] = (weakref.ref(solid, forget), compiled)


def compile_solid(solid: Solid, *, parallel: bool = False, warm: bool = True) -> CompiledSolid:
    """Compile `solid` into a pruned tape for the numba interpreter.

    Parameters
    ----------
    solid : Solid
        Any tree (see `CompiledSolid` for kinds without a rule).
    parallel : bool, keyword-only
        Use every core (see `CompiledSolid`).
    warm : bool, keyword-only
        Compile the interpreter now rather than on the first call.

    Returns
    -------
    CompiledSolid
        Callable ``(..., 3) -> (...)``, equal to ``solid(points)`` up to
        rounding (1e-12).  The interpreter is compiled once per process for
        every tree; a tree only costs its tape (about 5 ms for 50 nodes).

    Examples
    --------
    >>> from implicit import sphere
    >>> from implicit.compile import compile_solid
    >>> float(compile_solid(sphere(2.0))([[3.0, 0.0, 0.0]])[0])
    1.0
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    compiled = _cached(solid, bool(parallel))
    if compiled is None:
        compiled = CompiledSolid(solid, parallel=parallel)
        _store(solid, bool(parallel), compiled)
    if warm:
        compiled.warm()
    return compiled


def fast_evaluate(solid: Solid, flat: np.ndarray):
    """The automatic fast path behind `Solid.__call__`, or None to use numpy.

    A call takes the compiled path from `AUTO_MIN_POINTS` points (compiling
    the interpreter on first use), or from `CACHED_MIN_POINTS` points once
    the interpreter is compiled.
    """
    n = flat.shape[0]
    if n < CACHED_MIN_POINTS:
        return None
    if n < AUTO_MIN_POINTS and "serial" not in _KERNELS:
        return None
    compiled = compile_solid(solid, warm=False)
    if compiled.backend != "numba":
        return None
    return compiled.evaluate_flat(flat)
