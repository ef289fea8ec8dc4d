"""The faces a CSG tree knows: which face of which primitive decides the field at a point.

Every primitive leaf of a CSG tree (and each flat or cylindrical facet of a
sharp box or a cylinder) is a *facet*; each point is attributed to the facet
that decides the CSG ``min``/``max`` there (`FacetField`).  The facets name
the boundary regions of FEA meshes and give the exact normals from which the
boundary mesher rebuilds sharp edges and corners.
"""

from __future__ import annotations

import numpy as np

from .facet_gradients import leaf_facets_with_gradients
from .facet_prune import Capsules, facet_order, leaf_loops, operands, pruned_decide, subset_values
from .profile_facets import polygon_runs, run_fields
from .solid import Solid

__all__ = ["SMOOTH_KINDS", "FacetField", "facet_field"]

#: Leaves whose every facet is a smooth (C1) surface near the boundary: a cell of a mesh whose
#: vertices all lie on one such facet holds no sharp edge, however much its normals turn.
#: (A cone is not among them: its rims are edges of its one facet.)
SMOOTH_KINDS = frozenset({"box", "cylinder", "sphere", "torus", "capsule", "halfspace"})
#: `FacetField.decide` prunes the tree per bin of points (`implicit.facet_prune`) from this many points
#: and leaves: below, sorting the points into bins costs more than the leaves it saves (the benchmark
#: part's 4 leaves at 236,000 points: 0.11 s pruned, 0.09 s whole; the gear's 26 at 30,000: 0.015, 0.079).
PRUNE_MIN_POINTS = 1024
PRUNE_MIN_LEAVES = 8


# ---------------------------------------------------------------------------
# CSG facets: which face of which primitive decides the field at a point
# ---------------------------------------------------------------------------

def _leaf_facets(node: Solid, p: np.ndarray, split: bool = False):
    """Names and values ``(k, n)`` of a leaf's facets (an extrusion's side split at its sharp
    corners when `split`, see `split_side`); the leaf is the max of them."""
    kind = node.kind
    if kind == "box" and not getattr(node, "_rr", 0.0):
        q = p - node._c
        h = node._h
        vals = np.concatenate([q - h, -q - h], axis=1).T
        names = ["+x", "+y", "+z", "-x", "-y", "-z"]
        return names, vals
    if kind == "cylinder":
        q = (p - node._c) @ node._frame.T
        dr = np.hypot(q[:, 0], q[:, 1]) - node._r
        return ["wall", "top", "bottom"], np.stack([dr, q[:, 2] - node._hh, -q[:, 2] - node._hh])
    if kind == "extrude":
        if split and extrude_runs(node) is not None:
            names, vals, _, _ = split_side(node, p)
            return names, vals
        q = (p - node._c) @ node._rot
        d = node._profile._evaluate(np.ascontiguousarray(q[:, :2]))
        return ["side", "top", "bottom"], np.stack([d, q[:, 2] - node._hh, -q[:, 2] - node._hh])
    return [""], node._evaluate(p)[None, :]


def split_side(node, p, gradients=False):
    """Names, values ``(r + 2, n)``, gradients ``(r + 2, n, 3)`` (or None) and deciding facet ``(n,)``
    of an extrusion whose side is split into `r` runs at its sharp corners (`extrude_runs`).

    Every run is called ``side`` (the side stays one face to the user); the caps
    decide where they exceed the profile's distance, elsewhere the run holding
    the nearest profile edge (not a run whose continuation past its corner
    runs nearer).
    """
    v, starts = extrude_runs(node)
    q = (p - node._c) @ node._rot
    f, g2, (near, d) = run_fields(v, starts, q[:, :2], nearest=True)
    r = f.shape[0]
    caps = np.stack([q[:, 2] - node._hh, -q[:, 2] - node._hh])
    vals = np.concatenate([f, caps])
    dec = np.where(d >= caps.max(axis=0), near, r + caps.argmax(axis=0))
    grads = None
    if gradients:
        rot = node._rot
        n = p.shape[0]
        # q = (p - c) rot: a gradient in profile coordinates goes back through rot's columns
        side = g2[:, :, :1] * rot[:, 0] + g2[:, :, 1:] * rot[:, 1]
        axis = np.broadcast_to(rot[:, 2], (n, 3))
        grads = np.concatenate([side, np.stack([axis, -axis])])
    return ["side"] * r + ["top", "bottom"], vals, grads, dec


def extrude_runs(node):
    """The runs of an extrusion's polygon side (`implicit.profile_facets.polygon_runs`), or None
    when its side is one facet (a profile other than a polygon or rectangle, or without two sharp corners)."""
    prof = node._profile
    if prof.kind == "polygon":
        return polygon_runs(prof._v)
    if prof.kind == "rectangle":
        c = np.asarray(prof.params["center"], dtype=np.float64)
        h = 0.5 * np.asarray(prof.params["size"], dtype=np.float64)
        return polygon_runs(c + h * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]))
    return None


class FacetField:
    """The facets of a CSG tree: evaluate every facet and the deciding one at once.

    A facet is a primitive leaf, or one face of a sharp box (``+x`` ... ``-z``)
    or of a cylinder (``wall``, ``top``, ``bottom``).  Facet fields are
    expressed in world coordinates (transforms and offsets applied); their
    zero sets are the surfaces the CSG boundary is cut from.  Smooth blends
    and shells count as one leaf.

    With ``split_sides=True`` the side of an extruded polygon is cut at its
    sharp corners into facets all called ``side`` (`split_side`): the tips of
    a gear's teeth are then edges where two facets meet, as the corners of a
    box are, and a corner of a tooth is the common zero of three facets.

    Parameters
    ----------
    solid : Solid
    split_sides : bool
        Split extruded polygons' sides at their sharp corners.

    Attributes
    ----------
    names : list of str
        One name per facet, e.g. ``"cylinder_2.wall"`` (kind, leaf number in
        depth-first order, facet).
    smooth : (k,) bool
        Per facet: a smooth surface (a leaf of `SMOOTH_KINDS`: no edge of its own).
    """

    def __init__(self, solid: Solid, *, split_sides: bool = False):
        if not isinstance(solid, Solid):
            raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
        self.solid = solid
        self.split_sides = bool(split_sides)
        self.names: list[str] = []
        pts = np.zeros((1, 3))
        leaves = [0]
        self._walk(solid, pts, [], self.names, leaves)
        self._n_leaves = leaves[0]
        flags: list = []
        self._smooth_flags(solid, flags)
        #: Per facet: its zero set is smooth (a plane, sphere, torus, cylinder wall... `SMOOTH_KINDS`).
        self.smooth = np.array(flags, dtype=np.bool_).reshape(-1)

    def _smooth_flags(self, node, out):
        """`smooth` in the facets' order (that of `_values`)."""
        kind = node.kind
        if kind in ("union", "intersection", "difference"):
            for c in node.children:
                self._smooth_flags(c, out)
        elif kind in ("complement", "family", "affine", "offset"):
            self._smooth_flags(node.children[0], out)
        else:
            out.extend([kind in SMOOTH_KINDS] * self._n_facets(node))

    def _walk(self, node, p, vals, names, counter):
        kind = node.kind
        if kind in ("union", "intersection", "difference"):
            return _decide(kind, [self._walk(c, p, vals, names, counter) for c in node.children])
        if kind == "family":
            # a part-family instance is its built tree: its faces are that tree's
            return self._walk(node.children[0], p, vals, names, counter)
        if kind == "complement":
            v, d = self._walk(node.children[0], p, vals, names, counter)
            return -v, d
        if kind == "affine":
            start = len(vals)
            q = np.ascontiguousarray((p - node._offset) @ node._inv.T)
            v, d = self._walk(node.children[0], q, vals, names, counter)
            f = node._factor
            if f != 1.0:
                for i in range(start, len(vals)):
                    vals[i] = vals[i] * f
                v = v * f
            return v, d
        if kind == "offset":
            start = len(vals)
            v, d = self._walk(node.children[0], p, vals, names, counter)
            dist = node.params["distance"]
            for i in range(start, len(vals)):
                vals[i] = vals[i] - dist
            return v - dist, d
        if self._split(node):
            sub, fv, _, dec = split_side(node, p)
        else:
            sub, fv = _leaf_facets(node, p)
            dec = fv.argmax(axis=0) if len(sub) > 1 else np.zeros(p.shape[0], dtype=np.intp)
        start = len(vals)
        leaf = counter[0]
        counter[0] += 1
        for j, s in enumerate(sub):
            vals.append(fv[j])
            names.append(f"{kind}_{leaf}" + (f".{s}" if s else ""))
        value = node._evaluate(p)
        return np.asarray(value, dtype=np.float64), start + dec

    def __call__(self, points):
        """Field, deciding facet and every facet's value at `points`.

        Parameters
        ----------
        points : (n, 3) array_like

        Returns
        -------
        value : (n,) float
            The solid's field.
        decider : (n,) int
            Index into `names` of the facet that decides the CSG min/max.
        facets : (k, n) float
            Every facet's field.

        Examples
        --------
        >>> from implicit import box, cylinder
        >>> ff = FacetField(box(2) - cylinder(0.5, 4))
        >>> v, d, f = ff([[0.5, 0.0, 0.0], [1.0, 0.3, 0.0]])
        >>> [ff.names[i] for i in d]
        ['cylinder_1.wall', 'box_0.+x']
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        vals: list = []
        names: list = []
        value, dec = self._walk(self.solid, p, vals, names, [0])
        return value, dec, np.stack(vals) if vals else np.zeros((0, p.shape[0]))

    def decide(self, points):
        """Field and deciding facet at `points` (`__call__` without stacking every facet's field).

        Examples
        --------
        >>> from implicit import box, cylinder
        >>> ff = FacetField(box(2) - cylinder(0.5, 4))
        >>> [ff.names[i] for i in ff.decide([[0.5, 0.0, 0.0]])[1]]
        ['cylinder_1.wall']
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        if p.shape[0] >= PRUNE_MIN_POINTS and self._n_leaves >= PRUNE_MIN_LEAVES:
            # the same results, each operand evaluated only in the bins of points it may decide
            return pruned_decide(self, p)
        return self._walk_decide(self.solid, p, [0])

    def _walk_decide(self, node, p, at):
        """`_walk` without the facets' list: the field and the deciding facet (`at`: next facet index).

        A sharp box's or a cylinder's field is built from the facet values
        already computed, by the same operations as its ``_evaluate`` (so the
        same bits: ``|x| - h`` is the larger of ``x - h`` and ``-x - h``), and
        a one-facet leaf's field is its facet: each leaf is evaluated once.
        """
        kind = node.kind
        if kind in ("union", "intersection", "difference"):
            return _decide(kind, [self._walk_decide(c, p, at) for c in node.children])
        if kind == "family":
            return self._walk_decide(node.children[0], p, at)
        if kind == "complement":
            v, d = self._walk_decide(node.children[0], p, at)
            return -v, d
        if kind == "affine":
            q = np.ascontiguousarray((p - node._offset) @ node._inv.T)
            v, d = self._walk_decide(node.children[0], q, at)
            return (v * node._factor if node._factor != 1.0 else v), d
        if kind == "offset":
            v, d = self._walk_decide(node.children[0], p, at)
            return v - node.params["distance"], d
        start = at[0]
        at[0] += self._n_facets(node)
        return self._leaf_decide(node, p, start)

    def _leaf_decide(self, node, p, start):
        """A leaf's field and deciding facet (its first facet is number `start`)."""
        kind = node.kind
        loops = leaf_loops() if kind in ("box", "cylinder", "sphere") else None
        if loops is not None:
            # one compiled loop instead of numpy's dozen passes: the same bits (`implicit.facet_leaf_kernel`)
            value, dec = np.empty(p.shape[0]), np.zeros(p.shape[0], dtype=np.intp)
            if kind == "box" and not getattr(node, "_rr", 0.0):
                loops.box_decide(np.ascontiguousarray(p), node._c, node._h, float(node._rr), value, dec)
                return value, start + dec
            if kind == "cylinder":
                fr = node._frame
                if np.all((fr == 0.0) | (fr == 1.0) | (fr == -1.0)):     # along x, y or z: no product needed
                    loops.cylinder_decide_aligned(np.ascontiguousarray(p), node._c, np.ascontiguousarray(fr),
                                                  float(node._r), float(node._hh), value, dec)
                else:
                    q = (p - node._c) @ fr.T      # (numpy's product: the same bits)
                    loops.cylinder_decide(np.ascontiguousarray(q), float(node._r), float(node._hh), value, dec)
                return value, start + dec
            if kind == "sphere":
                loops.sphere_values(np.ascontiguousarray(p), node._c, float(node._r), value)
                return value, dec + start
        if kind == "box" and not getattr(node, "_rr", 0.0):
            q = p - node._c
            up, down = q - node._h, -q - node._h
            dec = _first_max([up[:, 0], up[:, 1], up[:, 2], down[:, 0], down[:, 1], down[:, 2]])
            a = np.maximum(up, down)          # = np.abs(q) - h, bit for bit
            outside = np.sqrt(np.einsum("ij,ij->i", np.maximum(a, 0), np.maximum(a, 0)))
            inside = np.minimum(a.max(axis=1), 0.0)
            return outside + inside - node._rr, start + dec
        if kind == "cylinder":
            q = (p - node._c) @ node._frame.T
            dr = np.hypot(q[:, 0], q[:, 1]) - node._r
            top, bottom = q[:, 2] - node._hh, -q[:, 2] - node._hh
            dec = _first_max([dr, top, bottom])
            dz = np.maximum(top, bottom)      # = np.abs(q[:, 2]) - hh, bit for bit
            outside = np.hypot(np.maximum(dr, 0), np.maximum(dz, 0))
            return outside + np.minimum(np.maximum(dr, dz), 0.0), start + dec
        if self._split(node):
            _, _, _, dec = split_side(node, p)
            return np.asarray(node._evaluate(p), dtype=np.float64), start + dec
        sub, fv = _leaf_facets(node, p)
        if len(sub) == 1:
            return np.asarray(fv[0], dtype=np.float64), np.full(p.shape[0], start, dtype=np.intp)
        return np.asarray(node._evaluate(p), dtype=np.float64), start + fv.argmax(axis=0)

    def facet_values(self, points):
        """Every facet's field ``(k, n)`` alone (no CSG decision: cheaper than calling the field).

        Examples
        --------
        >>> from implicit import box
        >>> FacetField(box(2.0)).facet_values([[0.5, 0.0, 0.0]])[:, 0].tolist()
        [-0.5, -1.0, -1.0, -1.5, -1.0, -1.0]
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        vals: list = []
        self._values(self.solid, p, vals)
        return np.stack(vals) if vals else np.zeros((0, p.shape[0]))

    def _values(self, node, p, vals):
        kind = node.kind
        if kind in ("union", "intersection", "difference"):
            for c in node.children:
                self._values(c, p, vals)
        elif kind in ("complement", "family"):
            self._values(node.children[0], p, vals)
        elif kind == "affine":
            start = len(vals)
            self._values(node.children[0], np.ascontiguousarray((p - node._offset) @ node._inv.T), vals)
            if node._factor != 1.0:
                for i in range(start, len(vals)):
                    vals[i] = vals[i] * node._factor
        elif kind == "offset":
            start = len(vals)
            self._values(node.children[0], p, vals)
            for i in range(start, len(vals)):
                vals[i] = vals[i] - node.params["distance"]
        else:
            vals.extend(_leaf_facets(node, p, self.split_sides)[1])

    def values_of(self, points, which):
        """Value of facet ``which[i, j]`` at point ``i``: shape ``which.shape`` (0 where out of range).

        The same values as ``facet_values(points)[which[i, j], i]``, but only
        the leaves of the facets asked for are evaluated, each at its own points.

        Examples
        --------
        >>> from implicit import box, sphere
        >>> ff = FacetField(box(1.0) | sphere(1.0, center=(3.0, 0.0, 0.0)))
        >>> ff.values_of([[0.0, 0.0, 0.0], [3.0, 0.0, 2.0]], [[1, 0], [6, 6]]).tolist()
        [[-0.5, -0.5], [1.0, 1.0]]
        """
        p, w = _points_and_which(points, which)
        if self._n_leaves < PRUNE_MIN_LEAVES:
            # a small tree: one walk of every leaf over all points costs less than walking it per facet
            ok = (w >= 0) & (w < len(self.names))
            fv = self.facet_values(p)
            out = np.where(ok, fv[np.where(ok, w, 0), np.arange(p.shape[0])[:, None]], 0.0)
        else:
            out = subset_values(self, p, w)
        return out.reshape(np.shape(which))

    def _leaf_values(self, node, p):
        """Every facet's field ``(k, n)`` of the leaf `node` (`facet_values`'s rows of it)."""
        return _leaf_facets(node, p, self.split_sides)[1]

    def facet_gradients(self, points, step=1e-7):
        """Gradients of every facet field by central differences, shape ``(k, n, 3)``.

        (The FEA surface's snapping relies on these; `facets_with_gradients`
        and `gradients_of` give the closed forms.)
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        n = p.shape[0]
        off = np.concatenate([np.eye(3), -np.eye(3)]) * step
        probe = (p[None, :, :] + off[:, None, :]).reshape(-1, 3)
        _, _, f = self(probe)
        f = f.reshape(len(self.names), 6, n)
        return np.moveaxis((f[:, :3] - f[:, 3:]) / (2 * step), 1, 2)

    def gradients_of(self, points, which, step=1e-7):
        """Exact gradient of facet ``which[i, j]`` at point ``i``: shape ``which.shape + (3,)``.

        Only the facets asked for are differentiated, each at its own points
        (the cheap way to the normals of a few faces at many points).

        Examples
        --------
        >>> from implicit import box, sphere
        >>> ff = FacetField(box(1.0) | sphere(1.0, center=(3.0, 0.0, 0.0)))
        >>> ff.gradients_of([[0.0, 0.0, 0.0], [3.0, 0.0, 2.0]], [1, 6]).tolist()
        [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        """
        p, w = _points_and_which(points, which)
        rows, cols = np.nonzero((w >= 0) & (w < len(self.names)))
        out = np.zeros(w.shape + (3,))
        g = np.zeros((rows.shape[0], 3))
        order = facet_order(w[rows, cols], len(self.names))
        rows, cols = rows[order], cols[order]
        fac = w[rows, cols]
        self._grad_walk(self.solid, p, rows, fac, g, [0], step)
        out[rows, cols] = g
        return out.reshape(np.shape(which) + (3,))

    def _grad_walk(self, node, p, rows, fac, g, counter, step):
        """Gradients of facets ``fac`` (sorted) at points ``p[rows]`` into `g`; returns the facet range done."""
        kind = node.kind
        start = counter[0]
        if kind in ("union", "intersection", "difference"):
            lo, hi = np.searchsorted(fac, [start, start + self._n_facets(node)])
            if hi == lo:                          # no facet of this subtree is asked for
                counter[0] += self._n_facets(node)
                return start, counter[0]
            for c in operands(self, node):
                if type(c) is Capsules:           # a run of capsules: one compiled loop over their rows
                    c.gradients(p, rows, fac, g, counter)
                else:
                    self._grad_walk(c, p, rows, fac, g, counter, step)
        elif kind in ("complement", "family", "offset"):
            self._grad_walk(node.children[0], p, rows, fac, g, counter, step)
        elif kind == "affine":
            lo, hi = np.searchsorted(fac, [start, start + self._n_facets(node)])
            if hi > lo:
                # only the rows asked for are mapped (each row's product does not depend on the others)
                need = np.unique(rows[lo:hi])
                q = np.empty_like(p)
                q[need] = (p[need] - node._offset) @ node._inv.T
                self._grad_walk(node.children[0], q, rows, fac, g, counter, step)
                # q = inv (p - offset): the chain rule takes a gradient g(q) to g(q) inv
                g[lo:hi] = g[lo:hi] @ (node._inv * node._factor)
            else:
                counter[0] += self._n_facets(node)
        else:
            k = self._n_facets(node)
            lo, hi = np.searchsorted(fac, [start, start + k])
            if hi > lo:
                sel = slice(lo, hi)
                at = np.ascontiguousarray(p[rows[sel]])
                if self._split(node):
                    fg = split_side(node, at, gradients=True)[2]
                else:
                    _, _, fg = leaf_facets_with_gradients(node, at, step, _leaf_facets)
                g[sel] = fg[fac[sel] - start, np.arange(hi - lo)]
            counter[0] += k
        return start, counter[0]

    def _split(self, node):
        """Whether `node` is an extrusion whose side this field splits at its sharp corners."""
        return self.split_sides and node.kind == "extrude" and extrude_runs(node) is not None

    def _n_facets(self, node):
        """Number of facets under `node` (cached per node id)."""
        cache = self.__dict__.setdefault("_count_cache", {})
        key = id(node)
        if key not in cache:
            if node.kind in ("union", "intersection", "difference", "complement", "family", "offset", "affine"):
                cache[key] = sum(self._n_facets(c) for c in node.children)
            else:
                cache[key] = len(_leaf_facets(node, np.zeros((1, 3)), self.split_sides)[0])
        return cache[key]

    def facets_with_gradients(self, points, step=1e-7, decide=False):
        """Every facet's field ``(k, n)`` and gradient ``(k, n, 3)`` in one walk of the tree.

        With ``decide=True`` the solid's field ``(n,)`` and the deciding
        facet ``(n,)`` are returned first, as by calling the field.

        Examples
        --------
        >>> from implicit import box
        >>> f, g = FacetField(box(2.0)).facets_with_gradients([[0.5, 0.0, 0.0]])
        >>> f[0, 0], g[0, 0].tolist()
        (-0.5, [1.0, 0.0, 0.0])
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        vals: list = []
        grads: list = []
        vd = self._walk_grad(self.solid, p, vals, grads, [0], step, decide)
        if vals:
            f, g = np.stack(vals), np.stack(grads)
        else:
            f, g = np.zeros((0, p.shape[0])), np.zeros((0, p.shape[0], 3))
        return (vd[0], vd[1], f, g) if decide else (f, g)

    def _walk_grad(self, node, p, vals, grads, counter, step, decide):
        kind = node.kind
        if kind in ("union", "intersection", "difference"):
            results = [self._walk_grad(c, p, vals, grads, counter, step, decide) for c in node.children]
            return _decide(kind, results) if decide else None
        if kind == "family":
            return self._walk_grad(node.children[0], p, vals, grads, counter, step, decide)
        if kind == "complement":
            r = self._walk_grad(node.children[0], p, vals, grads, counter, step, decide)
            return (-r[0], r[1]) if decide else None
        if kind == "affine":
            start = len(vals)
            q = np.ascontiguousarray((p - node._offset) @ node._inv.T)
            r = self._walk_grad(node.children[0], q, vals, grads, counter, step, decide)
            f = node._factor
            # q = inv (p - offset): the chain rule takes a gradient g(q) to g(q) inv
            jac = node._inv * f
            for i in range(start, len(vals)):
                grads[i] = grads[i] @ jac
                if f != 1.0:
                    vals[i] = vals[i] * f
            return (r[0] * f, r[1]) if decide else None
        if kind == "offset":
            start = len(vals)
            r = self._walk_grad(node.children[0], p, vals, grads, counter, step, decide)
            dist = node.params["distance"]
            for i in range(start, len(vals)):
                vals[i] = vals[i] - dist
            return (r[0] - dist, r[1]) if decide else None
        if self._split(node):
            sub, fv, fg, dec = split_side(node, p, gradients=True)
        else:
            sub, fv, fg = leaf_facets_with_gradients(node, p, step, _leaf_facets)
            dec = fv.argmax(axis=0) if len(sub) > 1 else np.zeros(p.shape[0], dtype=np.intp)
        start = len(vals)
        counter[0] += 1
        vals.extend(fv)
        grads.extend(fg)
        if not decide:
            return None
        value = fv[0] if len(sub) == 1 else np.asarray(node._evaluate(p), dtype=np.float64)
        dec = start + dec
        return np.asarray(value, dtype=np.float64), dec


def _points_and_which(points, which):
    """Points as a contiguous (n, 3) array and `which` as (n, k) facet indices, one row per point."""
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    w = np.asarray(which, dtype=np.int64)
    if w.ndim == 1:
        w = w[:, None]
    if w.shape[0] != p.shape[0] or w.ndim != 2:
        raise ValueError(f"which: expected one facet index (or one row) per point, got shape {w.shape}")
    return p, w


def facet_field(solid: Solid) -> FacetField:
    """The `FacetField` of `solid` (see there)."""
    return FacetField(solid)


def _first_max(rows):
    """Index of the first largest of the equal-length arrays `rows`, per column (``argmax`` of their stack)."""
    best = rows[0]
    idx = np.zeros(best.shape[0], dtype=np.intp)
    for j in range(1, len(rows)):
        more = rows[j] > best
        idx[more] = j
        best = np.maximum(best, rows[j])
    return idx


def _decide(kind, results):
    """The value of a sharp Boolean and, per point, the face that decides it.

    `results` holds each child's ``(values, deciding face)``; a difference
    negates its tools' values, a union takes the smallest, the others the largest.
    """
    if len(results) == 2:
        # two operands (most Booleans): the second wins where it is strictly better, or a NaN against a
        # number (what ``argmin`` / ``argmax`` of their stack pick), without the stack and its gathers
        (a, da), (b, db) = results
        if kind == "difference":
            b = b * -1.0
        second = (b < a) if kind == "union" else (b > a)
        second |= np.isnan(b) & ~np.isnan(a)
        return np.where(second, b, a), np.where(second, db, da)
    values = np.stack([r[0] for r in results])
    decs = np.stack([r[1] for r in results])
    if kind == "difference":
        values[1:] *= -1.0
    idx = values.argmin(axis=0) if kind == "union" else values.argmax(axis=0)
    cols = np.arange(values.shape[1])
    return values[idx, cols], decs[idx, cols]
