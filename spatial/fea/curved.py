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
