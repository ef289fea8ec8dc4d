"""The `Solid` expression node: the function representation of a solid.

A solid is a signed distance field ``f: R^3 -> R``: negative inside, zero on the
boundary, positive outside.  Every node of a CSG tree is an immutable `Solid`
that knows

* how to evaluate itself on an array of points (``solid(points)``),
* a conservative axis-aligned box holding its interior (``solid.bounds``),
* a conservative range of its values over many boxes at once
  (``solid.value_bounds(lo, hi)``), which lets cells be classified FULL, EMPTY
  or BOUNDARY without dense sampling,
* its children, so that the tree can be walked, printed and serialised.

Fields are either *exact* signed distances or conservative *bounds*: a bound
has the right sign everywhere and never overestimates the distance to the
boundary in magnitude (``|f(p)| <= dist(p, boundary)``).  Both are Lipschitz
with the constant `lipschitz` (1 for exact distances and for the CSG of exact
distances).
"""

from __future__ import annotations

import numbers
from typing import Any, Callable, Iterator

import numpy as np

__all__ = [
    "Solid",
    "as_points",
    "as_vector",
    "as_positive",
    "as_finite",
    "INFINITE_BOUNDS",
    "box_corners",
    "unit",
]

#: Bounds of a solid that fills space without limit.
INFINITE_BOUNDS = (np.full(3, -np.inf), np.full(3, np.inf))

# Points are evaluated in chunks of this many rows: temporaries of a chunk stay
# in the processor's cache instead of streaming whole arrays through memory
# (bench/bench_eval.py, 50-node plate: 0.60 M points/s at 16384 rows, the wall
# speed of 32768 at half the CPU time: numpy's matrix products of the larger
# chunks ran on two threads).
EVAL_CHUNK = 16384

# Calls with at least this many points may take the compiled fast path
# (implicit.evaluate.fast_evaluate decides; it needs numba).  Smaller calls on a
# tree of inner nodes ask it too: a large tree takes it from one point.
FAST_PATH_MIN_POINTS = 2048


# ---------------------------------------------------------------------------
# validation helpers shared by every module of the package
# ---------------------------------------------------------------------------

def as_points(points: Any, name: str = "points") -> np.ndarray:
    """Return `points` as a float64 array of shape ``(..., 3)``.

    Raises
    ------
    TypeError
        When `points` is not numeric.
    ValueError
        When the last axis is not of length 3 or a value is NaN.
    """
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected an array of shape (..., 3) of numbers, got {type(points).__name__}") from exc
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name}: expected an array of shape (..., 3), got shape {arr.shape}")
    if np.isnan(arr).any():
        raise ValueError(f"{name}: expected numbers, got NaN")
    return arr


def as_vector(value: Any, name: str, *, size: int = 3, nonzero: bool = False) -> np.ndarray:
    """Return `value` as a finite float64 vector of length `size`."""
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name}: expected {size} numbers, got {value!r}")
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected {size} numbers, got {value!r}") from exc
    if arr.ndim == 0:
        arr = np.full(size, float(arr))
    if arr.shape != (size,):
        raise ValueError(f"{name}: expected {size} numbers, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name}: expected finite numbers, got {arr.tolist()}")
    if nonzero and not np.any(arr):
        raise ValueError(f"{name}: expected a nonzero vector, got {arr.tolist()}")
    return arr


def unit(vector: np.ndarray) -> np.ndarray:
    """`vector` / |vector|, left as it is when already of unit length, so
    that normalising a stored (normalised) vector again gives the same bits."""
    length = float(np.linalg.norm(vector))
    return vector if abs(length - 1.0) <= 4e-16 else vector / length


def as_finite(value: Any, name: str) -> float:
    """Return `value` as a finite float, or raise naming `name`."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected a number, got {value!r}")
    out = float(value)
    if not np.isfinite(out):
        raise ValueError(f"{name}: expected a finite number, got {value!r}")
    return out


def as_positive(value: Any, name: str, *, allow_zero: bool = False) -> float:
    """Return `value` as a positive finite float, or raise naming `name`."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected a positive number, got {value!r}")
    out = float(value)
    if not np.isfinite(out) or out < 0 or (out == 0 and not allow_zero):
        kind = "a non-negative" if allow_zero else "a positive"
        raise ValueError(f"{name}: expected {kind} number, got {value!r}")
    return out


def box_corners(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Return the 8 corners of each box, shape ``(..., 8, 3)``."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    sel = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)], dtype=bool)
    return np.where(sel, hi[..., None, :], lo[..., None, :])


# ---------------------------------------------------------------------------
# the node
# ---------------------------------------------------------------------------

class Solid:
    """An immutable node of a CSG expression tree.

    Subclasses implement `_evaluate` on a ``(n, 3)`` float64 array and set
    `bounds`; they may override `_value_bounds` with something tighter than
    the Lipschitz bound.

    Parameters
    ----------
    children : tuple of Solid
        Operands of this node (empty for primitives).
    params : dict
        The node's own parameters, as plain Python values; they make the
        `repr`, the printed tree and the JSON form.
    bounds : (lo, hi)
        Conservative axis-aligned box holding the interior; may be infinite.
    exact : bool
        True when the field is an exact signed distance, False when it is a
        conservative bound.
    lipschitz : float
        Lipschitz constant of the field.

    Examples
    --------
    >>> from implicit import sphere, box
    >>> part = sphere(1.0) & box(1.5)
    >>> float(part([[0.0, 0.0, 0.0]])[0])
    -0.75
    """

    kind: str = "solid"
    __slots__ = ("_children", "_params", "_bounds", "_exact", "_lipschitz", "__weakref__")

    #: Every concrete node class by its `kind`, for deserialisation.
    registry: dict = {}

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        kind = cls.__dict__.get("kind")
        if kind is not None:
            Solid.registry[kind] = cls

    @classmethod
    def from_params(cls, children, params):
        """Rebuild a node of this class from its children and `params`.

        The default suits operators (``cls(*children, **params)``) and
        primitives (``cls(**params)``); classes whose constructor differs
        override it.
        """
        return cls(*children, **params)

    def __init__(self, children=(), params=None, bounds=INFINITE_BOUNDS, *, exact=False, lipschitz=1.0):
        for i, child in enumerate(children):
            if not isinstance(child, Solid):
                raise TypeError(f"{self.kind}: operand {i} must be a Solid, got {type(child).__name__}")
        lo, hi = (np.array(b, dtype=np.float64).reshape(3) for b in bounds)
        lo.flags.writeable = False
        hi.flags.writeable = False
        object.__setattr__(self, "_children", tuple(children))
        object.__setattr__(self, "_params", dict(params or {}))
        object.__setattr__(self, "_bounds", (lo, hi))
        object.__setattr__(self, "_exact", bool(exact))
        object.__setattr__(self, "_lipschitz", float(lipschitz))

    # -- immutability and identity ------------------------------------------------
    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is immutable; operations return new solids")

    def __delattr__(self, name):
        raise AttributeError(f"{type(self).__name__} is immutable")

    def __bool__(self):
        raise TypeError("the truth value of a Solid is ambiguous; evaluate it on points instead")

    def __eq__(self, other):
        raise TypeError("Solids are not compared with ==; use 'a is b' or compare their JSON")

    __hash__ = object.__hash__

    # -- properties ---------------------------------------------------------------
    @property
    def children(self) -> tuple:
        """Operands of this node."""
        return self._children

    @property
    def params(self) -> dict:
        """A copy of this node's own parameters."""
        return dict(self._params)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Conservative axis-aligned bounds ``(lo, hi)`` of the interior."""
        return self._bounds

    @property
    def is_bounded(self) -> bool:
        """True when `bounds` are finite."""
        lo, hi = self._bounds
        return bool(np.isfinite(lo).all() and np.isfinite(hi).all())

    @property
    def is_empty_bounds(self) -> bool:
        """True when the bounds enclose nothing (an empty solid)."""
        lo, hi = self._bounds
        return bool(np.any(lo > hi))

    @property
    def exact(self) -> bool:
        """True when the field is an exact signed distance (else a bound)."""
        return self._exact

    @property
    def lipschitz(self) -> float:
        """Lipschitz constant of the field."""
        return self._lipschitz

    def require_bounds(self, bounds=None) -> tuple[np.ndarray, np.ndarray]:
        """Finite bounds ``(lo, hi)`` for a decomposition of this solid.

        Parameters
        ----------
        bounds : ((3,), (3,)) array_like, optional
            A box given by the caller; used instead of `bounds` when given
            (it must be finite with ``lo <= hi``).

        Returns
        -------
        lo, hi : (3,) float64 ndarray
            Finite bounds.  Empty bounds (``lo > hi``) are returned as they are.

        Raises
        ------
        ValueError
            When the solid is unbounded and no `bounds` were given.

        Examples
        --------
        >>> from implicit import sphere, halfspace
        >>> lo, hi = sphere(1.0).require_bounds()
        >>> hi.tolist()
        [1.0, 1.0, 1.0]
        >>> lo, hi = halfspace((0, 0, 1)).require_bounds(((-1, -1, -1), (1, 1, 0)))
        """
        if bounds is not None:
            try:
                lo, hi = bounds
            except (TypeError, ValueError) as exc:
                raise ValueError("bounds: expected ((x0, y0, z0), (x1, y1, z1))") from exc
            lo = as_vector(lo, "bounds lower corner")
            hi = as_vector(hi, "bounds upper corner")
            if np.any(lo > hi):
                raise ValueError(f"bounds: expected lower corner <= upper corner, got {lo.tolist()} and {hi.tolist()}")
            return lo, hi
        lo, hi = self._bounds
        if self.is_empty_bounds:
            return lo.copy(), hi.copy()
        if not self.is_bounded:
            raise ValueError(
                f"{self.kind}: the solid is unbounded (bounds {lo.tolist()} .. {hi.tolist()}); pass "
                "bounds=((x0, y0, z0), (x1, y1, z1)) (command line: --bounds x0 y0 z0 x1 y1 z1)")
        return lo.copy(), hi.copy()

    def to_params(self) -> dict:
        """Parameters for the JSON form (default: `params`).

        Data-backed nodes override this (and `from_params`) to encode their
        data; the result must hold only JSON values (numbers, strings, bools,
        None, lists and dicts of them).
        """
        return self.params

    # -- evaluation -----------------------------------------------------------
    def __call__(self, points) -> np.ndarray:
        """Signed distances at `points`.

        Parameters
        ----------
        points : (..., 3) array_like
            Query points.

        Returns
        -------
        (...) float64 ndarray
            Negative inside, zero on the boundary, positive outside.
        """
        pts = as_points(points)
        shape = pts.shape[:-1]
        flat = np.ascontiguousarray(pts.reshape(-1, 3))
        n = flat.shape[0]
        if n >= FAST_PATH_MIN_POINTS or (self._children and n):
            # Large calls (and any call on a large tree) go through the compiled,
            # pruned evaluation (implicit.evaluate); None means numpy is used (no
            # numba, a small call on a small tree, or a node kind without a rule).
            fast = _evaluator["fast_evaluate"](self, flat) if _evaluator else None
            if fast is not None:
                return fast.reshape(shape)
        if n <= EVAL_CHUNK:
            out = self._evaluate(flat)
        else:
            out = np.empty(n)
            for start in range(0, n, EVAL_CHUNK):
                out[start:start + EVAL_CHUNK] = self._evaluate(flat[start:start + EVAL_CHUNK])
        return np.asarray(out, dtype=np.float64).reshape(shape)

    def evaluate(self, points) -> np.ndarray:
        """Alias of calling the solid: signed distances at `points`."""
        return self(points)

    def compiled(self, *, parallel: bool = False):
        """This tree compiled for fast evaluation (`implicit.evaluate.compile_solid`)."""
        if not _evaluator:
            raise ImportError("the compiled evaluator is not loaded: import implicit.evaluate (it needs numba)")
        return _evaluator["compile_solid"](self, parallel=parallel)

    def _evaluate(self, p: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def contains(self, points) -> np.ndarray:
        """Boolean mask of points inside or on the boundary."""
        return self(points) <= 0.0

    # -- conservative value bounds over boxes -------------------------------------
    def value_bounds(self, lo, hi) -> tuple[np.ndarray, np.ndarray]:
        """Conservative range of the field over each of many boxes.

        Parameters
        ----------
        lo, hi : (m, 3) array_like
            Lower and upper corners of ``m`` boxes.

        Returns
        -------
        vmin, vmax : (m,) float64 ndarray
            For every point ``p`` of box ``i``: ``vmin[i] <= f(p) <= vmax[i]``.
            A box with ``vmin > 0`` is EMPTY, one with ``vmax < 0`` is FULL.
        """
        lo = as_points(lo, "lo").reshape(-1, 3)
        hi = as_points(hi, "hi").reshape(-1, 3)
        if lo.shape != hi.shape:
            raise ValueError(f"lo and hi: expected the same shape, got {lo.shape} and {hi.shape}")
        if np.any(lo > hi):
            raise ValueError("lo, hi: every lower corner must be <= its upper corner")
        vmin, vmax = self._value_bounds(lo, hi)
        return np.asarray(vmin, dtype=np.float64), np.asarray(vmax, dtype=np.float64)

    def _value_bounds(self, lo: np.ndarray, hi: np.ndarray):
        """Lipschitz bound: ``f(centre) -/+ L * half diagonal``."""
        centre = 0.5 * (lo + hi)
        radius = 0.5 * np.linalg.norm(hi - lo, axis=-1)
        value = self(centre)
        spread = self._lipschitz * radius
        return value - spread, value + spread

    # -- gradient -------------------------------------------------------------
    def gradient(self, points, *, step: float | None = None) -> np.ndarray:
        """Gradient of the field by central differences, shape ``(..., 3)``.

        `step` defaults to a millionth of the bounds' extent (or 1e-6).
        """
        pts = as_points(points)
        if step is None:
            lo, hi = self._bounds
            ext = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
            step = 1e-6 * max(float(np.max(ext)), 1.0)
        flat = pts.reshape(-1, 3)
        offsets = np.eye(3) * step
        probe = np.concatenate([flat[:, None, :] + offsets, flat[:, None, :] - offsets], axis=1)
        vals = self(probe.reshape(-1, 3)).reshape(-1, 6)
        grad = (vals[:, :3] - vals[:, 3:]) / (2.0 * step)
        return grad.reshape(pts.shape)

    # -- tree -----------------------------------------------------------------
    def walk(self) -> Iterator["Solid"]:
        """Depth-first, pre-order iteration over the tree's nodes."""
        stack = [self]
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(node._children))

    def count_nodes(self) -> int:
        """Number of nodes in the tree."""
        return sum(1 for _ in self.walk())

    def count_primitives(self) -> int:
        """Number of leaves (primitives and data-backed fields) in the tree."""
        return sum(1 for n in self.walk() if not n._children)

    def depth(self) -> int:
        """Depth of the tree (a lone primitive has depth 1)."""
        best = 0
        stack = [(self, 1)]
        while stack:
            node, d = stack.pop()
            best = max(best, d)
            stack.extend((c, d + 1) for c in node._children)
        return best

    def tree(self) -> str:
        """The tree as indented text, one node a line."""
        lines = []
        stack = [(self, 0)]
        while stack:
            node, level = stack.pop()
            lines.append("  " * level + node._label())
            stack.extend((c, level + 1) for c in reversed(node._children))
        return "\n".join(lines)

    def _label(self) -> str:
        args = ", ".join(f"{k}={_fmt(v)}" for k, v in self._params.items())
        return f"{self.kind}({args})"

    def __repr__(self) -> str:
        if not self._children:
            return self._label()
        inner = ", ".join(repr(c) for c in self._children)
        args = ", ".join(f"{k}={_fmt(v)}" for k, v in self._params.items())
        return f"{self.kind}({inner}{', ' if args else ''}{args})"

    # -- operators (implemented in csg / transforms, bound at import) ------------
    def __or__(self, other):
        return _ops["union"](self, other)

    def __and__(self, other):
        return _ops["intersection"](self, other)

    def __sub__(self, other):
        return _ops["difference"](self, other)

    def __invert__(self):
        return _ops["complement"](self)

    def translate(self, offset):
        """A copy moved by `offset` (3,)."""
        return _ops["translate"](self, offset)

    def rotate(self, angle_degrees, axis=(0.0, 0.0, 1.0), about=(0.0, 0.0, 0.0)):
        """A copy rotated by `angle_degrees` about `axis` through `about`."""
        return _ops["rotate"](self, angle_degrees, axis=axis, about=about)

    def scale(self, factor):
        """A copy scaled uniformly by `factor` about the origin."""
        return _ops["scale"](self, factor)

    def mirror(self, normal, point=(0.0, 0.0, 0.0)):
        """A copy mirrored in the plane through `point` with `normal`."""
        return _ops["mirror"](self, normal, point=point)

    def affine(self, matrix, offset=(0.0, 0.0, 0.0)):
        """A copy mapped by ``p -> matrix @ p + offset`` (any invertible matrix)."""
        return _ops["affine"](self, matrix, offset=offset)

    def offset(self, distance):
        """A copy grown (positive) or shrunk (negative) by `distance`."""
        return _ops["offset"](self, distance)

    def shell(self, thickness):
        """A hollow copy: the set within `thickness`/2 of the boundary."""
        return _ops["shell"](self, thickness)


#: Operator implementations, filled in by the modules that define them, so that
#: `solid.py` stays free of import cycles.
_ops: dict[str, Callable] = {}


#: The compiled evaluator's entry points, registered by `implicit.evaluate` when it
#: is imported: the nodes never import the evaluator, which imports them.
_evaluator: dict[str, Callable] = {}


def register_evaluator(*, fast_evaluate: Callable, compile_solid: Callable) -> None:
    """Install the fast path behind `Solid.__call__` and `Solid.compiled`."""
    _evaluator.update(fast_evaluate=fast_evaluate, compile_solid=compile_solid)


_kind_loaders: list[Callable] = []


def register_kind_loader(loader: Callable) -> None:
    """Register `loader`, which imports node modules that ``import implicit`` leaves for later.

    Decoding calls `load_all_kinds` before it calls a kind unknown: the
    parametric solids (and scipy, which they need) load only then, or when
    their names are first read from `implicit`.
    """
    _kind_loaders.append(loader)


def load_all_kinds() -> None:
    """Import every node module registered for later, so that `Solid.registry` holds every kind."""
    while _kind_loaders:
        _kind_loaders.pop()()


def register_operator(name: str):
    """Decorator: make `func` the implementation behind `Solid.<name>`."""
    def deco(func):
        _ops[name] = func
        return func
    return deco


def _fmt(value) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    if isinstance(value, np.ndarray):
        return _fmt(value.tolist())
    return repr(value)
