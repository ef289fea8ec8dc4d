"""Facet walks that evaluate only the primitives near each point.

`implicit.facets.FacetField` walks the whole CSG tree at every point: a
lattice of 540 capsules costs 540 leaf evaluations a point.  Two walks here
do work proportional to the primitives near the points instead, with the
same results bit for bit:

* `pruned_decide`, the field and the deciding facet: the points are sorted
  into bins, and an operand of a sharp union, intersection or difference
  that cannot decide it anywhere in a bin's box is not evaluated on that
  bin's points (the bounds are those of `implicit.evaluate.prune`: the value
  at the box's centre plus or minus the Lipschitz constant times the
  half-diagonal).  An operand left out is strictly beaten everywhere in the
  box, so the smallest (largest) value and the first operand attaining it are
  those of the full walk;
* `subset_values`, the value of one chosen facet per point (the 2-3 facets
  of a feature vertex): each leaf is evaluated only at the points that ask
  for one of its facets.

Every leaf is evaluated by the code of the full walk on a subset of its
points; numpy's element-wise operations and the (n, 3) x (3, 3) products
of the transforms give each point the same bits whatever the other points.

References
----------
M. Keeter, "Massively Parallel Rendering of Complex Closed-Form Implicit
Surfaces", ACM Trans. Graph. 39(4), 2020, doi:10.1145/3386569.3392429.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_BINS_PER_AXIS", "POINTS_PER_BIN", "Bins", "Capsules", "facet_order", "leaf_loops", "operands",
           "pruned_decide", "subset_values"]

#: Target number of points per bin of the grid the walk is pruned on.
POINTS_PER_BIN = 64
#: Largest number of bins along one axis.
MAX_BINS_PER_AXIS = 128
#: Relative slack of the bounds: the values compared carry rounding errors.
SLACK = 1e-9

_BOOLEANS = ("union", "intersection", "difference")
_PASS_THROUGH = ("complement", "family", "affine", "offset")


class Bins:
    """The points sorted into the occupied bins of a grid.

    Parameters
    ----------
    points : (n, 3) float
    per_bin : int
        Target number of points per bin (over the points' bounding box).

    Attributes
    ----------
    order : (n,) int
        The points in bin order: ``points[order]``.
    starts : (m + 1,) int
        Bin ``b`` holds sorted points ``starts[b] .. starts[b + 1] - 1``.
    lo, hi : (m, 3) float
        The tight box of each bin's points.

    Examples
    --------
    >>> b = Bins(np.array([[0.0, 0, 0], [10.0, 0, 0], [0.1, 0, 0]]), per_bin=1)
    >>> b.starts.tolist(), b.order.tolist()
    ([0, 2, 3], [0, 2, 1])
    """

    def __init__(self, points, per_bin=POINTS_PER_BIN):
        p = np.asarray(points, dtype=np.float64)
        n = p.shape[0]
        loops = _capsule_loops()
        fast = loops is not None and n > 0 and p.ndim == 2 and p.shape[1] == 3 and p.flags.c_contiguous
        # (the compiled passes give the same keys: a zero's sign in the range changes no cell)
        lo, hi = loops[4](p) if fast else (p.min(axis=0), p.max(axis=0))
        ext = hi - lo
        flat = ext <= 1e-9 * max(float(ext.max()), 1e-300)
        g = np.ones(3, dtype=np.int64)
        if (~flat).any():
            h = (float(np.prod(ext[~flat])) * per_bin / max(n, 1)) ** (1.0 / int((~flat).sum()))
            g[~flat] = np.clip(np.round(ext[~flat] / h), 1, MAX_BINS_PER_AXIS).astype(np.int64)
        scale = np.where(flat, 0.0, g / np.where(flat, 1.0, ext))
        if fast:
            key = loops[3](p, lo, scale, g)
        else:
            cell = np.minimum(((p - lo) * scale).astype(np.int64), g - 1)
            key = (cell[:, 0] * g[1] + cell[:, 1]) * g[2] + cell[:, 2]
        n_keys = int(np.prod(g))
        if loops is not None and n and 0 <= key.min() and key.max() < n_keys:
            # a compiled counting sort of the bins' keys: numpy's stable order of them, several times faster
            self.order, self.starts = loops[2](key, n_keys)
        else:
            self.order = np.argsort(key, kind="stable")
            ks = key[self.order]
            self.starts = np.concatenate([[0], np.flatnonzero(ks[1:] != ks[:-1]) + 1, [n]]).astype(np.int64)
        self.sorted = np.ascontiguousarray(p[self.order])
        first = self.starts[:-1]
        self.lo = np.minimum.reduceat(self.sorted, first, axis=0)
        self.hi = np.maximum.reduceat(self.sorted, first, axis=0)

    @property
    def lengths(self):
        return np.diff(self.starts)


def _ranges(starts, lengths):
    """The concatenated ranges ``starts[i] .. starts[i] + lengths[i] - 1``."""
    total = int(lengths.sum())
    ends = np.cumsum(lengths)
    return np.arange(total, dtype=np.int64) - np.repeat(ends - lengths - starts, lengths)


def pruned_decide(ff, points, per_bin=POINTS_PER_BIN):
    """Field ``(n,)`` and deciding facet ``(n,)`` of `ff` (a `FacetField`) at `points`, as
    `FacetField.decide` gives them, evaluating each operand only in the bins it may decide.

    Examples
    --------
    >>> from implicit import box, cylinder, union
    >>> from implicit.facets import FacetField
    >>> ff = FacetField(union(*[cylinder(0.2, 1.0, center=(x, 0, 0)) for x in range(20)]))
    >>> p = np.random.default_rng(0).uniform(-1, 20, (5000, 3))
    >>> v, d = pruned_decide(ff, p)
    >>> v0, d0 = ff._walk_decide(ff.solid, p, [0])
    >>> bool(np.array_equal(v, v0) and np.array_equal(d, d0))
    True
    """
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    n = p.shape[0]
    if n == 0 or not np.isfinite(p).all():
        return ff._walk_decide(ff.solid, p, [0])
    bins = Bins(p, per_bin)
    centre = 0.5 * (bins.lo + bins.hi)
    radius = 0.5 * np.sqrt(np.einsum("ij,ij->i", bins.hi - bins.lo, bins.hi - bins.lo))
    keeps: list = []
    _record(ff.solid, centre, 1.0, radius, keeps, _tape_values(ff.solid, centre))
    walk = _Walk(ff, keeps, bins.lengths)
    value, dec = walk.node(ff.solid, bins.sorted, np.arange(bins.lengths.shape[0]))
    out_v = np.empty(n)
    out_d = np.empty(n, dtype=np.intp)
    out_v[bins.order] = value
    out_d[bins.order] = dec
    return out_v, out_d


def _tape_values(solid, centres):
    """The operands' values of every Boolean of `solid` at `centres`, by id of the Boolean ``(children, m)``,
    from one run of the compiled tape (`implicit.evaluate`), or None without it.

    They bound the operands as numpy's do (the tape rounds otherwise by about 1e-15 relative, well within
    `SLACK`) at a fraction of the cost: numpy evaluates every leaf of the tree at every centre, leaf by
    leaf.  A Boolean met twice in the tree (a shared subtree) is left out: its operands are evaluated.
    """
    try:
        from .evaluate.compile import compile_solid
        from .evaluate.kernels import _call, _kernel
    except ImportError:
        return None
    compiled = compile_solid(solid, warm=False)
    if compiled.backend != "numba" or not compiled.tape.groups:
        return None
    rec = _call(_kernel("serial"), compiled.tape, np.ascontiguousarray(centres), record=True)
    groups = compiled.tape.groups
    count: dict = {}
    for node, *_ in groups:
        count[id(node)] = count.get(id(node), 0) + 1
    out: dict = {}
    for node, _frame, slots, _entries in groups:
        if count[id(node)] == 1 and len(slots) == len(node.children) and node.kind in _BOOLEANS:
            out[id(node)] = rec[slots]
    return out


def _record(node, c, scale, radius, keeps, known=None, need=True):
    """The field at the bins' centres `c`; appends, for every sharp Boolean in depth-first order,
    which of its operands may decide it in each bin, ``(children, m)`` bool.  `known`: the operands'
    values of Booleans by id (`_tape_values`), whose leaves are then not evaluated; returns None for
    a subtree whose value is not `need`-ed."""
    kind = node.kind
    if kind in _BOOLEANS:
        slot = len(keeps)
        keeps.append(None)
        given = known.get(id(node)) if known else None
        kids = [_record(ch, c, scale, radius, keeps, known, given is None) for ch in node.children]
        vals = np.array(given, dtype=np.float64) if given is not None else np.stack(kids)
        lips = np.array([ch.lipschitz for ch in node.children])[:, None]
        with np.errstate(invalid="ignore"):
            spread = lips * (radius * scale * (1.0 + SLACK))[None, :] + SLACK * (1.0 + np.abs(vals))
            vmin, vmax = vals - spread, vals + spread
            if kind == "union":
                keeps[slot] = ~(vmin > vmax.min(axis=0))
                return vals.min(axis=0)
            if kind == "intersection":
                keeps[slot] = ~(vmax < vmin.max(axis=0))
                return vals.max(axis=0)
            # max(base, -tools): operand ranges [vmin, vmax] and [-vmax, -vmin]
            lower = np.concatenate([vmin[:1], -vmax[1:]])
            upper = np.concatenate([vmax[:1], -vmin[1:]])
            keeps[slot] = ~(upper < lower.max(axis=0))
            vals[1:] *= -1.0
            return vals.max(axis=0)
    if kind in _PASS_THROUGH and not _has_boolean(node) and not need:
        return None
    if kind == "family":
        return _record(node.children[0], c, scale, radius, keeps, known, need)
    if kind == "complement":
        v = _record(node.children[0], c, scale, radius, keeps, known, need)
        return None if v is None else -v
    if kind == "offset":
        v = _record(node.children[0], c, scale, radius, keeps, known, need)
        return None if v is None else v - node.params["distance"]
    if kind == "affine":
        q = np.ascontiguousarray((c - node._offset) @ node._inv.T)
        # a child evaluated at inv (p - offset) varies by at most |inv| times its Lipschitz constant
        v = _record(node.children[0], q, scale * float(np.linalg.norm(node._inv, 2)), radius, keeps, known, need)
        return None if v is None else v * node._factor
    if not need:
        return None
    return np.asarray(node._evaluate(c), dtype=np.float64)


def _has_boolean(node):
    """Whether a sharp Boolean lies below the pass-through chain `node`."""
    while node.kind in _PASS_THROUGH:
        node = node.children[0]
    return node.kind in _BOOLEANS


class _Walk:
    """`FacetField._walk_decide` over the points of the bins each node may decide.

    A node gets its points ``p`` (in its coordinates) and the bins ``bsel``
    they fill, in order: its rows are the concatenated rows of those bins.
    """

    def __init__(self, ff, keeps, lengths):
        self.ff = ff
        self.keeps = keeps
        self.lengths = lengths
        self.at = 0          # next facet index
        self.slot = 0        # next sharp Boolean, depth-first
        self._booleans: dict = {}

    def skip(self, node):
        """Move past `node`'s facets and Booleans (an operand evaluated nowhere)."""
        self.at += self.ff._n_facets(node)
        self.slot += self._count_booleans(node)

    def _count_booleans(self, node):
        key = id(node)
        if key not in self._booleans:
            own = 1 if node.kind in _BOOLEANS else 0
            below = sum(self._count_booleans(c) for c in node.children) \
                if node.kind in _BOOLEANS + _PASS_THROUGH else 0
            self._booleans[key] = own + below
        return self._booleans[key]

    def node(self, node, p, bsel):
        kind = node.kind
        if kind in _BOOLEANS:
            return self.boolean(node, p, bsel)
        if kind == "family":
            return self.node(node.children[0], p, bsel)
        if kind == "complement":
            v, d = self.node(node.children[0], p, bsel)
            return -v, d
        if kind == "affine":
            q = np.ascontiguousarray((p - node._offset) @ node._inv.T)
            v, d = self.node(node.children[0], q, bsel)
            return (v * node._factor if node._factor != 1.0 else v), d
        if kind == "offset":
            v, d = self.node(node.children[0], p, bsel)
            return v - node.params["distance"], d
        start = self.at
        self.at += self.ff._n_facets(node)
        return self.ff._leaf_decide(node, p, start)

    def boolean(self, node, p, bsel):
        """A sharp Boolean: the first operand attaining the min (union) or max, operands in order;
        a difference negates its tools (`implicit.facets._decide`)."""
        keep = self.keeps[self.slot]
        self.slot += 1
        fold = _fold()
        if fold is None:
            return self._boolean_each(node, keep, p, bsel)
        r = p.shape[0]
        lengths = self.lengths[bsel]
        offsets = np.cumsum(lengths) - lengths
        # every (operand, bin) it may decide, operands in order; their points' rows, operand by operand
        cj, bj = np.nonzero(keep[:, bsel])
        plen = lengths[bj]
        rows = _ranges(offsets[bj], plen)
        count = len(node.children)
        pair_at = np.concatenate([[0], np.cumsum(np.bincount(cj, minlength=count))])
        row_at = np.concatenate([[0], np.cumsum(plen)])[pair_at]
        values = np.empty(rows.shape[0])
        decs = np.empty(rows.shape[0], dtype=np.intp)
        negate = node.kind == "difference"
        j = 0
        for child in operands(self.ff, node):
            if type(child) is Capsules:
                # a run of capsule operands: one compiled loop over all their rows
                k = len(child.children)
                a, b = int(row_at[j]), int(row_at[j + k])
                if b > a:
                    which = np.repeat(np.arange(k), np.diff(row_at[j:j + k + 1]))
                    child.values_at(p, rows[a:b], which, values[a:b])
                    decs[a:b] = self.at + which
                    if negate:
                        seg, tool = values[a:b], (which + j) > 0
                        seg[tool] = -seg[tool]
                self.at += k
                j += k
                continue
            i, j = j, j + 1
            a, b = int(row_at[i]), int(row_at[j])
            if a == b:
                self.skip(child)
                continue
            if b - a == r:
                q, sub = p, bsel
            else:
                q, sub = np.ascontiguousarray(p[rows[a:b]]), bsel[bj[pair_at[i]:pair_at[j]]]
            if child.kind not in _BOOLEANS + _PASS_THROUGH and self.ff._n_facets(child) == 1:
                # a one-facet leaf (`FacetField._leaf_decide`'s own case, without its array of facet indices)
                v = np.asarray(child._evaluate(q), dtype=np.float64)
                decs[a:b] = self.at
                self.at += 1
            else:
                v, d = self.node(child, q, sub)
                decs[a:b] = d
            values[a:b] = -v if (i and negate) else v
        cur = np.empty(r)
        dec = np.empty(r, dtype=np.intp)
        fold(rows, values, decs, node.kind == "union", cur, dec, np.zeros(r, dtype=np.bool_))
        return cur, dec

    def _boolean_each(self, node, keep, p, bsel):
        """`boolean` without numba: the operands folded one by one by numpy."""
        r = p.shape[0]
        lengths = self.lengths[bsel]
        offsets = np.cumsum(lengths) - lengths
        cur = np.empty(r)
        dec = np.empty(r, dtype=np.intp)
        filled = np.zeros(r, dtype=np.bool_)
        smaller = node.kind == "union"
        for j, child in enumerate(node.children):
            mask = keep[j][bsel]
            if mask.all():
                pos = None
                v, d = self.node(child, p, bsel)
            elif mask.any():
                pos = _ranges(offsets[mask], lengths[mask])
                v, d = self.node(child, np.ascontiguousarray(p[pos]), bsel[mask])
            else:
                self.skip(child)
                continue
            if j and node.kind == "difference":
                v = -v
            c = cur if pos is None else cur[pos]
            f = filled if pos is None else filled[pos]
            with np.errstate(invalid="ignore"):
                beats = (v < c) if smaller else (v > c)
            # argmin / argmax return the first NaN: a NaN replaces a number, nothing replaces a NaN
            take = ~f | beats | (np.isnan(v) & ~np.isnan(c))
            if pos is None:
                cur[take] = v[take]
                dec[take] = d[take]
                filled[:] = True
            else:
                at = pos[take]
                cur[at] = v[take]
                dec[at] = d[take]
                filled[pos] = True
        return cur, dec


def _fold():
    """The compiled fold of a Boolean's operands (`implicit.facet_prune_kernel`), or None without numba."""
    try:
        from .facet_prune_kernel import first_best
    except ImportError:
        return None
    return first_best


def subset_values(ff, points, which):
    """Value of facet ``which[i, j]`` at point ``i`` (0 where ``which`` is out of range), as
    `FacetField.facet_values` gives it, each leaf evaluated only where one of its facets is asked.

    Examples
    --------
    >>> from implicit import box, sphere
    >>> from implicit.facets import FacetField
    >>> ff = FacetField(box(2.0) | sphere(1.0, center=(3.0, 0.0, 0.0)))
    >>> subset_values(ff, np.array([[0.5, 0.0, 0.0], [3.0, 0.0, 0.0]]), np.array([[0], [6]])).tolist()
    [[-0.5], [-1.0]]
    """
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    w = np.asarray(which, dtype=np.int64)
    rows, cols = np.nonzero((w >= 0) & (w < len(ff.names)))
    out = np.zeros(w.shape)
    order = facet_order(w[rows, cols], len(ff.names))
    rows, cols = rows[order], cols[order]
    fac = w[rows, cols]
    v = np.zeros(rows.shape[0])
    _subset_walk(ff, ff.solid, p, rows, fac, v, [0])
    out[rows, cols] = v
    return out


def facet_order(fac, count):
    """The stable order of the facet indices `fac` (all in ``0 .. count - 1``): numpy sorts 16-bit
    integers stably by radix, several times faster than 64-bit ones.

    Examples
    --------
    >>> facet_order(np.array([3, 1, 3, 0]), 4).tolist()
    [3, 1, 0, 2]
    """
    if count <= np.iinfo(np.uint16).max:
        fac = fac.astype(np.uint16)
    return np.argsort(fac, kind="stable")


def _subset_walk(ff, node, p, rows, fac, v, counter):
    """Values of facets ``fac`` (sorted) at points ``p[rows]`` into `v` (`FacetField._values`'s
    operations, in its order, on the points that ask)."""
    kind = node.kind
    start = counter[0]
    k = ff._n_facets(node)
    lo, hi = np.searchsorted(fac, [start, start + k])
    if hi == lo:
        counter[0] += k
        return
    if kind in _BOOLEANS:
        for c in operands(ff, node):
            if type(c) is Capsules:
                c.values(p, rows, fac, v, counter)
            else:
                _subset_walk(ff, c, p, rows, fac, v, counter)
    elif kind in ("complement", "family"):
        _subset_walk(ff, node.children[0], p, rows, fac, v, counter)
    elif kind == "affine":
        # only the rows asked for are mapped (each row's product does not depend on the others)
        need = np.unique(rows[lo:hi])
        q = np.empty_like(p)
        q[need] = (p[need] - node._offset) @ node._inv.T
        _subset_walk(ff, node.children[0], q, rows, fac, v, counter)
        if node._factor != 1.0:
            v[lo:hi] = v[lo:hi] * node._factor
    elif kind == "offset":
        _subset_walk(ff, node.children[0], p, rows, fac, v, counter)
        v[lo:hi] = v[lo:hi] - node.params["distance"]
    else:
        fv = ff._leaf_values(node, np.ascontiguousarray(p[rows[lo:hi]]))
        v[lo:hi] = np.asarray(fv, dtype=np.float64)[fac[lo:hi] - start, np.arange(hi - lo)]
        counter[0] += k


class Capsules:
    """A run of consecutive capsule operands of one Boolean (a lattice's struts), evaluated by one
    compiled loop over the rows of all of them (`implicit.facet_prune_kernel`) instead of a call
    each: every row by the arithmetic of the capsule's own loop, so the same bits.  Each capsule
    is one facet: the run's facets are consecutive, in the operands' order."""

    __slots__ = ("children", "a", "ab", "ab2", "r")

    def __init__(self, children):
        self.children = list(children)
        self.a = np.array([c._a for c in children], dtype=np.float64).reshape(-1, 3)
        self.ab = np.array([c._ab for c in children], dtype=np.float64).reshape(-1, 3)
        self.ab2 = np.array([c._ab2 for c in children], dtype=np.float64)
        self.r = np.array([c._r for c in children], dtype=np.float64)

    def values_at(self, p, rows, which, out):
        """``out[k]``: capsule ``which[k]``'s field at ``p[rows[k]]``."""
        _capsule_loops()[0](p, rows, which, self.a, self.ab, self.ab2, self.r, out)

    def values(self, p, rows, fac, out, counter):
        """`_subset_walk` over the run: the facets ``fac`` (sorted) asked at ``p[rows]`` into `out`."""
        start = counter[0]
        k = len(self.children)
        lo, hi = np.searchsorted(fac, [start, start + k])
        if hi > lo:
            self.values_at(p, rows[lo:hi], fac[lo:hi] - start, out[lo:hi])
        counter[0] += k

    def gradients(self, p, rows, fac, g, counter):
        """`implicit.facets.FacetField._grad_walk` over the run: gradients into the rows of `g`."""
        start = counter[0]
        k = len(self.children)
        lo, hi = np.searchsorted(fac, [start, start + k])
        if hi > lo:
            _capsule_loops()[1](p, rows[lo:hi], fac[lo:hi] - start, self.a, self.ab, self.ab2, g[lo:hi])
        counter[0] += k


#: Consecutive capsule operands batched from this many on (one alone keeps its own call).
MIN_CAPSULE_RUN = 2


def operands(ff, node):
    """The operands of the Boolean `node`, with each run of `MIN_CAPSULE_RUN` or more consecutive
    capsules as one `Capsules` (cached on `ff`); its children as they are without the compiled loops."""
    cache = ff.__dict__.setdefault("_operand_cache", {})
    key = id(node)
    if key in cache:
        return cache[key]
    from .primitives import Capsule, capsule_kernels

    out: list = []
    if _capsule_loops() is None or capsule_kernels() is None:
        out = list(node.children)
    else:
        run: list = []
        for c in list(node.children) + [None]:
            if c is not None and type(c) is Capsule:
                run.append(c)
                continue
            if len(run) >= MIN_CAPSULE_RUN:
                out.append(Capsules(run))
            else:
                out.extend(run)
            run = []
            if c is not None:
                out.append(c)
    cache[key] = out
    return out


_LOOPS: list = []


def _capsule_loops():
    """``(capsules_at, capsule_gradients_at, bin_points, bin_keys, point_range)`` of
    `implicit.facet_prune_kernel`, or None without numba."""
    if not _LOOPS:
        try:
            from .facet_prune_kernel import bin_keys, bin_points, capsule_gradients_at, capsules_at, point_range
        except ImportError:
            _LOOPS.append(None)
        else:
            _LOOPS.append((capsules_at, capsule_gradients_at, bin_points, bin_keys, point_range))
    return _LOOPS[0]


_LEAF_LOOPS: list = []


def leaf_loops():
    """The module `implicit.facet_leaf_kernel` (a box's, a cylinder's and a sphere's field and deciding
    facet by one compiled loop each), or None without numba (then numpy evaluates them)."""
    if not _LEAF_LOOPS:
        try:
            from . import facet_leaf_kernel
        except ImportError:
            _LEAF_LOOPS.append(None)
        else:
            _LEAF_LOOPS.append(facet_leaf_kernel)
    return _LEAF_LOOPS[0]
