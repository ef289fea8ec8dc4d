"""Curved 10-node elements: mid-edge nodes added, boundary ones moved onto the true surface.

Mid-edge nodes of boundary edges go onto the solid's zero set (Newton steps),
onto the feature curve for an edge along a sharp edge (two crossing facets,
`independent_facets`), and the move is carried into the interior mid-edge
nodes (`spread_curving`) so the elements next to a curved boundary bend with
it instead of folding.  Where an element still folds, its interior mid-edge
nodes are moved until the Bezier coefficients of its Jacobian determinant are
all positive (`untangle_midnodes`; where that is not enough the boundary mid
nodes off the feature curves slide on the surface as well), and a flat
boundary element in the way of a curved edge (three corners on a hole's rim)
is removed (`curve_boundary`).
A move is given up only where none of that proves every element valid.
"""

from __future__ import annotations

import numpy as np

from .facets import project_to_surface
from .incidence import node_cells
from .jacobian_bounds import jacobian_bezier, jacobian_sign
from .quality import _EDGES, tet_volumes
from .slivers import _SIDE_COMMON, _ragged, boundary_faces

__all__ = ["add_midnodes", "curve_boundary", "project_midnodes", "spread_curving", "untangle_midnodes",
           "MIN_CURVED_JACOBIAN"]

def add_midnodes(points, tets):
    """10-node elements from 4-node ones: shared mid-edge nodes appended to the points."""
    edges = tets[:, _EDGES]  # (m, 6, 2)
    key = np.sort(edges.reshape(-1, 2), axis=1)
    uniq, inv = np.unique(key, axis=0, return_inverse=True)
    mid = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
    ids = points.shape[0] + inv.reshape(-1, 6)
    return np.concatenate([points, mid]), np.concatenate([tets, ids], axis=1), uniq


def project_midnodes(solid, ff, points, tets10, boundary, n_corner, size):
    """Move mid-edge nodes of boundary edges onto the surface (onto feature curves
    when both end nodes lie on the same two facets); undo moves that fold an element.

    Where a move folds an element, the interior mid-edge nodes around it are moved first
    (`spread_curving`, then `untangle_midnodes`) to make room for it.
    """
    return _project_midnodes(solid, ff, points, tets10, boundary, n_corner, size)[0]


def _project_midnodes(solid, ff, points, tets10, boundary, n_corner, size):
    """`project_midnodes`, and the boundary edges ``(k, 2)`` whose mid node was left on its chord."""
    pts = points.copy()
    b_edges = np.sort(np.concatenate([boundary[:, [0, 1]], boundary[:, [1, 2]], boundary[:, [2, 0]]]), axis=1)
    b_edges = np.unique(b_edges, axis=0)
    # Mid node of each boundary edge: look it up among the elements' edges.
    el_edges = np.sort(tets10[:, :4][:, _EDGES].reshape(-1, 2), axis=1)
    el_mid = tets10[:, 4:].reshape(-1)
    ekey = el_edges[:, 0] * (n_corner + 1) + el_edges[:, 1]
    bkey = b_edges[:, 0] * (n_corner + 1) + b_edges[:, 1]
    _, first = np.unique(ekey, return_index=True)
    pos = np.searchsorted(ekey[first], bkey)
    mids = el_mid[first[pos]]
    start = pts[mids].copy()
    moved = project_to_surface(solid, start, max_move=size)
    # Feature edges: both ends on the same pair of facets.
    _, _, fa = ff(pts[b_edges[:, 0]])
    _, _, fb = ff(pts[b_edges[:, 1]])
    tol = 1e-7 * max(size, 1.0)
    on_both = (np.abs(fa) < tol) & (np.abs(fb) < tol)  # (k, e)
    feature = on_both.sum(axis=0) >= 2
    if feature.any():
        from .facets import independent_facets, solve_on_facets

        ii = np.nonzero(feature)[0]
        sets = independent_facets(ff, start[ii], on_both[:, ii], count=2)
        ok = sets[:, 1] >= 0
        ii, sets = ii[ok], sets[ok]
        snapped = solve_on_facets(ff, start[ii], sets)
        good = (np.linalg.norm(snapped - start[ii], axis=1) < size) & np.isfinite(snapped).all(axis=1)
        good &= np.abs(solid(snapped)) < tol
        moved[ii[good]] = snapped[good]
    else:
        ii, good = np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool)
    pts[mids] = moved
    from .quality import scaled_jacobian

    bad = scaled_jacobian(pts, tets10) <= MIN_CURVED_JACOBIAN
    if bad.any():
        # A curved boundary edge folds an element whose other nodes lie close to it: carry the
        # boundary displacement into the interior mid-edge nodes instead of giving it up.
        pts = spread_curving(points, pts, tets10, mids)
        folded = scaled_jacobian(pts, tets10) <= 0
        if folded.any():
            # Still folded: the interior mid nodes around it bend further, where that proves it valid.
            free = np.zeros(len(pts), dtype=bool)
            free[n_corner:] = True
            free[mids] = False
            pts = untangle_midnodes(pts, tets10, free, active=folded)
            folded = scaled_jacobian(pts, tets10) <= 0
            if folded.any():
                # Still folded (a curved edge across a face narrower than the size): the boundary mid
                # nodes off the feature curves slide on the surface too, the curved one with them.
                slide = np.zeros(len(pts), dtype=bool)
                slide[mids] = True
                slide[mids[ii[good]]] = False
                pts = untangle_midnodes(pts, tets10, free | slide, active=folded, solid=solid, slide=slide)
            folded = None
    else:
        folded = np.zeros(len(tets10), dtype=bool)
    is_mid = np.zeros(len(pts), dtype=bool)
    is_mid[mids] = True
    for _ in range(12):
        # Give up the move of one boundary mid node per folded element (the one that moved most),
        # not all of them: most folds come from a single curved edge.
        bad = scaled_jacobian(pts, tets10) <= 0 if folded is None else folded
        folded = None
        if not bad.any():
            break
        cand = tets10[bad, 4:]
        step = np.linalg.norm(pts[cand] - points[cand], axis=2) * is_mid[cand]
        if not step.any():
            break
        pick = cand[np.arange(len(cand)), step.argmax(axis=1)]
        pts[pick[step.max(axis=1) > 0]] = points[pick[step.max(axis=1) > 0]]
    for _ in range(5 if bad.any() else 0):
        sj = scaled_jacobian(pts, tets10)
        bad = sj <= 0
        if not bad.any():
            break
        back = np.unique(tets10[bad, 4:])
        back = back[(pts[back] != points[back]).any(axis=1)]
        if is_mid[back].any():
            back = back[is_mid[back]]
        # else folded by the spread interior moves alone: those go back to straight edges too
        pts[back] = points[back]
    # Off: given up, or never reached (a Newton step longer than `size`).
    return pts, b_edges[np.abs(solid(pts[mids])) > OFF_SURFACE * size]


#: Scaled Jacobian under which a curved element has its interior mid-edge nodes moved along.
MIN_CURVED_JACOBIAN = 0.2


def spread_curving(straight, curved, tets10, boundary_mids, iterations=40):
    """Move interior mid-edge nodes by a smooth extension of the boundary mid-node moves.

    The displacement of the boundary mid-edge nodes (fixed) is extended to the
    other mid-edge nodes by Jacobi steps of a graph Laplacian (each mid node
    takes the mean displacement of the mid nodes of its elements), which
    bends the elements next to a curved boundary along with it.
    """
    n = len(straight)
    disp = curved - straight
    fixed = np.zeros(n, dtype=bool)
    fixed[boundary_mids] = True
    fixed[: int(tets10[:, :4].max()) + 1] = True  # corners stay
    mid = tets10[:, 4:]
    # Pairs of mid nodes sharing an element (both directions).
    i, j = np.triu_indices(6, 1)
    a = np.concatenate([mid[:, i].reshape(-1), mid[:, j].reshape(-1)])
    b = np.concatenate([mid[:, j].reshape(-1), mid[:, i].reshape(-1)])
    deg = np.bincount(a, minlength=n).astype(np.float64)
    free = ~fixed & (deg > 0)
    for _ in range(iterations):
        # bincount adds in the order of `a` as np.add.at does (the same bits), ten times faster
        acc = np.stack([np.bincount(a, weights=disp[b, k], minlength=n) for k in range(3)], axis=1)
        disp[free] = acc[free] / deg[free][:, None]
    out = curved.copy()
    out[free] = straight[free] + disp[free]
    return out


#: Distance to the surface, as a fraction of the size, past which a boundary node counts as off it
#: (`tet_mesh`'s ``info["off_surface_nodes"]``).
OFF_SURFACE = 1e-6

#: Rounds of `curve_boundary`: flat boundary elements removed, mid nodes placed again.
CURVE_RETRIES = 3


def curve_boundary(solid, ff, points, tets, boundary, size, *, retries=CURVE_RETRIES):
    """10-node elements from 4-node ones with every boundary mid-edge node on the surface where
    that folds no element: `add_midnodes`, then `project_midnodes`.

    A mid node that cannot go onto the surface most often sits on the common edge of the two
    boundary sides of a flat element whose four corners lie on the surface (a face whose three
    corners sit on a hole's rim: the rim's arc between two of them passes through the third).
    Such an element is removed -- its other two sides become the boundary, the surface's
    diagonal flips -- and the mid nodes are placed again, up to `retries` times.

    Returns the points with mid nodes ``(n + e, 3)``, the 10-node elements, the 4-node elements
    kept and the number of elements removed.

    Examples
    --------
    >>> from implicit import sphere
    >>> from spatial.fea.facets import FacetField
    >>> from spatial.fea.slivers import boundary_faces
    >>> from scipy.spatial import Delaunay
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float) * 0.5
    >>> t = np.array([[0, 1, 2, 3]])
    >>> q, t10, t4, removed = curve_boundary(sphere(1.0), FacetField(sphere(1.0)), p, t,
    ...                                      boundary_faces(t)[0], 1.0)
    >>> t10.shape, removed
    ((1, 10), 0)
    """
    removed = 0
    tets = np.asarray(tets, dtype=np.int64)
    for attempt in range(retries + 1):
        pts, tets10, _ = add_midnodes(points, tets)
        pts, off = _project_midnodes(solid, ff, pts, tets10, boundary, len(points), size)
        if off.size == 0 or attempt == retries:
            break
        drop = _flat_caps(tets, off)
        if drop.size == 0:
            break
        tets = np.delete(tets, drop, axis=0)
        boundary = boundary_faces(tets)[0]
        removed += int(drop.size)
    return pts, tets10, tets, removed


def _flat_caps(tets, edges):
    """Elements with two boundary sides, one of whose five boundary edges is one of `edges`
    ``(k, 2)`` (sorted ends), and whose sixth edge is not on the boundary yet; no two sharing a node."""
    bfaces, belem, bside = boundary_faces(tets)
    nb = np.bincount(belem, minlength=len(tets))
    two = np.nonzero(nb[belem] == 2)[0]
    if two.size == 0:
        return two
    order = np.argsort(belem[two], kind="stable")
    pair = two[order].reshape(-1, 2)
    elem = belem[pair[:, 0]]
    common = tets[elem[:, None], _SIDE_COMMON[bside[pair[:, 0]], bside[pair[:, 1]]]]
    corners = tets[elem]
    # The far edge: the two corners off the sides' common edge; the other five are boundary edges.
    far = np.sort(corners[(corners != common[:, :1]) & (corners != common[:, 1:])].reshape(-1, 2), axis=1)
    n = int(tets.max()) + 1
    own = np.sort(corners[:, _EDGES], axis=2)
    own_code = own[:, :, 0] * n + own[:, :, 1]
    hit = np.isin(own_code, edges[:, 0] * n + edges[:, 1]) & (own_code != (far[:, 0] * n + far[:, 1])[:, None])
    be = np.sort(np.concatenate([bfaces[:, [0, 1]], bfaces[:, [1, 2]], bfaces[:, [2, 0]]]), axis=1)
    ok = hit.any(axis=1) & ~np.isin(far[:, 0] * n + far[:, 1], be[:, 0] * n + be[:, 1])
    elem = elem[ok]
    uniq, cnt = np.unique(tets[elem].reshape(-1), return_counts=True)
    return elem[~np.isin(tets[elem], uniq[cnt > 1]).any(axis=1)]


def _min_coefficient(points, tets10):
    """Smallest Bezier coefficient of each element's Jacobian determinant over its straight value
    (6 times the corner volume): 1 for a straight element, > 0 proves it valid."""
    return jacobian_bezier(points, tets10).min(axis=1) / (6.0 * tet_volumes(points, tets10[:, :4]))


#: The smallest scaled Bezier coefficient (`_min_coefficient`) `untangle_midnodes` aims at.
UNTANGLE_TARGET = 0.05
#: Rounds in a row without a better position after which `untangle_midnodes` gives up.
UNTANGLE_STALL = 8


def untangle_midnodes(points, tets10, free, *, active=None, rounds=60, seed=0, trials=24, solid=None,
                      slide=None):
    """Move the `free` mid-edge nodes of elements whose Jacobian is not proven positive until
    it is (every Bezier coefficient of its determinant > 0), where a move can do it.

    Each round takes an independent set of free mid nodes of such elements (no two in one
    element), tries the chord's middle and random nearby positions, and keeps the one with the
    largest smallest scaled Bezier coefficient over the elements around the node: the
    interior edges next to a curved boundary edge bend out of its way.  Corner nodes and the
    other mid nodes stay.  `active` marks the elements to unfold (default: those whose
    Jacobian is not proven positive).  The `slide` nodes (a mask, with `solid`) try positions
    projected onto the solid's surface only, so that a boundary mid node stays on it.
    Returns the new points.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> e = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    >>> x = np.concatenate([p, 0.5 * (p[e[:, 0]] + p[e[:, 1]])])
    >>> x[4] = [0.5, 0.3, 0.0]   # mid node of edge 01 bent into the element: folded
    >>> t = np.arange(10)[None]
    >>> free = np.r_[[False] * 5, [True] * 5]  # the corners and that mid node stay
    >>> int(jacobian_sign(x, t)[0]), int(jacobian_sign(untangle_midnodes(x, t, free), t)[0])
    (-1, 1)
    """
    rng = np.random.default_rng(seed)
    pts = np.array(points, dtype=np.float64)
    tets10 = np.asarray(tets10, dtype=np.int64)
    free = np.asarray(free, dtype=bool)
    n = len(pts)
    if slide is not None and solid is None:
        raise ValueError("slide: needs the solid whose surface the nodes slide on")
    slide = np.zeros(n, dtype=bool) if slide is None else np.asarray(slide, dtype=bool)
    mid = tets10[:, 4:]
    flat = mid.reshape(-1)
    order, starts = node_cells(mid, n)
    tet_of = order // 6
    ends = np.zeros((n, 2), dtype=np.int64)
    ends[flat] = tets10[:, :4][:, _EDGES].reshape(-1, 2)
    length = np.linalg.norm(pts[ends[:, 0]] - pts[ends[:, 1]], axis=1)
    # The elements to unfold: given, or those whose Jacobian is not proven positive.
    active = jacobian_sign(pts, tets10) != 1 if active is None else np.array(active, dtype=bool)
    score = np.full(len(tets10), np.inf)
    score[active] = _min_coefficient(pts, tets10[active])
    stalled = 0
    for _ in range(rounds):
        bad = active & (score < UNTANGLE_TARGET)
        if not bad.any():
            break
        cand = np.zeros(n, dtype=bool)
        cand[mid[bad].reshape(-1)] = True
        cand &= free
        if not cand.any():
            break
        # Independent set as in `slivers.improve`: the smallest priority among an element's candidates moves.
        prio = rng.permutation(n)
        near = mid[np.unique(tet_of[_ragged(starts, np.nonzero(cand)[0])])]
        tmin = np.where(cand[near], prio[near], n).min(axis=1)
        blocked = np.zeros(n, dtype=bool)
        blocked[near[tmin[:, None] != prio[near]]] = True
        verts = np.nonzero(cand & ~blocked)[0]
        counts = starts[verts + 1] - starts[verts]
        pair_t = tet_of[_ragged(starts, verts)]
        pair_v = np.repeat(np.arange(verts.size), counts)
        seg = np.r_[0, np.cumsum(counts)[:-1]]
        cur = pts[verts]
        chord = 0.5 * (pts[ends[verts, 0]] + pts[ends[verts, 1]])
        tried = [cur, chord, 0.5 * (cur + chord)]
        for k in range(trials):
            scale = (0.02 + 0.3 * (k % 4) / 3.0) * length[verts]
            tried.append(cur + rng.normal(size=cur.shape) * scale[:, None] / np.sqrt(3.0))
        tried = np.stack(tried)  # (t, v, 3)
        on = slide[verts]
        if on.any():
            # positions off the surface are tried at their projection; those not reaching it stay put
            t_on = tried[:, on].reshape(-1, 3)
            proj = project_to_surface(solid, t_on, max_move=0.5 * length[verts[on]].max())
            tol = 0.1 * OFF_SURFACE * np.tile(length[verts[on]], len(tried))
            reached = np.abs(solid(proj)) <= tol
            proj[~reached] = np.tile(cur[on], (len(tried), 1))[~reached]
            tried[:, on] = proj.reshape(len(tried), -1, 3)
        el = tets10[pair_t]
        x = np.broadcast_to(pts[el], (len(tried),) + el.shape + (3,)).copy()  # (t, p, 10, 3)
        row, col = np.nonzero(el == verts[pair_v][:, None])
        x[:, row, col] = tried[:, pair_v[row]]
        flat_x = x.reshape(-1, 3)
        sc = _min_coefficient(flat_x, np.arange(len(flat_x)).reshape(-1, 10)).reshape(len(tried), -1)
        worst = np.minimum.reduceat(sc, seg, axis=1)
        best = worst.argmax(axis=0)
        cols = np.arange(verts.size)
        better = worst[best, cols] > worst[0] + 1e-12
        pts[verts[better]] = tried[best[better], cols[better]]
        # A fold no free node can undo: stop after some rounds of other independent sets gaining nothing.
        stalled = 0 if better.any() else stalled + 1
        if stalled >= UNTANGLE_STALL:
            break
        touched = np.unique(pair_t[better[pair_v]])
        # elements around a moved node may have been made worse: they are watched from now on
        active[touched] = True
        score[touched] = _min_coefficient(pts, tets10[touched])
    return pts
