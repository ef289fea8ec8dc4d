"""Curved 10-node elements: mid-edge nodes added, boundary ones moved onto the true surface.

Mid-edge nodes of boundary edges go onto the solid's zero set (Newton steps),
onto the feature curve for an edge along a sharp edge (two crossing facets,
`independent_facets`), and the move is carried into the interior mid-edge
nodes (`spread_curving`) so the elements next to a curved boundary bend with
it instead of folding.
"""

from __future__ import annotations

import numpy as np

from .facets import project_to_surface
from .quality import _EDGES

__all__ = ["add_midnodes", "project_midnodes", "spread_curving", "MIN_CURVED_JACOBIAN"]

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
    when both end nodes lie on the same two facets); undo moves that fold an element."""
    mids, moved = midnode_targets(solid, ff, points, tets10, boundary, n_corner, size)
    return _place_midnodes(points, tets10, mids, moved)


def midnode_targets(solid, ff, points, tets10, boundary, n_corner, size):
    """The mid-edge nodes of the boundary edges ``(k,)`` and their places on the surface ``(k, 3)``
    (on the feature curve for an edge along one)."""
    pts = points
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
    return mids, moved


def _place_midnodes(points, tets10, mids, moved):
    """`points` with mid nodes `mids` at `moved`, the moves that fold an element given up."""
    pts = points.copy()
    pts[mids] = moved
    from .quality import scaled_jacobian

    bad = scaled_jacobian(pts, tets10) <= MIN_CURVED_JACOBIAN
    if bad.any():
        # A curved boundary edge folds an element whose other nodes lie close to it: carry the
        # boundary displacement into the interior mid-edge nodes instead of giving it up.
        pts = spread_curving(points, pts, tets10, mids)
    is_mid = np.zeros(len(pts), dtype=bool)
    is_mid[mids] = True
    for _ in range(12):
        # Give up the move of one boundary mid node per folded element (the one that moved most),
        # not all of them: most folds come from a single curved edge.
        bad = scaled_jacobian(pts, tets10) <= 0
        if not bad.any():
            break
        cand = tets10[bad, 4:]
        step = np.linalg.norm(pts[cand] - points[cand], axis=2) * is_mid[cand]
        if not step.any():
            break
        pick = cand[np.arange(len(cand)), step.argmax(axis=1)]
        pts[pick[step.max(axis=1) > 0]] = points[pick[step.max(axis=1) > 0]]
    for _ in range(5):
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
    return pts


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
        acc = np.zeros((n, 3))
        np.add.at(acc, a, disp[b])
        disp[free] = acc[free] / deg[free][:, None]
    out = curved.copy()
    out[free] = straight[free] + disp[free]
    return out


#: Rounds of edge splits before the mid nodes are placed (each halves the split edges' sag).
SPLIT_ROUNDS = 3
#: Smallest dihedral angle (degrees) of the pieces of a split (`tet_mesh`'s default minimum).
SPLIT_MIN_DIHEDRAL = 10.0


def split_folding_edges(solid, ff, points, tets, boundary, size, rounds=SPLIT_ROUNDS):
    """Split the boundary edges whose curved mid node would fold an element, at that mid node's
    place on the surface.

    A mid node moved onto a hole's wall or rim moves into the material by the
    sag of its edge; when an element next to the edge is thinner than about four
    times that, its quadratic map folds (the mid-node shape function's slope is 4).
    The edge is split instead: its elements are cut in two through the surface
    point, which becomes a corner node (the linear pieces stay valid for a move
    about four times larger) and the two halves sag a quarter as much.  Each
    element takes at most one split per round; a split whose pieces would not
    all keep a positive volume is not made.

    Parameters
    ----------
    solid, ff : Solid, FacetField
    points : (n, 3) float array
        Corner nodes.
    tets : (m, 4) int array
        Linear elements, positively oriented.
    boundary : (b, 3) int array
        Boundary triangles.
    size : float
        The element size (the largest mid-node move looked for).

    Returns
    -------
    points, tets : the nodes (split points appended) and the elements.

    Examples
    --------
    >>> from implicit import cylinder
    >>> from spatial.fea.facets import FacetField
    >>> from spatial.fea.slivers import boundary_faces
    >>> pts = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 0.5], [0.8, 0.8, 0.5]], float)  # one sliver on a rim
    >>> p, t = split_folding_edges(cylinder(1.0, 1.0), FacetField(cylinder(1.0, 1.0)), pts,
    ...                            np.array([[0, 1, 2, 3]]), boundary_faces(np.array([[0, 1, 2, 3]]))[0], 1.0)
    >>> len(p), len(t)  # doctest: +SKIP
    """
    from .slivers import boundary_faces
    from .quality import tet_volumes

    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64)
    for _ in range(rounds):
        n_corner = len(points)
        pts10, tets10, uniq = add_midnodes(points, tets)
        mids, moved = midnode_targets(solid, ff, pts10, tets10, boundary, n_corner, size)
        placed = _place_midnodes(pts10, tets10, mids, moved)
        given_up = np.abs(solid(placed[mids])) > 1e-7 * max(size, 1.0)
        given_up &= np.linalg.norm(moved - pts10[mids], axis=1) > 0
        if not given_up.any():
            break
        edge_ids = mids[given_up] - n_corner                   # rows of `uniq`
        where = moved[given_up]
        points, tets, made = _split_edges(points, tets, uniq, edge_ids, where, tet_volumes)
        if not made:
            break
        boundary = boundary_faces(tets)[0]
    return points, tets


def _split_edges(points, tets, uniq, edge_ids, where, tet_volumes):
    """Cut the elements around edges ``uniq[edge_ids]`` at points `where`; at most one edge per
    element, none whose pieces would be inverted or flat.  Returns (points, tets, edges split)."""
    from .quality import dihedral_angles

    n = len(points)
    key = np.sort(tets[:, _EDGES], axis=2)                                   # (m, 6, 2)
    code = key[..., 0] * (n + 1) + key[..., 1]                              # (m, 6)
    ucode = uniq[:, 0] * (n + 1) + uniq[:, 1]
    cand = np.zeros(len(uniq), dtype=bool)
    cand[edge_ids] = True
    spot = np.full(len(uniq), -1)
    spot[edge_ids] = np.arange(len(edge_ids))
    row = np.searchsorted(ucode, code)                                       # edge row of each element edge
    for _ in range(20):
        hit = cand[row]                                                      # (m, 6)
        # An element with two candidate edges keeps the first; the others are dropped everywhere.
        first = hit.argmax(axis=1)
        extra = hit.copy()
        extra[np.arange(len(tets)), first] = False
        drop = np.unique(row[extra])
        # Pieces of each split with the new point: all must keep a positive volume.
        el = np.nonzero(hit.any(axis=1))[0]
        loc = first[el]
        e = row[el, loc]
        newp = where[spot[e]]
        a, b = _EDGES[loc, 0], _EDGES[loc, 1]
        t1 = tets[el].copy()
        t2 = tets[el].copy()
        t1[np.arange(len(el)), b] = n + np.arange(len(el))
        t2[np.arange(len(el)), a] = n + np.arange(len(el))
        trial = np.concatenate([points, newp])
        bad = (tet_volumes(trial, t1) <= 0) | (tet_volumes(trial, t2) <= 0)
        # Nor pieces flatter than the mesh was asked to be (or than their parent, if it is already).
        floor = np.minimum(dihedral_angles(points, tets[el]).min(axis=1), SPLIT_MIN_DIHEDRAL)
        ok_vol = ~bad
        if ok_vol.any():
            worst = np.minimum(dihedral_angles(trial, t1[ok_vol]).min(axis=1), dihedral_angles(trial, t2[ok_vol]).min(axis=1))
            bad[ok_vol] = worst < floor[ok_vol]
        drop = np.union1d(drop, e[bad])
        if drop.size == 0:
            break
        cand[drop] = False
    else:
        return points, tets, 0
    if el.size == 0:
        return points, tets, 0
    # One new node per split edge, shared by the elements around it.
    split, node = np.unique(e, return_inverse=True)
    new_points = np.concatenate([points, where[spot[split]]])
    ids = n + node.reshape(-1)
    rows = np.arange(len(el))
    t1 = tets[el].copy()
    t2 = tets[el].copy()
    t1[rows, b] = ids
    t2[rows, a] = ids
    keep = np.ones(len(tets), dtype=bool)
    keep[el] = False
    return new_points, np.concatenate([tets[keep], t1, t2]), int(split.size)
