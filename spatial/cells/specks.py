"""Features the lattice may lose, whatever their shape: specks, slivers, knife edges, thin gaps.

`spatial.cells.walls` measures walls between parallel faces; a speck left by
an intersection, the sliver of a knife edge or a gap closed by an offset has
no such faces.  What every lost feature has is a local extremum of the field
near the surface: the field of a part thick enough for the lattice falls
from any sample near its surface towards the inside, so among the samples a
shallow local minimum (``f`` no larger than at any neighbour) is a place
where material ends on every side within a few voxels -- a speck, a sliver,
the tip of a knife edge -- and a shallow local maximum a gap closed on every
side.  `lost_feature` finds them at surface cost:

1. the octree's classification already sampled the centres of the BOUNDARY
   cells of edge ``2h`` (lattice nodes, every one within reach of the
   surface) and knows the sign of the uniform cells around them; a BOUNDARY
   cell whose centre value is a minimum (or maximum) of its 26 neighbours'
   is a candidate -- the neighbours are read for the cells still in the
   running only (the six faces rule out nearly every cell of a smooth
   surface), no evaluation but for a neighbour of unknown sign, inside a
   uniform cell larger than ``4h``;
2. a candidate deeper than ``L h`` on its side holds a ball of material (or of
   gap) a voxel in radius and is dropped (never lost: see `speck_candidates`);
   around each other one -- the shallowest first, as many as the budget
   allows (`candidate_budget`: `MIN_CANDIDATES`, and one more per
   `CELLS_PER_CANDIDATE` BOUNDARY cells, so that the cost follows the
   surface) -- the field is sampled on a grid `FINER` times finer than the
   lattice over ``4h`` a side; the feature's thickness is twice the largest distance from a fine
   sample inside it to one outside (a Euclidean distance transform: the
   field's values need not be distances) and its extent the span of its
   fine samples inside;
3. a feature thinner than two voxels (the rule of the walls) may be lost:
   it is named by the facets nearest its deepest point
   (`implicit.facets.FacetField`) with the voxel that keeps it, a quarter of
   its thickness (`WALL_VOXELS`); candidates beyond the budget are counted,
   and the warning says how many were not examined and about which voxel
   examines them all.

The search (step 1) and the measurement (steps 2-3) are separate
(`speck_candidates`, `examine`) so that the cluster mesher finds the
candidates brick by brick on its workers and measures them together on the
client: the same candidates, budget and warning as one process.

A candidate whose fine samples hold no material (a feature thinner than a
fine step, or none) is sampled once more `FINER` times finer about its
smallest sample.

Examples
--------
Two plates 0.015 thick cut out of a box and the rest taken from a block
leave two gaps in the material that neither the tree nor the walls know:

>>> import warnings
>>> from implicit import box
>>> from spatial import mesh
>>> part = box(2.0) - (box(1.0, center=(0.01, 0, 0)) - box((1.2, 1.2, 0.97), center=(0.01, 0, 0)))
>>> with warnings.catch_warnings(record=True) as said:
...     warnings.simplefilter("always")
...     m = mesh(part, voxel_size=0.05, progress=False)
>>> ["a thin gap" in str(w.message) for w in said]
[True]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["LostFeature", "lost_feature", "speck_candidates", "examine", "candidate_budget", "warn_lost",
           "warn_feature",
           "FINER", "MIN_CANDIDATES", "CELLS_PER_CANDIDATE"]

#: Fine samples per voxel around a candidate.
FINER = 4
#: Candidates sampled finely whatever the surface (the shallowest first).
MIN_CANDIDATES = 48
#: One more candidate examined per this many BOUNDARY cells of edge 2h: a candidate's ``17**3`` fine
#: samples cost about as much as meshing 15-25 cells, so the examination stays within a few % of the
#: mesh (benchmark part, bench/bench_specks.py).
CELLS_PER_CANDIDATE = 512
#: A feature thinner than this many voxels may be lost (the walls' rule: coarser than half of it).
LOST_VOXELS = 2.0
#: Largest grid of cells of edge 2h held at once: a shell whose box holds more is searched slab by
#: slab along x (float32: 64 MB).
DENSE_CELLS = 1 << 24
#: Marks a neighbour of unknown value asked for (above any value or `_FAR`, until written).
_MARK = 3e38
#: Value standing for a uniform cell's (beyond any boundary cell's value).
_FAR = 1e30


@dataclass(frozen=True)
class LostFeature:
    """The thinnest feature the lattice may lose: `kind` ('material' or 'gap'), `thickness`, its
    `extent` across, a point `at` inside it, the facets `between` that bound it, `count`, the
    candidates found thinner than two voxels, and the `resolution` of the measurement (the fine
    samples' spacing: the thickness is known to within it)."""

    kind: str
    thickness: float
    extent: float
    at: tuple
    between: str
    count: int = 1
    resolution: float = 0.0
    #: Candidates beyond the budget, not examined (`examine`), and the voxel whose budget examines them all.
    unexamined: int = 0
    examine_voxel: float = 0.0

    def describe(self) -> str:
        """One phrase naming the feature: ``'a thin piece of material 0.02 thick, 0.05 across, bounded by ... near (x, y, z)'``."""
        if self.kind == "unexamined":
            return f"{self.unexamined} candidates for a feature the lattice may lose not examined"
        where = ", ".join(f"{v:.4g}" for v in self.at)
        what = "a thin piece of material" if self.kind == "material" else "a thin gap"
        who = f" bounded by {self.between}" if self.between else ""
        more = f" (and {self.count - 1} more)" if self.count > 1 else ""
        return f"{what} {self.thickness:.3g} thick, {self.extent:.3g} across,{who} near ({where}){more}"

    def keep_voxel(self, voxels=4):
        """The voxel size that keeps the feature: `voxels` through its thickness."""
        return self.thickness / voxels


def lost_feature(solid, origin, h, cells, centres, *, uniform=None, uniform_parents=None, name_by=None,
                 budget=None):
    """The thinnest feature under two voxels the lattice may lose (see the module notes), or None.

    Parameters
    ----------
    solid : Solid
        The solid meshed (its field is sampled around the candidates).
    origin : (3,) float
        The lattice's origin; cell ``c`` of edge ``2h`` has its centre at ``origin + (2c + 1) h``.
    h : float
        The voxel size.
    cells : (m, 3) int
        The BOUNDARY cells of edge ``2h``.
    centres : (m,) float
        The field at their centres.
    uniform, uniform_parents : ((k, 3) int, (k,) int8), optional
        The uniform cells of edge ``2h`` and ``4h`` found around them, with their signs.
    name_by : Solid, optional
        The solid whose facets name the feature (default `solid`).
    budget : int, optional
        Candidates examined at most (default `candidate_budget` of the cells).

    Returns
    -------
    LostFeature or None
        None when no candidate examined is lost and none was left unexamined; a feature of kind
        ``'unexamined'`` when none examined is lost but the budget left some out.

    Examples
    --------
    >>> from implicit import box, sphere
    >>> from spatial.cells.lattice import make_lattice
    >>> from spatial.meshing.boundary import boundary_cells_2h
    >>> lat = make_lattice(box(1.0) | sphere(0.03, (0.0, 0.0, 0.8)), voxel_size=0.1)
    >>> found = boundary_cells_2h(lat, False)
    >>> lost_feature(lat.solid, lat.origin, 0.1, found["cells"], found["centres"], uniform=found["uniform"],
    ...              uniform_parents=found["uniform_parents"]).kind
    'material'
    """
    cells = np.asarray(cells)
    centres = np.asarray(centres, dtype=np.float64)
    if cells.shape[0] == 0 or centres.shape[0] != cells.shape[0]:
        return None
    pts, side, depth = speck_candidates(solid, origin, h, cells, centres, uniform=uniform,
                                        uniform_parents=uniform_parents)
    return examine(solid, pts, side, depth, h, cells=cells.shape[0], budget=budget, name_by=name_by)


def candidate_budget(boundary_cells):
    """Candidates examined for a shell of `boundary_cells` BOUNDARY cells of edge 2h: `MIN_CANDIDATES`,
    plus one per `CELLS_PER_CANDIDATE` cells (the examination's cost follows the mesh's)."""
    return max(MIN_CANDIDATES, int(boundary_cells) // CELLS_PER_CANDIDATE)


def _lipschitz(solid):
    lip = float(getattr(solid, "lipschitz", 1.0) or 1.0)
    return lip if math.isfinite(lip) and lip > 0 else 1.0


def speck_candidates(solid, origin, h, cells, centres, *, uniform=None, uniform_parents=None):
    """The places a feature may be lost: the BOUNDARY cells of edge 2h whose centre value is a local
    minimum (side +1, material) or maximum (side -1, gap) of its 26 neighbours' (step 1 of the notes).

    A candidate whose centre lies deeper than ``L h`` on its side (``L`` the Lipschitz constant) is
    dropped: a ball of radius ``h`` about it is all material (or all gap), so its measured thickness
    is at least ``2h`` less a fine step, never lost.  A neighbour of `cells` outside them and the
    uniform cells given is sampled, so a part of the lattice (a brick) gives the candidates it holds.

    Returns
    -------
    points : (k, 3) float
        The candidates' cell centres.
    side : (k,) int8
    depth : (k,) float
        ``|f|`` at the centres (the shallowest are examined first).
    """
    cells = np.asarray(cells)
    centres = np.asarray(centres, dtype=np.float64)
    none = np.zeros((0, 3)), np.zeros(0, np.int8), np.zeros(0)
    if cells.shape[0] == 0 or centres.shape[0] != cells.shape[0]:
        return none
    origin = np.asarray(origin, dtype=np.float64)
    cand, side = _candidates(solid, origin, h, cells, centres, uniform, uniform_parents)
    if cand.size == 0:
        return none
    v = centres[cand]
    keep = side * v >= -_lipschitz(solid) * h * (1 + 1e-9)
    cand, side = cand[keep], side[keep]
    return origin + (2 * cells[cand].astype(np.float64) + 1) * h, side, np.abs(centres[cand])


def examine(solid, points, side, depth, h, *, cells, budget=None, name_by=None):
    """Measure the candidates of `speck_candidates` (steps 2-3 of the notes): the thinnest lost, or None.

    Candidates side by side (neighbouring cells) with the same value (to float32, the ties of the
    search) are one plateau of the field -- a flat face lying on the cells' centres, a fillet's flat
    field -- and one feature at most: the first of each plateau is measured before any second one.
    `cells` is the number of BOUNDARY cells of edge 2h the candidates come from; the `budget`
    (default `candidate_budget` of them) are measured in that order, the shallowest first, ties broken
    by position, so that candidates gathered in any order give the same answer.  The plateaus with no
    candidate measured are counted in ``unexamined``, with ``examine_voxel`` the voxel whose shell of
    cells (growing as ``1 / h**2``) buys a budget for them all, when their number stays.  When none
    measured is lost but some plateaus were left out, a `LostFeature` of kind ``'unexamined'`` says so.
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    side = np.asarray(side, dtype=np.int8)
    depth = np.asarray(depth, dtype=np.float64)
    if points.shape[0] == 0:
        return None
    budget = max(1, int(candidate_budget(cells) if budget is None else budget))
    order = np.lexsort((points[:, 2], points[:, 1], points[:, 0], depth))
    plateau = _plateaus(points[order], side[order], depth[order], h)
    # the plateaus' first members first, then their second ones...: each in the order above
    resort = np.lexsort((np.arange(order.size), _rank_within(plateau)))
    order, plateau = order[resort], plateau[resort]
    over = int(np.unique(plateau).size - np.unique(plateau[:budget]).size)
    order = order[:budget]
    feat = _measure(solid, points[order], side[order], h, _lipschitz(solid), solid if name_by is None else name_by)
    if not over:
        return feat
    plateaus = int(np.unique(plateau).size)
    finer = h * min(1.0, math.sqrt(max(int(cells), 1) / plateaus / CELLS_PER_CANDIDATE))
    if feat is None:
        return LostFeature("unexamined", math.nan, math.nan, tuple(float(v) for v in points[order[-1]]), "", 0,
                           0.0, over, finer)
    return replace(feat, unexamined=over, examine_voxel=finer)


def _plateaus(points, side, depth, h):
    """Label of each candidate's plateau: the candidates joined through neighbouring cells (of the 26
    about each) of the same side and float32 value."""
    n = points.shape[0]
    if n < 2:
        return np.zeros(n, np.int64)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    # the cells of edge 2h, from their centres, as sorted linear keys of their box (one cell of margin)
    c = np.rint((points - points.min(axis=0)) / (2 * h)).astype(np.int64) + 1
    span = c.max(axis=0) + 2
    key = (c[:, 0] * span[1] + c[:, 1]) * span[2] + c[:, 2]
    order = np.argsort(key, kind="stable")
    skey = key[order]
    value = (side * depth).astype(np.float32)
    ends = []
    # half the neighbours: each pair once
    for d in (o for o in _offsets() if tuple(o) > (0, 0, 0)):
        k = key + (d[0] * span[1] + d[1]) * span[2] + d[2]
        pos = np.minimum(np.searchsorted(skey, k), n - 1)
        hit = np.flatnonzero(skey[pos] == k)
        other = order[pos[hit]]
        same = value[hit] == value[other]
        ends.append(np.stack([hit[same], other[same]], axis=1))
    pairs = np.concatenate(ends)
    graph = coo_matrix((np.ones(pairs.shape[0], np.int8), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def _rank_within(labels):
    """Each element's rank among the elements of its label, in the array's order."""
    order = np.argsort(labels, kind="stable")
    sorted_labels = labels[order]
    starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]])
    counts = np.diff(np.r_[starts, labels.size])
    rank = np.empty(labels.size, np.int64)
    rank[order] = np.arange(labels.size) - np.repeat(starts, counts)
    return rank


def _candidates(solid, origin, h, cells, centres, uniform, uniform_parents):
    """Indices of the BOUNDARY cells whose centre value is a minimum (side +1) or maximum (side -1)
    of its 26 neighbours'.

    The values known -- the BOUNDARY cells' centres, the signs of the uniform cells of edge 2h and
    4h as ``+-_FAR`` -- fill a grid over the shell's box, slab by slab along x when the box holds
    more than `DENSE_CELLS` cells (compiled: passes over the cells only; a slab's grid is cleared by
    writing NaN where it was written, so the cost follows the shell, not its box).  A slab's grid
    holds one plane more on each side, so every cell sees its 26 neighbours as the whole box would.
    A neighbour of unknown sign (inside a uniform cell larger than ``4h``) is sampled.
    """
    from . import specks_kernels as K

    lo, hi = K.box(cells)
    # the box starts on an even cell, so that a parent of edge 4h maps to whole children
    lo = lo - 1 - (lo - 1) % 2
    dims = hi + 2 - lo
    plane = int(dims[1] * dims[2])
    n = int(dims[0])
    # core planes per slab: the whole box when it fits, else what fits with a plane on each side
    per = n if n * plane <= DENSE_CELLS else max(1, DENSE_CELLS // plane - 2)
    known = [(u[0], u[1], k) + K.by_plane(u[0][:, 0], k, int(lo[0]), n)
             for u, k in ((uniform_parents, 2), (uniform, 1)) if u is not None and len(u[0])]
    order, starts = K.by_plane(cells[:, 0], 1, int(lo[0]), n)
    buf = np.full(min(n, per + 2) * plane, np.nan, dtype=np.float32)
    offs = _offsets()
    deltas = (offs[:, 0] * plane + offs[:, 1] * int(dims[2]) + offs[:, 2]).astype(np.int64)
    mark, far, nan = np.float32(_MARK), np.float32(_FAR), np.float32(np.nan)
    clear = np.full(1, np.nan)
    status = np.zeros(cells.shape[0], np.int8)
    for p0 in range(0, n, per):
        p1 = min(p0 + per, n)
        core = order[starts[p0]:starts[p1]]
        if core.size == 0:
            continue
        g0, g1 = max(p0 - 1, 0), min(p1 + 1, n)
        sdims = np.array([g1 - g0, dims[1], dims[2]], dtype=np.int64)
        shift = -lo - np.array([g0, 0, 0], dtype=np.int64)
        grid = buf[:(g1 - g0) * plane]
        # the uniform cells over the slab's planes (a parent of 4h over the plane below too)
        parts = [(uc, signs, k, by[at[max(g0 - k + 1, 0)]:at[g1]]) for uc, signs, k, by, at in known]
        for uc, signs, k, which in parts:
            K.fill(grid, sdims, uc, signs, which, k, shift, far)
        # the cells' own values as float32 too, so that a tie stays a tie
        near = order[starts[g0]:starts[g1]]
        K.put(grid, sdims, cells, near, shift, centres)
        st, ask = K.extrema(grid, sdims, cells, shift, core, deltas, mark)
        if ask.size:
            # neighbours of unknown sign: sampled, then the undecided cells decided again
            q = np.stack([ask // plane + g0, (ask // int(dims[2])) % dims[1], ask % int(dims[2])], axis=1)
            K.put_flat(grid, ask, np.asarray(solid(origin + (2 * (q + lo) + 1) * h), dtype=np.float32))
            again = np.flatnonzero(st == 2)
            st[again] = K.extrema(grid, sdims, cells, shift, core[again], deltas, mark)[0]
        status[core] = st
        if p1 < n:
            for uc, signs, k, which in parts:
                K.fill(grid, sdims, uc, signs, which, k, shift, nan)
            K.put(grid, sdims, cells, near, shift, clear)
            K.put_flat(grid, ask, np.full(ask.size, np.nan, np.float32))
    is_min, is_max = np.flatnonzero(status == 1), np.flatnonzero(status == -1)
    return (np.concatenate([is_min, is_max]),
            np.concatenate([np.ones(is_min.size, np.int8), -np.ones(is_max.size, np.int8)]))


def _offsets():
    """The 26 neighbours' offsets, the six faces first, then the edges and the corners."""
    offs = np.array([o for o in np.ndindex(3, 3, 3) if o != (1, 1, 1)], dtype=np.int64) - 1
    return offs[np.argsort(np.abs(offs).sum(axis=1), kind="stable")]


def _fine(solid, centre_pts, half, n):
    """The field on an ``n**3`` grid of half-width `half` about each point: (k, n, n, n)."""
    t = np.linspace(-half, half, n)
    off = np.stack(np.meshgrid(t, t, t, indexing="ij"), axis=-1).reshape(-1, 3)
    pts = (centre_pts[:, None, :] + off[None]).reshape(-1, 3)
    return np.asarray(solid(pts), dtype=np.float64).reshape(-1, n, n, n), off


def _measure(solid, centre_pts, side, h, lip, name_by):
    n = 4 * FINER + 1
    step = h / FINER
    g, off = _fine(solid, centre_pts, 2 * h, n)
    g *= side[:, None, None, None]
    # a candidate with no material among its fine samples: once more, finer, about its smallest one
    empty = ~(g < 0).any(axis=(1, 2, 3))
    if empty.any():
        k = np.flatnonzero(empty)
        best = off[np.argmin(g[k].reshape(k.size, -1), axis=1)]
        g2, off2 = _fine(solid, centre_pts[k] + best, 2 * step, n)
        g2 *= side[k, None, None, None]
        found = (g2 < 0).any(axis=(1, 2, 3))
        k = k[found]
        g[k], centre_pts = g2[found], centre_pts.copy()
        centre_pts[k] = centre_pts[k] + best[found]
        steps = np.full(g.shape[0], step)
        steps[k] = step / FINER
    else:
        steps = np.full(g.shape[0], step)
    has = (g < 0).any(axis=(1, 2, 3))
    if not has.any():
        return None
    keep = np.flatnonzero(has)
    g, steps, centre_pts, side = g[keep], steps[keep], centre_pts[keep], side[keep]
    from scipy import ndimage

    # the feature's thickness is read on its fine samples, not the field's values (a field far from a
    # distance, or a max() whose gradient vanishes at the deepest point, would misread it): twice the
    # largest distance from a sample inside to one outside, less a sample's width.  The blocks are
    # stacked along a first axis of huge spacing (one transform, no block sees another's samples);
    # beyond a block's faces is unknown, not outside
    inside = g < 0
    edt = ndimage.distance_transform_edt(inside, sampling=(1e9, 1.0, 1.0, 1.0))
    # a region whose deepest sample lies on the block's faces goes on beyond them (the outside beside
    # a face the block straddles, the material under it): its thickness is not measured here
    core = edt[:, 1:-1, 1:-1, 1:-1]
    cut = edt.reshape(edt.shape[0], -1).max(axis=1) > core.reshape(core.shape[0], -1).max(axis=1)
    flat = core.reshape(core.shape[0], -1)
    deepest = np.argmax(flat, axis=1)
    thick = np.where(cut, np.inf, (2 * flat[np.arange(flat.shape[0]), deepest] - 1) * steps)
    m = n - 2
    deepest = np.ravel_multi_index(np.unravel_index(deepest, (m, m, m)), (n, n, n)) + (n * n + n + 1)
    # its extent: the longest side of the box of its samples inside
    span = np.zeros(g.shape[0])
    for ax in (1, 2, 3):
        any_ax = inside.any(axis=tuple(a for a in (1, 2, 3) if a != ax))
        first = np.argmax(any_ax, axis=1)
        last = any_ax.shape[1] - 1 - np.argmax(any_ax[:, ::-1], axis=1)
        span = np.maximum(span, (last - first + 1) * steps)
    # lost only when thinner than two voxels whatever the rounding of the samples: the deepest
    # sample lies up to half a step's diagonal off the feature's middle, the nearest sample outside
    # up to a step beyond the surface
    res = (1 + math.sqrt(3)) * steps
    lost = thick + res < LOST_VOXELS * h
    if not lost.any():
        return None
    k = np.flatnonzero(lost)
    best = k[np.argmin(thick[k])]
    at = centre_pts[best] + off[deepest[best]] * (steps[best] / step)
    return LostFeature("material" if side[best] > 0 else "gap", float(thick[best]), float(span[best]),
                       tuple(float(v) for v in at), _bounded_by(name_by, at, thick[best]), int(k.size),
                       float(res[best]))


def _bounded_by(solid, at, thick):
    """The facets nearest the point `at` inside a feature `thick` thick ('' when unknown)."""
    try:
        from implicit.facets import FacetField

        ff = FacetField(solid)
        _, dec, vals = ff(np.asarray(at, dtype=np.float64)[None])
    except Exception:  # noqa: BLE001 - a name is a courtesy; the feature stands without it
        return ""
    d = np.abs(vals[:, 0])
    near = [int(i) for i in np.argsort(d, kind="stable") if d[i] <= max(thick, 1e-300)][:3]
    if int(dec[0]) not in near:
        near = [int(dec[0])] + near[:2]
    names = sorted({ff.names[i] for i in near})
    return ", ".join(names[:-1]) + (" and " if len(names) > 1 else "") + names[-1] if names else ""


def warn_lost(solid, origin, h, found, announced=None, *, name_by=None, stacklevel=2):
    """Warn (one line) when `lost_feature` finds a feature the lattice may lose.

    `found` is the classification of `spatial.meshing.boundary_cells_2h`
    (``cells``, ``centres``, ``uniform``, ``uniform_parents``); `announced`
    the voxel size an earlier warning already told to keep a wall (None:
    none) -- a feature that voxel keeps is not told again; `name_by` the
    solid whose facets name the feature (default `solid`: give the user's
    tree when `solid` is it clipped to the bounds).  Returns the feature or
    None.
    """
    feat = lost_feature(solid, origin, h, found["cells"], found["centres"], uniform=found.get("uniform"),
                        uniform_parents=found.get("uniform_parents"), name_by=name_by)
    return warn_feature(feat, h, announced, stacklevel=stacklevel + 1)


def warn_feature(feat, h, announced=None, *, stacklevel=2):
    """The one line of `warn_lost` for a feature `lost_feature` or `examine` returned (None: nothing said);
    returns the feature warned about, or None."""
    import warnings

    if feat is None:
        return None
    more = ""
    if feat.unexamined:
        more = f"; {feat.unexamined} more candidates not examined; voxel_size={feat.examine_voxel:.4g} examines them"
    if feat.kind == "unexamined":
        warnings.warn(f"mesh: {feat.describe()}; voxel_size={feat.examine_voxel:.4g} examines them",
                      RuntimeWarning, stacklevel=stacklevel + 1)
        return feat
    # a feature no thinner, to the measurement's resolution, than the wall announced: told already
    if announced is not None and (feat.thickness + feat.resolution) / 4 >= announced:
        if not feat.unexamined:
            return None
        warnings.warn(f"mesh: {replace(feat, kind='unexamined').describe()}; voxel_size={feat.examine_voxel:.4g} "
                      "examines them", RuntimeWarning, stacklevel=stacklevel + 1)
        return feat
    warnings.warn(f"mesh: voxel size {h:.4g} is coarser than half {feat.describe()}; the feature may be lost; "
                  f"voxel_size={feat.keep_voxel():.4g} keeps it{more}", RuntimeWarning, stacklevel=stacklevel + 1)
    return feat
