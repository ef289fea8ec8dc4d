"""The faces a CSG tree knows, and projection onto a solid's surface.

Every primitive leaf of a CSG tree (and each flat or cylindrical facet of a
sharp box or a cylinder) is a *facet*; each point is attributed to the facet
that decides the CSG ``min``/``max`` there (`implicit.facets.FacetField`, re-exported here).  Facets name the
boundary regions of FEA meshes and guide vertices onto the sharp edges and
corners where facets meet (`solve_on_facets`).  `project_to_surface` takes
points onto the zero set with Newton steps along the gradient.
"""

from __future__ import annotations

import numpy as np

from implicit.facets import FacetField as _TreeFacets
from implicit.solid import Solid

__all__ = ["FacetField", "facet_field", "face_names", "independent_facets", "project_to_surface", "solve_on_facets",
           "value_and_gradient", "NEWTON_STEPS"]

#: Nodes whose facets are those of their children (the others are leaves of `_TreeFacets`).
_COMPOSITE = ("union", "intersection", "difference", "complement", "family", "offset", "affine")


class FacetField(_TreeFacets):
    """The facets of a CSG tree (`implicit.facets.FacetField`), named as the model names them.

    A facet of a node that a part family labelled (`implicit.families.label`)
    is called by that label (``hole_1.wall``, ``bracket.base_bottom``); the
    others keep the names the tree gives them (``box_0.+x``,
    ``cylinder_2.wall``: kind, leaf number in depth-first order, face).
    Several facets may share a name (coplanar faces of one part): they make
    one face set.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> from implicit.families import instance
    >>> FacetField(box(2) - cylinder(0.5, 4)).names[-3:]
    ['cylinder_1.wall', 'cylinder_1.top', 'cylinder_1.bottom']
    >>> FacetField(instance("hole_plate", rows=1, cols=1)).names[-3:]
    ['hole_1.wall', 'hole_1.top', 'hole_1.bottom']
    """

    def __init__(self, solid: Solid, *, split_sides: bool = False):
        super().__init__(solid, split_sides=split_sides)
        self.names = _labelled_names(self, solid, self.names)


def facet_field(solid: Solid) -> FacetField:
    """The `FacetField` of `solid` (see there)."""
    return FacetField(solid)


def _labelled_names(ff, solid, names):
    """`names` with the facets of labelled nodes renamed by their (innermost) label."""
    from implicit.families import FamilyInstance

    labels = {}
    for node in solid.walk():
        if isinstance(node, FamilyInstance):
            for labelled, name, faces in node.labels:
                labels.setdefault(id(labelled), (name, faces))
    if not labels:
        return list(names)
    out = list(names)
    done = [False] * len(names)

    def visit(node, start):
        if node.kind in _COMPOSITE:
            at = start
            for child in node.children:
                visit(child, at)
                at += ff._n_facets(child)
        lab = labels.get(id(node))
        if lab is None:
            return
        name, faces = lab
        for i in range(start, start + ff._n_facets(node)):
            if not done[i]:
                sub = names[i].split(".", 1)[1] if "." in names[i] else ""
                face = faces.get(sub, sub)
                out[i] = face if "." in face else f"{name}.{face}" if face else name
                done[i] = True

    visit(solid, 0)
    return out


#: Newton steps used to put a point back on the zero set.
NEWTON_STEPS = 6

# ---------------------------------------------------------------------------
# projection onto the zero set
# ---------------------------------------------------------------------------

def project_to_surface(solid: Solid, points, *, steps: int = NEWTON_STEPS, max_move=None) -> np.ndarray:
    """Move `points` onto the zero set of `solid` by Newton steps along its gradient.

    Each step is ``p <- p - f(p) grad f / |grad f|^2``.  Points whose total
    move would exceed `max_move` are left where they were.

    Parameters
    ----------
    solid : Solid
    points : (n, 3) array_like
    steps : int
        Number of Newton steps.
    max_move : float, optional
        Largest allowed displacement.

    Returns
    -------
    (n, 3) float ndarray

    Examples
    --------
    >>> from implicit import sphere
    >>> project_to_surface(sphere(1.0), [[0.0, 0.0, 0.9]]).round(12).tolist()
    [[0.0, 0.0, 1.0]]
    """
    p0 = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    p = p0.copy()
    lo, hi = solid.bounds
    ext = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
    h = 1e-7 * max(float(np.max(ext)), 1.0)
    for _ in range(steps):
        f, g = value_and_gradient(solid, p, h)
        g2 = np.einsum("ij,ij->i", g, g)
        ok = g2 > 1e-12
        p[ok] -= (f[ok] / g2[ok])[:, None] * g[ok]
    if max_move is not None:
        far = np.linalg.norm(p - p0, axis=1) > max_move
        p[far] = p0[far]
    return p


#: Central-difference probes of `value_and_gradient`: the point itself, then +x +y +z -x -y -z.
_PROBES = np.concatenate([np.zeros((1, 3)), np.eye(3), -np.eye(3)])


def value_and_gradient(solid: Solid, points, step):
    """The field and its central-difference gradient (step `step`) at `points` ``(n, 3)``.

    One evaluation of the seven probes of every point: the evaluator's cost per
    call (pruning, binning) is paid once instead of twice.

    Examples
    --------
    >>> from implicit import sphere
    >>> f, g = value_and_gradient(sphere(1.0), np.array([[0.0, 0.0, 2.0]]), 1e-6)
    >>> f.round(9).tolist(), g.round(6).tolist()
    ([1.0], [[0.0, 0.0, 1.0]])
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    vals = solid((p[:, None, :] + step * _PROBES).reshape(-1, 3)).reshape(-1, 7)
    return vals[:, 0], (vals[:, 1:4] - vals[:, 4:]) / (2.0 * step)


def solve_on_facets(ff: FacetField, p, sets, iters=8):
    """Move points onto the common zero set of 2 or 3 facets (an edge or a corner).

    Gauss-Newton with the minimum-norm step ``dp = -J^T (J J^T)^-1 f`` on the
    chosen facets' fields.

    Parameters
    ----------
    ff : FacetField
    p : (n, 3) float
        Start points.
    sets : (n, k) int
        Facet indices per point, ``k`` <= 3; -1 leaves a slot unused.
    iters : int
        Number of steps.

    Returns
    -------
    (n, 3) float ndarray

    Examples
    --------
    >>> from implicit import box
    >>> ff = FacetField(box(2.0))          # facets +x +y +z -x -y -z
    >>> solve_on_facets(ff, np.array([[0.9, 0.8, 0.7]]), np.array([[0, 1, 2]])).round(12).tolist()
    [[1.0, 1.0, 1.0]]
    """
    p = p.copy()
    k = sets.shape[1]
    used = sets >= 0
    idx = np.where(used, sets, 0)
    rows = np.arange(p.shape[0])
    scale = max(float(np.abs(p).max(initial=0.0)), 1.0)
    for _ in range(iters):
        f = ff.facet_values(p)
        fv = f[idx, rows[:, None]] * used
        if not np.any(np.abs(fv) > 1e-15 * scale):
            break  # every point is on its facets to rounding: further steps only shuffle the last bits
        # Central differences of every facet (the closed-form gradients of the chosen ones differ in the last
        # bits, which moved the beam's surface at size 8 off a corner).
        g = ff.facet_gradients(p)
        J = np.stack([g[idx[:, j], rows] for j in range(k)], axis=1) * used[:, :, None]
        # Minimum-norm step: dp = -J^T (J J^T)^+ f.
        JJ = J @ np.swapaxes(J, 1, 2) + np.where(used, 0.0, 1.0)[:, :, None] * np.eye(k)
        try:
            y = np.linalg.solve(JJ, fv[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            y = np.einsum("nij,nj->ni", np.linalg.pinv(JJ), fv)
        step = np.einsum("nji,nj->ni", J, y)
        p -= step
        if not step.any():
            break  # a fixed point: every further step is zero as well
    return p


def independent_facets(ff: FacetField, points, near, count=3, parallel=0.99):
    """Up to `count` facets per point, taken in order from `near`, whose gradients are independent.

    Coplanar faces of solids that touch (the -z faces of both legs of an L
    bracket) are all near 0 along an edge or corner, but only facets that
    cross define it: a facet is skipped when its gradient lies (within
    `parallel` as |cos|, or within the plane of the two taken) in the span
    of the facets already taken.

    Parameters
    ----------
    ff : FacetField
    points : (n, 3) float
    near : (k, n) bool
        Facets that may be used at each point, in order of preference (index order).
    count : {2, 3}
    parallel : float

    Returns
    -------
    (n, count) int
        Facet indices, -1 where fewer independent facets were found.

    Examples
    --------
    >>> from implicit import box
    >>> ff = FacetField(box(2.0, center=(0, 0, 0)) | box(2.0, center=(2, 0, 0)))
    >>> near = np.abs(ff([[1.0, 1.0, 1.0]])[2]) < 1e-9        # +x, +y, +z of one, -x, +y, +z of the other
    >>> [ff.names[i] for i in independent_facets(ff, np.array([[1.0, 1.0, 1.0]]), near)[0]]
    ['box_0.+x', 'box_0.+y', 'box_0.+z']
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n = p.shape[0]
    out = np.full((n, count), -1, dtype=np.int64)
    if n == 0:
        return out
    g = ff.facet_gradients(p)
    g = g / np.maximum(np.linalg.norm(g, axis=2, keepdims=True), 1e-300)
    taken = np.zeros(n, dtype=np.int64)
    basis = np.zeros((n, 3, 3))
    rows = np.arange(n)
    for k in range(near.shape[0]):
        gk = g[k]
        # Component of the gradient outside the span of the facets taken (Gram-Schmidt).
        resid = gk - np.einsum("nij,nj->ni", np.swapaxes(basis, 1, 2), np.einsum("nij,nj->ni", basis, gk))
        r = np.linalg.norm(resid, axis=1)
        ok = near[k] & (taken < count) & (r > np.sqrt(1.0 - parallel**2))
        if not ok.any():
            continue
        idx = rows[ok]
        out[idx, taken[idx]] = k
        basis[idx, taken[idx]] = resid[idx] / r[idx, None]
        taken[idx] += 1
    return out


def face_names(solid: Solid, *, resolution: int = 48) -> list:
    """Names of the facets that make part of the boundary of `solid` (the FEA face sets).

    The boundary is meshed coarsely (`resolution` cells across), its vertices
    are put on the surface and each is attributed to its deciding facet;
    facets of the tree that never reach the boundary (the caps of a
    cylinder cut through a plate) are left out.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> face_names(box(2.0) - cylinder(0.5, 4.0))
    ['box_0.+x', 'box_0.+y', 'box_0.+z', 'box_0.-x', 'box_0.-y', 'box_0.-z', 'cylinder_1.wall']
    """
    from ..meshing.boundary import mesh

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    ff = FacetField(solid)
    if not solid.is_bounded or solid.is_empty_bounds:
        return sorted(set(ff.names))
    surf = mesh(solid, resolution=resolution, progress=False)
    if surf.n_points == 0:
        return []
    p = project_to_surface(solid, np.asarray(surf.points, dtype=np.float64))
    _, dec, _ = ff(p)
    return sorted({ff.names[i] for i in np.unique(dec)})
