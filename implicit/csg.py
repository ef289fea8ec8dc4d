"""Constructive solid geometry: union, intersection, difference, complement.

The sharp operators use ``min`` / ``max`` of the operands' fields; they keep
the operands' Lipschitz constant and the conservative-bound property (the
result of exact distances is a bound, exact outside a union and inside an
intersection).

Regularised booleans: a solid is the closure of its interior ``{f < 0}`` and
its boundary is the boundary of that closure.  The zero set of a combined
field can hold more than that: two boxes touching face to face union into a
field that is 0 on the shared face and negative on both sides of it, so the
face lies inside the closure of the interior and is not boundary (no internal
face: meshing from the field's sign sees no sign change across it); the same
boxes intersect into a field that is ``>= 0`` everywhere, a solid with an empty
interior (zero volume, no boundary to mesh), not a dangling face.

The smooth variants blend with the polynomial smooth minimum of radius
``blend``; they stay 1-Lipschitz.

References
----------
I. Quilez, "Smooth minimum", 2013 (polynomial smin).
A. Ricci, "A constructive geometry for computer graphics", 1973.
"""

from __future__ import annotations

import numpy as np

from .solid import INFINITE_BOUNDS, Solid, as_positive, register_operator

__all__ = [
    "Union",
    "Intersection",
    "Difference",
    "Complement",
    "SmoothUnion",
    "SmoothIntersection",
    "SmoothDifference",
    "union",
    "intersection",
    "difference",
    "complement",
    "smooth_union",
    "smooth_intersection",
    "smooth_difference",
    "bound_slack",
]


def _union_bounds(children):
    los = np.array([c.bounds[0] for c in children])
    his = np.array([c.bounds[1] for c in children])
    # Children with empty bounds add nothing.
    keep = ~np.any(los > his, axis=1)
    if not keep.any():
        return np.full(3, np.inf), np.full(3, -np.inf)
    return los[keep].min(axis=0), his[keep].max(axis=0)


def _intersection_bounds(children):
    los = np.array([c.bounds[0] for c in children])
    his = np.array([c.bounds[1] for c in children])
    lo, hi = los.max(axis=0), his.min(axis=0)
    if np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) or np.any(lo > hi):
        return lo, hi
    planes = [c for c in children if c.kind == "halfspace"]
    if not planes:
        return lo, hi
    return _halfspace_box(planes, lo, hi)


def _halfspace_box(planes, lo, hi):
    """Bounds of the intersection of half-spaces and the box ``[lo, hi]``.

    Each half-space is a plane ``n . x <= d``; the finite sides of the box
    (the other children's bounds) are planes too.  Six linear programs give
    the extreme coordinates of the polytope: a tetrahedron of four tilted
    half-spaces gets its finite box although no child has one.  An
    unbounded direction keeps its infinite bound; an empty intersection gets
    empty bounds.
    """
    from scipy.optimize import linprog

    normals = [np.asarray(p.params["normal"], dtype=np.float64) for p in planes]
    offsets = [float(np.dot(p.params["normal"], p.params["point"])) for p in planes]
    eye = np.eye(3)
    for i in range(3):
        if np.isfinite(hi[i]):
            normals.append(eye[i])
            offsets.append(float(hi[i]))
        if np.isfinite(lo[i]):
            normals.append(-eye[i])
            offsets.append(-float(lo[i]))
    a_ub, b_ub = np.array(normals), np.array(offsets)
    out_lo, out_hi = lo.copy(), hi.copy()
    for i in range(3):
        for sign in (1.0, -1.0):
            cost = np.zeros(3)
            cost[i] = sign                      # minimise x_i (sign 1) or -x_i (sign -1)
            res = linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=[(None, None)] * 3, method="highs")
            if res.status == 2:                 # infeasible: nothing is inside
                return np.full(3, np.inf), np.full(3, -np.inf)
            if res.status != 0:                 # unbounded (or unsolved): keep the box's side
                continue
            value = float(res.x[i])
            # the LP's vertex is exact to round-off; a little slack keeps it conservative
            slack = 1e-9 * max(1.0, abs(value), float(np.abs(b_ub).max()))
            if sign > 0:
                out_lo[i] = max(out_lo[i], value - slack)
            else:
                out_hi[i] = min(out_hi[i], value + slack)
    return out_lo, out_hi


class _SharpBoolean(Solid):
    """A sharp boolean: the first child's field folded with each other child's
    by ``min`` or ``max`` (`_fold`), the others negated when `_negate_tools`."""

    __slots__ = ()
    _negate_tools = False

    def __init__(self, children, bounds):
        super().__init__(children, {}, bounds, exact=False, lipschitz=max(c.lipschitz for c in children))

    def _evaluate(self, p):
        out = np.array(self._children[0]._evaluate(p), dtype=np.float64, copy=True)
        for child in self._children[1:]:
            value = child._evaluate(p)
            self._fold(out, -value if self._negate_tools else value, out=out)
        return out


class Union(_SharpBoolean):
    """Union of any number of solids: ``min`` of their fields."""

    kind = "union"
    __slots__ = ()
    _fold = np.minimum

    def __init__(self, *children):
        if len(children) < 1:
            raise ValueError("union: expected at least one solid")
        _check(children, "union")
        super().__init__(children, _union_bounds(children))


class Intersection(_SharpBoolean):
    """Intersection of any number of solids: ``max`` of their fields."""

    kind = "intersection"
    __slots__ = ()
    _fold = np.maximum

    def __init__(self, *children):
        if len(children) < 1:
            raise ValueError("intersection: expected at least one solid")
        _check(children, "intersection")
        super().__init__(children, _intersection_bounds(children))


class Difference(_SharpBoolean):
    """``a`` minus the union of the others: ``max(a, -b, -c, ...)``."""

    kind = "difference"
    __slots__ = ()
    _fold = np.maximum
    _negate_tools = True

    def __init__(self, base, *tools):
        if not tools:
            raise ValueError("difference: expected a base solid and at least one solid to subtract")
        _check((base,) + tools, "difference")
        super().__init__((base,) + tools, base.bounds if isinstance(base, Solid) else INFINITE_BOUNDS)


class Complement(Solid):
    """Everything outside a solid: the negated field (unbounded)."""

    kind = "complement"
    __slots__ = ()

    def __init__(self, solid):
        _check((solid,), "complement")
        super().__init__((solid,), {}, INFINITE_BOUNDS, exact=solid.exact, lipschitz=solid.lipschitz)

    def _evaluate(self, p):
        return -self._children[0]._evaluate(p)


def bound_slack(solid: Solid) -> float:
    """Factor ``s`` with: ``f(p) < t`` (t > 0) puts ``p`` within ``s * t`` of
    `solid`'s bounds.

    It is 1 for exact fields and their sharp CSG; an affine map multiplies it
    by its condition number, and a primitive whose field is a scaled bound
    declares its own factor as the class attribute ``bound_slack``.
    """
    worst = 1.0
    stack = [(solid, 1.0)]
    while stack:
        node, factor = stack.pop()
        factor *= float(getattr(node, "bound_slack_factor", 1.0))
        if not node.children:
            worst = max(worst, factor)
        stack.extend((c, factor) for c in node.children)
    return worst


def grown_bounds(solid: Solid, t: float):
    """Bounds of ``{p : f(p) < t}`` for ``t >= 0``: where an offset or a shell of `solid` reaches.

    Padding the solid's own bounds by ``t * bound_slack`` is not enough below
    an intersection: ``max(a, b) < t`` only puts ``p`` within ``t`` of each
    child, and the two grown children can overlap well outside the grown
    intersection (two slabs crossing at a small angle).  So sharp Booleans
    grow their children first, then combine; an affine node grows its child
    by ``t`` over its scale factor and maps the box; half-spaces shift their
    planes.  Other nodes pad their bounds by ``t * bound_slack``.
    """
    from .primitives import HalfSpace
    from .transforms import Affine

    t = float(t)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    if t <= 0:
        return lo, hi
    if isinstance(solid, Difference):
        return grown_bounds(solid.children[0], t)
    if isinstance(solid, (Union, Intersection)):
        parts = [grown_bounds(c, t) for c in solid.children]
        los, his = np.array([q[0] for q in parts]), np.array([q[1] for q in parts])
        if isinstance(solid, Union):
            return los.min(axis=0), his.max(axis=0)
        glo, ghi = los.max(axis=0), his.min(axis=0)
        planes = [c for c in solid.children if isinstance(c, HalfSpace)]
        if planes and not (np.all(np.isfinite(glo)) and np.all(np.isfinite(ghi))):
            shifted = [HalfSpace(c.params["normal"], np.asarray(c.params["point"]) + t * np.asarray(c.params["normal"]))
                       for c in planes]
            glo, ghi = _halfspace_box(shifted, glo, ghi)
        return glo, ghi                 # lo > hi on an axis: empty, as `_intersection_bounds` says
    if isinstance(solid, Affine):
        clo, chi = grown_bounds(solid.children[0], t / solid._factor)
        a, off = solid._matrix, solid._offset
        with np.errstate(invalid="ignore"):
            c_lo = np.where(a == 0.0, 0.0, a * clo)
            c_hi = np.where(a == 0.0, 0.0, a * chi)
        return np.minimum(c_lo, c_hi).sum(axis=1) + off, np.maximum(c_lo, c_hi).sum(axis=1) + off
    pad = t * bound_slack(solid)
    return lo - pad, hi + pad


def _smin(a, b, k):
    """Polynomial smooth minimum of radius `k` (1-Lipschitz when a, b are)."""
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0.0, 1.0)
    return b + (a - b) * h - k * h * (1.0 - h)


class _Smooth(Solid):
    __slots__ = ()

    def __init__(self, children, blend, bounds):
        blend = as_positive(blend, "blend")
        super().__init__(children, {"blend": blend}, bounds, exact=False,
                         lipschitz=max(c.lipschitz for c in children))

    @property
    def blend(self) -> float:
        return self._params["blend"]


class SmoothUnion(_Smooth):
    """Union with a fillet of radius about `blend` where the solids meet."""

    kind = "smooth_union"
    __slots__ = ()

    def __init__(self, *children, blend):
        if len(children) < 1:
            raise ValueError("smooth_union: expected at least one solid")
        _check(children, "smooth_union")
        lo, hi = _union_bounds(children)
        # Each pairwise blend lowers the field by at most blend/4, so the result
        # is at least min(f_i) - (n - 1) blend / 4: material appears only where
        # some child's field is below that.  `bound_slack` turns a field value
        # into a distance beyond that child's bounds.
        pad = (len(children) - 1) * as_positive(blend, "blend") / 4.0
        pad *= max(bound_slack(c) for c in children)
        super().__init__(children, blend, (lo - pad, hi + pad))

    def _evaluate(self, p):
        k = self._params["blend"]
        out = self._children[0]._evaluate(p)
        for child in self._children[1:]:
            out = _smin(out, child._evaluate(p), k)
        return out


class SmoothIntersection(_Smooth):
    """Intersection with its edges rounded by about `blend`."""

    kind = "smooth_intersection"
    __slots__ = ()

    def __init__(self, *children, blend):
        if len(children) < 1:
            raise ValueError("smooth_intersection: expected at least one solid")
        _check(children, "smooth_intersection")
        super().__init__(children, blend, _intersection_bounds(children))

    def _evaluate(self, p):
        k = self._params["blend"]
        out = self._children[0]._evaluate(p)
        for child in self._children[1:]:
            out = -_smin(-out, -child._evaluate(p), k)
        return out


class SmoothDifference(_Smooth):
    """``a`` minus the others, the cut edges rounded by about `blend`."""

    kind = "smooth_difference"
    __slots__ = ()

    def __init__(self, base, *tools, blend):
        if not tools:
            raise ValueError("smooth_difference: expected a base solid and at least one solid to subtract")
        _check((base,) + tools, "smooth_difference")
        super().__init__((base,) + tools, blend, base.bounds)

    def _evaluate(self, p):
        k = self._params["blend"]
        out = self._children[0]._evaluate(p)
        for child in self._children[1:]:
            out = -_smin(-out, child._evaluate(p), k)
        return out


def _check(solids, name):
    for i, s in enumerate(solids):
        if not isinstance(s, Solid):
            raise TypeError(f"{name}: argument {i} must be a Solid, got {type(s).__name__}")


def _flattened(cls, solids):
    """One `cls` node over `solids`, nested `cls` nodes spliced in (a lone solid is itself)."""
    _check(solids, cls.kind)
    if not solids:
        raise ValueError(f"{cls.kind}: expected at least one solid")
    flat = []
    for s in solids:
        flat.extend(s.children if type(s) is cls else (s,))
    return flat[0] if len(flat) == 1 else cls(*flat)


@register_operator("union")
def union(*solids: Solid) -> Solid:
    """Union of solids (``a | b | ...``); nested unions are flattened.

    Examples
    --------
    >>> from implicit import sphere, union
    >>> u = union(sphere(1), sphere(1).translate((1.5, 0, 0)))
    >>> u.count_primitives()
    2
    """
    return _flattened(Union, solids)


@register_operator("intersection")
def intersection(*solids: Solid) -> Solid:
    """Intersection of solids (``a & b & ...``); nested ones are flattened."""
    return _flattened(Intersection, solids)


@register_operator("difference")
def difference(base: Solid, *tools: Solid) -> Solid:
    """``base`` minus every solid of `tools` (``a - b - c``)."""
    _check((base,) + tools, "difference")
    if type(base) is Difference:
        return Difference(*base.children, *tools)
    return Difference(base, *tools)


@register_operator("complement")
def complement(solid: Solid) -> Solid:
    """Everything but `solid` (``~a``); ``~~a`` is ``a``."""
    _check((solid,), "complement")
    if type(solid) is Complement:
        return solid.children[0]
    return Complement(solid)


def smooth_union(*solids: Solid, blend: float) -> Solid:
    """Union with fillets of radius about `blend` where solids meet."""
    _check(solids, "smooth_union")
    return SmoothUnion(*solids, blend=blend)


def smooth_intersection(*solids: Solid, blend: float) -> Solid:
    """Intersection with edges rounded by about `blend`."""
    _check(solids, "smooth_intersection")
    return SmoothIntersection(*solids, blend=blend)


def smooth_difference(base: Solid, *tools: Solid, blend: float) -> Solid:
    """``base`` minus `tools`, the cut edges rounded by about `blend`."""
    _check((base,) + tools, "smooth_difference")
    return SmoothDifference(base, *tools, blend=blend)
