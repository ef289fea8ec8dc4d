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

Modules: the tape and its rules are `implicit.evaluate.tape` and
`implicit.evaluate.rules`, binning and pruning decisions `implicit.evaluate.prune`; this
module holds the numba kernels and the public entry points.

Examples
--------
>>> from implicit import sphere, box
>>> from implicit.evaluate.compile import compile_solid
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

import weakref

import numpy as np

from . import prune
from . import rules  # noqa: F401  (the node kinds' rules register themselves)
from .kernels import (COMPILE_SECONDS, _KERNELS, _call, _flags, _kernel, _load_numba,  # noqa: F401
                      numba_available)
from ..solid import Solid, as_points
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
    "SMALL_CALL_MIN_NODES",
]

#: Calls of at least this many points were once needed to compile the interpreter; the fast path
#: now starts at `CACHED_MIN_POINTS` in every process (kept for callers of the name).
AUTO_MIN_POINTS = 100_000
#: Calls from this size take the fast path
#: (the tape beats numpy from a few hundred points).
CACHED_MIN_POINTS = 2048
#: Trees of at least this many nodes take the fast path from one point: numpy pays
#: 5-10 us a node a call whatever the points (the 540-capsule lattice: 5.5 ms for one point,
#: 13 ms for 512, against the tape's 0.05 and 1.2 ms; the 51-node gear 0.34 ms against 0.013),
#: the tape about 10 us a call once built (80 ms for the lattice's 543 nodes, once per solid).
SMALL_CALL_MIN_NODES = 32
#: Per-bin pruning (binning, bounds per bin) pays from about this size
#: (bin sizes: `implicit.evaluate.prune.POINTS_PER_BIN`).
PRUNE_MIN_POINTS = 8192


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


# Node counts by id of the solid (as `_COMPILED`): a small call asks for it every time.
_NODES: dict[int, tuple[weakref.ref, int]] = {}


def _nodes(solid: Solid) -> int:
    """Number of nodes of `solid` (counted once per solid)."""
    entry = _NODES.get(id(solid))
    if entry is not None and entry[0]() is solid:
        return entry[1]
    count = solid.count_nodes()
    key = id(solid)

    def forget(_ref, key=key, table=_NODES):
        entry = table.get(key)
        if entry is not None and entry[0] is _ref:
            del table[key]
    _NODES[key] = (weakref.ref(solid, forget), count)
    return count


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
    >>> from implicit.evaluate.compile import compile_solid
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

    A call takes the compiled path from `CACHED_MIN_POINTS` points, or from
    one point on a tree of `SMALL_CALL_MIN_NODES` nodes or more, loading the
    interpreter (from numba's disk cache) on first use.  The choice depends
    on the call and the tree alone, never on what the process ran before:
    numpy and the tape may round differently, and the same solid must give
    the same values -- and the same mesh -- in every process.
    """
    n = flat.shape[0]
    if n < CACHED_MIN_POINTS and (n == 0 or _nodes(solid) < SMALL_CALL_MIN_NODES):
        return None
    compiled = compile_solid(solid, warm=False)
    if compiled.backend != "numba":
        return None
    return compiled.evaluate_flat(flat)
