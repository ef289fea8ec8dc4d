"""The tape of a CSG tree: elementary operations on registers of points.

`Tape(solid)` flattens a tree into rows ``(opcode, destination, operands,
constant index)`` that the numba interpreter of `implicit.evaluate.compile` runs on
blocks of points.  Every node class has a *rule* (`RULES`, filled by
`implicit.evaluate.rules`) that emits its operations through `KernelSource`;
registers are reused after their last use.  Operands of unions,
intersections and differences are wrapped in *skips* that pruning switches
per bin, and their values are *stored* by a second form of the tape run at
bin centres to bound them (`implicit.evaluate.prune`).  A node of a kind without a
rule becomes an *input* column computed by its own numpy code.

Examples
--------
>>> from implicit import sphere, box
>>> from implicit.evaluate.tape import Tape
>>> tape = Tape(sphere(1.0) - box(0.5))
>>> len(tape), len(tape.flags), tape.nreg   # fill, 2 skips, hyp3, subk, max, box, maxneg
(8, 2, 6)
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..solid import Solid

__all__ = ["Tape", "KernelSource", "OPS", "RULES", "PRUNE_MODES", "register_rule", "Unsupported"]


class Unsupported(Exception):
    """A node kind without a rule: the tree is evaluated by plain numpy."""


#: Elementary operations of the tape: name -> (opcode, operand signature).
#: Signature letters: ``r`` a register (a value per point), ``k`` a constant.
OPS = {
    "add": (0, "rr"), "sub": (1, "rr"), "mul": (2, "rr"), "div": (3, "rr"),
    "min": (4, "rr"), "max": (5, "rr"),
    "addk": (6, "rk"), "subk": (7, "rk"), "mulk": (8, "rk"), "divk": (9, "rk"),
    "mink": (10, "rk"), "maxk": (11, "rk"), "ksub": (12, "rk"),
    "neg": (13, "r"), "abs": (14, "r"), "sqrt": (15, "r"),
    "madk": (16, "rrk"),     # a * k + b
    "hyp2": (17, "rr"),      # sqrt(a*a + b*b)
    "hyp3": (18, "rrr"),     # sqrt(a*a + b*b + c*c)
    "fill": (19, "k"),
    "selneg": (20, "rk"),    # K[k] where a < 0 else K[k + 1]
    "negif2": (21, "rrr"),   # -a where b < 0 and c < 0 else a
    "sqrtmin": (22, "rrrr"),  # sqrt(min(a*a + b*b, c*c + d*d))
    "maxneg": (23, "rr"),    # max(a, -b)
    "store": (24, "r"),      # record a (the value of an operand, for pruning)
    "cylinder": (25, "rrrk"),  # capped cylinder: local x, y, z; K[k] radius, K[k+1] half height
    "box": (26, "rrrk"),     # box: offsets x, y, z; K[k..k+2] half sizes, K[k+3] rounding
    "input": (27, ""),       # a column of values computed by numpy (a kind without a rule)
}
_SKIP = 99
_STORE = 24
_INPUT = 27
_NCOL = 7  # opcode, dst, a, b, c, d, k


class KernelSource:
    """Collects the tape of one tree: elementary operations on registers.

    Rules call `const` for every number they read from a node, `op` to append
    an operation (returning its result register), `node` to emit a child and
    `open_flag` / `close_flag` around an operand that pruning may skip.
    Registers 0, 1, 2 hold x, y, z.
    """

    def __init__(self, *, prune: bool = True):
        self.prune = prune
        self.consts: list[float] = []
        self.code: list[list[int]] = []
        self.nreg = 3
        #: For every pruning flag: (node, operand index, frame) in emission
        #: order; `frame` is ``(matrix, offset)`` mapping world points to the
        #: node's coordinates, or None when they are not an affine image.
        self.flags: list[tuple[Solid, int, tuple | None]] = []
        self._open: list[int] = []
        self._frames: dict[tuple, tuple] = {(0, 1, 2): (np.eye(3), np.zeros(3))}
        self._coords: list[tuple] = []
        # Nodes being emitted: [node, operands emitted so far, stores of them].
        self._stack: list[list] = []
        #: Prunable nodes emitted: (node, frame, store slot of each operand,
        #: [(operand index, flag column)]).
        self.groups: list[tuple[Solid, tuple | None, list[int], list]] = []
        self.nstore = 0
        # numpy maps from world points to coordinates, for kinds without a rule.
        self._maps: dict[tuple, tuple] = {(0, 1, 2): ()}
        #: Nodes of kinds without a rule, evaluated by numpy into input
        #: columns: (node, maps from world points to its coordinates).
        self.opaque: list[tuple[Solid, tuple]] = []

    def const(self, value) -> int:
        """Index of the constant `value`."""
        self.consts.append(float(value))
        return len(self.consts) - 1

    def consts_of(self, values) -> list[int]:
        """Constant indices of every float of `values` (flattened)."""
        return [self.const(v) for v in np.asarray(values, dtype=np.float64).ravel()]

    def reg(self) -> int:
        """A fresh register."""
        self.nreg += 1
        return self.nreg - 1

    def op(self, name: str, *args, into: int | None = None) -> int:
        """Append operation `name` on `args` (registers / constant indices).

        Writes a fresh register, or `into` (for accumulators); returns it.
        """
        opcode, sig = OPS[name]
        if len(args) != len(sig):
            raise ValueError(f"{name}: expected {len(sig)} operands, got {len(args)}")
        row = [opcode, self.reg() if into is None else into, -1, -1, -1, -1, -1]
        regs = [a for a, s in zip(args, sig) if s == "r"]
        row[2:2 + len(regs)] = regs
        if "k" in sig:
            row[6] = args[sig.index("k")]
        self.code.append(row)
        return row[1]

    def node(self, node: Solid, coords: tuple[int, int, int]) -> int:
        """Emit `node` evaluated at `coords`; return its register."""
        rule = RULES.get(type(node))
        if rule is None:
            if self._maps.get(tuple(coords)) is None:
                raise Unsupported(type(node).__name__)
            rule = _opaque
        parent = self._stack[-1] if self._stack else None
        entry = [node, 0, [], []]
        if type(node) in PRUNE_MODES and self.prune:
            self.groups.append((node, self._frames.get(tuple(coords)), entry[2], entry[3]))
        self._coords.append(tuple(coords))
        self._stack.append(entry)
        try:
            result = rule(node, self, tuple(coords))
        finally:
            self._coords.pop()
            self._stack.pop()
        if parent is not None and type(parent[0]) in PRUNE_MODES and self.prune:
            # Record the operand's value: bounds per bin come from these
            # values at the bins' centres (the tape run without skips).
            row = [OPS["store"][0], -1, result, self.nstore, -1, -1, -1]
            self.code.append(row)
            parent[2].append(self.nstore)
            self.nstore += 1
        return result

    def frame(self, coords) -> tuple | None:
        """``(matrix, offset)`` with ``coords = matrix @ p + offset`` for world
        points ``p``, or None when `coords` are no known affine image."""
        return self._frames.get(tuple(coords))

    def map_points(self, coords, parent, func) -> None:
        """Declare how numpy computes `coords` from the `parent` coordinates:
        ``func((n, 3) array) -> (n, 3) array``, the same arithmetic as the
        node's ``_evaluate``.  Nodes of kinds without a rule below it are then
        evaluated by numpy as inputs of the tape (else the whole tree is)."""
        chain = self._maps.get(tuple(parent))
        if chain is not None and tuple(coords) != tuple(parent):
            self._maps[tuple(coords)] = chain + (func,)

    def set_frame(self, coords, matrix, offset) -> None:
        """Declare `coords` the affine image ``matrix @ p + offset`` of world
        points (pruning below a rule that maps coordinates needs it; without
        it operands below are never pruned, which is always correct)."""
        self._frames[tuple(coords)] = (np.asarray(matrix, dtype=np.float64),
                                       np.asarray(offset, dtype=np.float64))

    def open_flag(self, node: Solid, index: int) -> None:
        """Start the operations of operand `index` of `node`, skipped in bins
        where pruning finds that operand cannot change the result."""
        if self.prune:
            coords = self._coords[-1] if self._coords else (0, 1, 2)
            self.flags.append((node, index, self._frames.get(coords)))
            if self._stack and self._stack[-1][0] is node:
                self._stack[-1][3].append((index, len(self.flags) - 1))
            self.code.append([_SKIP, -1, len(self.flags) - 1, -1, -1, -1, -1])
        self._open.append(len(self.code) - 1)

    def close_flag(self) -> None:
        """End the operand opened last (the skip jumps here)."""
        at = self._open.pop()
        if self.prune:
            self.code[at][3] = len(self.code)


#: Fast-path rules by node class: ``rule(node, gen, coords) -> register``.
RULES: dict[type, Callable[[Solid, KernelSource, tuple], int]] = {}

#: How pruning treats the operands of a node class: "min" (union), "max"
#: (intersection), "diff" (difference), "smin" / "smax" / "sdiff" (smooth).
PRUNE_MODES: dict[type, str] = {}


def register_rule(cls: type, *, prune: str | None = None):
    """Decorator: make `func` the fast-path rule for node class `cls`.

    Parameters
    ----------
    cls : type
        A `Solid` subclass.
    prune : {"min", "max", "diff", "smin", "smax", "sdiff"}, optional
        How operands of this node may be dropped per bin (such rules wrap
        every prunable operand in `KernelSource.open_flag` / `close_flag`).

    Notes
    -----
    A rule must compute what the node's ``_evaluate`` computes, in the same
    order of floating-point operations where it can (tests hold the two to
    1e-12).  A rule that evaluates a child at new coordinates declares them
    with `KernelSource.set_frame` when they are an affine image of the
    parent's (otherwise pruning stays off below it) and with
    `KernelSource.map_points` (otherwise a kind without a rule below it sends
    the whole tree to numpy).  Pruning trusts every node's `lipschitz`.

    Examples
    --------
    A rule for a node ``Ball`` with attributes ``_c`` (3,) and ``_r``:

    >>> def _ball(node, gen, coords):
    ...     c = gen.consts_of(node._c)
    ...     d = [gen.op("subk", coords[i], c[i]) for i in range(3)]
    ...     return gen.op("subk", gen.op("hyp3", *d), gen.const(node._r))
    """
    if not (isinstance(cls, type) and issubclass(cls, Solid)):
        raise TypeError(f"cls: expected a Solid subclass, got {cls!r}")
    if prune not in (None, "min", "max", "diff", "smin", "smax", "sdiff"):
        raise ValueError(f"prune: expected one of min, max, diff, smin, smax, sdiff or None, got {prune!r}")

    def deco(func):
        RULES[cls] = func
        if prune is not None:
            PRUNE_MODES[cls] = prune
        else:
            PRUNE_MODES.pop(cls, None)
        return func
    return deco


def _opaque(node, gen, coords):
    """A node without a rule: its values come in as a column computed by the
    node's own ``_evaluate`` at the coordinates numpy would give it."""
    reg = gen.reg()
    gen.code.append([_INPUT, reg, -1, len(gen.opaque), -1, -1, -1])
    gen.opaque.append((node, gen._maps[tuple(coords)]))
    return reg


def _allocate(code: np.ndarray, result: int):
    """Linear-scan register allocation: reuse a register after its last use.

    Skips only jump forward over whole operands, and a value live across a
    skipped range has an interval covering it, so the intervals in program
    order are a valid liveness.
    """
    n = len(code)
    first: dict[int, int] = {0: -1, 1: -1, 2: -1}
    last: dict[int, int] = {result: n}
    for pc, row in enumerate(code):
        if row[0] == _SKIP:
            continue
        if row[0] == _STORE:
            last[int(row[2])] = max(last.get(int(row[2]), pc), pc)
            continue
        if row[0] == _INPUT:
            last[int(row[1])] = max(last.get(int(row[1]), pc), pc)
            continue
        for r in row[2:6]:
            if r >= 0:
                last[r] = max(last.get(r, pc), pc)
        first.setdefault(int(row[1]), pc)
        last[int(row[1])] = max(last.get(int(row[1]), pc), pc)
    ends: dict[int, list[int]] = {}
    for r, pc in last.items():
        ends.setdefault(pc, []).append(r)
    mapping = {0: 0, 1: 1, 2: 2}
    free: list[int] = []
    top = 3
    out = code.copy()
    for pc, row in enumerate(code):
        if row[0] == _STORE:
            out[pc, 2] = mapping[int(row[2])]
        elif row[0] != _SKIP:
            if row[0] != _INPUT:
                for j in range(2, 6):
                    if row[j] >= 0:
                        out[pc, j] = mapping[int(row[j])]
            dst = int(row[1])
            if dst not in mapping:
                if free:
                    mapping[dst] = free.pop()
                else:
                    mapping[dst] = top
                    top += 1
            out[pc, 1] = mapping[dst]
        for r in ends.get(pc, ()):
            if r > 2 and r in mapping and r != result:
                free.append(mapping[r])
    return out, mapping[result] if result in mapping else result, top


class Tape:
    """The compiled form of a tree for the interpreter.

    Attributes
    ----------
    code : (k, 7) int64
        Operations (opcode, destination, operands, constant index) with a
        skip before every prunable operand.
    record : (k', 7) int64
        The same without skips, storing the operands of prunable nodes (run
        at bin centres to bound them).
    consts : (c,) float64
    flags : list of (node, operand index, frame)
        The pruning flags in the order of the skips.
    groups : list of (node, frame, store slots)
        Prunable nodes with the store slot of each operand.
    group_bounds : list of (float, (c, 1) float) or None
        For each group whose operands are all stored and lie in a known
        frame: the spectral norm of the frame's linear part and the operands'
        Lipschitz constants (the factors of their bounds over a box); None
        for the others.
    opaque : list of (node, maps)
        Nodes of kinds without a rule, read as input columns.
    input_flags : list of (f,) int64
        For every input, the flags whose skips enclose it.
    """

    __slots__ = ("code", "record", "consts", "flags", "groups", "group_bounds", "result", "nreg", "nstore",
                 "opaque", "input_flags")

    def __init__(self, solid: Solid, *, prune: bool = True):
        gen = KernelSource(prune=prune)
        result = gen.node(solid, (0, 1, 2))
        code = np.array(gen.code, dtype=np.int64).reshape(-1, _NCOL)
        code, self.result, self.nreg = _allocate(code, result)
        self.consts = np.array(gen.consts + [0.0], dtype=np.float64)
        self.flags = gen.flags
        self.groups = gen.groups
        # Once per tape: every pruned evaluation bounds the same groups, and
        # the spectral norm is an SVD.
        self.group_bounds = [
            None if frame is None or len(slots) != len(node.children)
            else (float(np.linalg.norm(frame[0], 2)), np.array([c.lipschitz for c in node.children])[:, None])
            for node, frame, slots, _ in self.groups]
        self.nstore = gen.nstore
        self.opaque = gen.opaque
        self.code = _drop(code, _STORE)
        self.record = _drop(code, _SKIP)
        # The flags whose skips enclose each input (all set: the input is read).
        self.input_flags = [np.zeros(0, np.int64) for _ in self.opaque]
        open_skips: list[tuple[int, int]] = []
        for pc, row in enumerate(self.code):
            while open_skips and open_skips[-1][1] <= pc:
                open_skips.pop()
            if row[0] == _SKIP:
                open_skips.append((int(row[2]), int(row[3])))
            elif row[0] == _INPUT:
                self.input_flags[int(row[3])] = np.array([f for f, _ in open_skips], dtype=np.int64)

    def inputs(self, points: np.ndarray, starts=None, active=None) -> np.ndarray:
        """Input columns ``(len(opaque), n)`` at `points` (n, 3): each node's
        own evaluation at the coordinates numpy's evaluation gives it.

        With bins (`starts`, `active` flags) a column is filled only in the
        bins where its node is reached (elsewhere it is 0 and never read).
        """
        if not self.opaque:
            return _NO_INPUT
        n = points.shape[0]
        cols = np.zeros((len(self.opaque), n))
        for i, (node, maps) in enumerate(self.opaque):
            rows = slice(None)
            if active is not None and len(self.input_flags[i]):
                need = active[:, self.input_flags[i]].all(axis=1)
                if not need.any():
                    continue
                rows = np.repeat(need, np.diff(starts))
            q = points[rows]
            for func in maps:
                q = func(q)
            cols[i, rows] = _numpy_evaluate(node, np.ascontiguousarray(q))
        return cols

    def __len__(self) -> int:
        return len(self.code)


def _drop(code: np.ndarray, opcode: int) -> np.ndarray:
    """`code` without the rows of `opcode`, skip targets renumbered."""
    keep = code[:, 0] != opcode
    newpos = np.concatenate([[0], np.cumsum(keep)])
    out = code[keep].copy()
    skips = out[:, 0] == _SKIP
    out[skips, 3] = newpos[out[skips, 3]]
    return out


def _numpy_evaluate(solid: Solid, flat: np.ndarray) -> np.ndarray:
    """The plain numpy evaluation (chunked as `Solid.__call__` does)."""
    from ..solid import EVAL_CHUNK
    n = flat.shape[0]
    if n <= EVAL_CHUNK:
        return np.asarray(solid._evaluate(flat), dtype=np.float64)
    out = np.empty(n)
    for start in range(0, n, EVAL_CHUNK):
        out[start:start + EVAL_CHUNK] = solid._evaluate(flat[start:start + EVAL_CHUNK])
    return out


_NO_INPUT = np.empty((0, 0))
