"""Sliver removal: smoothing interior (and sliding boundary) vertices, peeling flat boundary elements.

Each round of `improve` moves an independent set of vertices of bad elements
(no two in one element) to the best of several trial positions: the mean of
the neighbours and random nearby points, scored by the worst element around
the vertex (dihedral angles, and the radius-edge ratio when a limit is
given), never inverting one.  `peel` removes flat elements with two sides on
the boundary; `flip23` replaces two elements sharing a face by three.  Edge
removal, edge splits and the rounds of the whole pass are in `sliver_flips`.

References
----------
L. A. Freitag, C. Ollivier-Gooch, "Tetrahedral mesh improvement using swapping
and smoothing", IJNME 40, 1997 (optimisation-based smoothing).
"""

from __future__ import annotations

import numpy as np

from .facets import project_to_surface
from .incidence import node_cells, single_sides
from .model import SIDE_NODES
from .score_kernel import best_trials, element_scores, smoothing_set

__all__ = ["boundary_faces", "element_score", "flip23", "improve", "peel", "score"]

#: The two corners shared by sides i and j (``_SIDE_COMMON[i, j]``).
_SIDE_COMMON = np.array([[sorted(set(SIDE_NODES[i]) & set(SIDE_NODES[j])) if i != j else [0, 0]
                          for j in range(4)] for i in range(4)])

def boundary_faces(tets):
    """Sides that belong to one element: (corner nodes (b, 3), element (b,), side (b,)).

    The sides are those `incidence.single_sides` finds (bucketed by their smallest corner in one
    compiled counting sort; a sort of one integer code per side took 5 to 10 ms at 19,000 elements).
    """
    tets = np.asarray(tets)
    once = np.flatnonzero(single_sides(tets, SIDE_NODES))
    elem, side = once // 4, once % 4
    return tets[elem[:, None], SIDE_NODES[side]], elem, side


def score(d, min_dihedral, max_dihedral):
    """Quality of elements from their dihedral angles ``(..., 6)``: both limits map to min_dihedral."""
    lo = d.min(axis=-1)
    hi = (180.0 - d.max(axis=-1)) * (min_dihedral / (180.0 - max_dihedral))
    return np.minimum(lo, hi)


#: gmsh's gamma (3 inradius / circumradius) the smoothing aims at: lower counts as a small angle.
SMOOTH_GAMMA = 0.25


def element_score(points, tets, min_dihedral, max_dihedral, radius_edge=None, min_gamma=SMOOTH_GAMMA):
    """`score` of the elements, with a radius-edge ratio above `radius_edge` scored as a
    dihedral angle under the minimum (the ratio over the limit scales it down)."""
    # One compiled pass per element (`score_kernel`): the numpy form is a dozen array passes.
    return element_scores(points, tets, min_dihedral, max_dihedral, radius_edge, min_gamma)


#: Random trial steps of the smoothing, as factors of the longest edge at the vertex (times `jitter`).
_JITTER_STEPS = np.array([0.05 + 0.25 * (k % 4) / 3.0 for k in range(24)])


def improve(points, tets, movable, min_dihedral, max_dihedral, *, rounds=40, seed=0, solid=None, slide=None,
             jitter=1.0, radius_edge=None, scores=None, with_scores=False):
    """Smooth movable vertices of bad elements until no element is bad or nothing moves.

    Each round takes an independent set of candidate vertices (no two in one
    element), tries the mean of the neighbours and random nearby positions,
    and keeps the one with the best worst-element score (never inverting one).
    `scores` may give the elements' `element_score` at `points` (computed when
    not given); with `with_scores` the scores at the result are returned too,
    ``(points, scores)``.
    """
    rng = np.random.default_rng(seed)
    pts = points.copy()
    n = pts.shape[0]
    order, starts = node_cells(tets, n)
    tet_of = order // 4
    target = min_dihedral + 1.0
    n_trials = _JITTER_STEPS.size
    score = (element_score(pts, tets, min_dihedral, max_dihedral, radius_edge) if scores is None
             else np.array(scores, dtype=np.float64))
    for _ in range(rounds):
        bad = score < target
        if not bad.any():
            break
        cand = np.zeros(n, dtype=bool)
        cand[tets[bad].reshape(-1)] = True
        cand &= movable
        if not cand.any():
            break
        # Independent set: a vertex moves only if it has the smallest priority among the
        # candidates of all its elements (priorities drawn anew each round, so all get turns);
        # its elements, neighbour mean and longest edge come from the same compiled pass.
        prio = rng.permutation(n)
        verts, counts, pair_tet, nbr_mean, edge = smoothing_set(pts, tets, starts, tet_of, cand, prio)
        if verts.size == 0:
            break
        pair_v = np.repeat(np.arange(verts.size), counts)
        seg = np.concatenate([[0], np.cumsum(counts)[:-1]])
        elem = tets[pair_tet]
        # Trial positions: current, neighbour mean (two step lengths), random jitter.
        cur = pts[verts]
        trials = np.empty((3 + n_trials, verts.size, 3))
        trials[0], trials[1], trials[2] = cur, nbr_mean, 0.5 * (cur + nbr_mean)
        scale = _JITTER_STEPS[:, None] * jitter * edge  # (t, k), as (0.05 + 0.25 (k % 4) / 3) jitter edge
        trials[3:] = cur + rng.normal(size=(n_trials,) + cur.shape) * scale[:, :, None] / np.sqrt(3.0)
        if slide is not None:
            sl = slide[verts]
            if sl.any():
                tv = trials[1:, sl].reshape(-1, 3)
                trials[1:, sl] = project_to_surface(solid, tv, steps=3).reshape(trials.shape[0] - 1, -1, 3)
        # The first trial of each vertex whose worst element beats the earlier ones, in one compiled
        # pass that drops a trial at its first element no better than the best so far.
        best, _ = best_trials(pts, elem, verts, seg, counts, trials, min_dihedral, max_dihedral, radius_edge,
                              SMOOTH_GAMMA)
        pts[verts] = trials[best, np.arange(verts.size)]
        # Only the elements around moved vertices change their score.
        touched = np.unique(pair_tet[best[pair_v] != 0])
        if touched.size:
            score[touched] = element_score(pts, tets[touched], min_dihedral, max_dihedral, radius_edge)
    return (pts, score) if with_scores else pts


def _ragged(starts, rows):
    """Positions ``starts[r] .. starts[r + 1] - 1`` of every row ``r`` of `rows`, concatenated."""
    counts = starts[rows + 1] - starts[rows]
    return np.repeat(starts[rows], counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))


def peel(points, tets, min_dihedral, max_dihedral):
    """Remove flat elements that have two sides on the boundary.

    Such a sliver lies on the surface (all four nodes on it); removing it
    leaves its two other sides as boundary, which stay on the surface.  An
    element is kept when its remaining sides' common edge is already on the
    boundary (the boundary would stop being manifold).  Returns the elements
    left and how many were removed.
    """
    # `score` of the dihedral angles alone, in one compiled pass (the numpy angles cost 0.03 s at 24,000 elements).
    sc = element_scores(points, tets, min_dihedral, max_dihedral, None, 0.0)
    bad = np.nonzero(sc < min_dihedral)[0]
    if bad.size == 0:
        return tets, 0
    bfaces, belem, bside = boundary_faces(tets)
    nb = np.bincount(belem, minlength=len(tets))
    cand = bad[nb[bad] == 2]
    if cand.size == 0:
        return tets, 0
    # The edge shared by the two inner sides must not be on the boundary already.
    on_b = np.zeros((len(tets), 4), dtype=bool)
    on_b[belem, bside] = True
    sides = on_b[cand]
    inner = np.nonzero(~sides)[1].reshape(-1, 2)
    edge = np.sort(tets[cand[:, None], _SIDE_COMMON[inner[:, 0], inner[:, 1]]], axis=1)
    bedges = np.sort(np.concatenate([bfaces[:, [0, 1]], bfaces[:, [1, 2]], bfaces[:, [2, 0]]]), axis=1)
    n = points.shape[0] + 1
    on_boundary = np.isin(edge[:, 0] * n + edge[:, 1], bedges[:, 0] * n + bedges[:, 1])
    # One removal per neighbourhood: no two removed elements may share a node.
    cand = cand[~on_boundary]
    if cand.size == 0:
        return tets, 0
    uniq, cnt = np.unique(tets[cand].reshape(-1), return_counts=True)
    cand = cand[~np.isin(tets[cand], uniq[cnt > 1]).any(axis=1)]
    keep = np.ones(len(tets), dtype=bool)
    keep[cand] = False
    return tets[keep], int(cand.size)


def _orient(points, tets):
    x = points[tets]
    return np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0])) / 6.0


def flip23(points, tets, min_dihedral, max_dihedral, radius_edge=None, rounds=4):
    """Replace pairs of elements sharing a face by three elements around the edge joining
    their far vertices, where that raises the worse score of the pair (2-3 flips).

    Only interior faces flip, so the boundary stays as it is.  Each round flips
    an independent set (no element in two flips), best gains first.  Returns the
    new elements and the number of flips.
    """
    tets = np.asarray(tets, dtype=np.int64)
    total = 0
    for _ in range(rounds):
        sc = element_score(points, tets, min_dihedral, max_dihedral, radius_edge)
        target = min_dihedral + 1.0
        bad = np.nonzero(sc < target)[0]
        if bad.size == 0:
            break
        m = len(tets)
        faces = np.sort(tets[:, _OPPOSITE].reshape(-1, 3), axis=1)  # face k of tet t is opposite corner k
        _, inv, cnt = np.unique(faces, axis=0, return_inverse=True, return_counts=True)
        inv = inv.reshape(-1)
        order = np.argsort(inv, kind="stable")
        # The element across each face (-1 on the boundary).
        across = np.full(m * 4, -1, dtype=np.int64)
        shared = cnt[inv[order]] == 2
        pos = order[shared].reshape(-1, 2)
        across[pos[:, 0]], across[pos[:, 1]] = pos[:, 1], pos[:, 0]
        cand = (bad[:, None] * 4 + np.arange(4)[None, :]).reshape(-1)
        cand = cand[across[cand] >= 0]
        if cand.size == 0:
            break
        t1 = cand // 4
        t2 = across[cand] // 4
        f = tets[t1][np.arange(t1.size)[:, None], _OPPOSITE[cand % 4]]  # (k, 3) shared face
        v1 = tets[t1, cand % 4]
        v2 = tets[t2, across[cand] % 4]
        new = np.stack([np.stack([v1, v2, f[:, i], f[:, (i + 1) % 3]], axis=1) for i in range(3)], axis=1)
        vol = _orient(points, new.reshape(-1, 4)).reshape(-1, 3)
        same = (np.sign(vol) == np.sign(vol[:, :1])).all(axis=1) & (np.abs(vol).min(axis=1) > 0)
        new = np.where((vol < 0)[:, :, None], new[:, :, [1, 0, 2, 3]], new)
        nsc = element_score(points, new.reshape(-1, 4), min_dihedral, max_dihedral, radius_edge).reshape(-1, 3).min(axis=1)
        gain = nsc - np.minimum(sc[t1], sc[t2])
        ok = same & (gain > 1e-6)
        if not ok.any():
            break
        t1, t2, new, gain = t1[ok], t2[ok], new[ok], gain[ok]
        # Independent set: a flip goes ahead when it is the best of every flip touching its
        # two elements (ties broken by position), so no element is in two flips.
        key = gain * (1 + 1e-9) + np.arange(gain.size) * 1e-12
        best = np.full(m, -np.inf)
        np.maximum.at(best, t1, key)
        np.maximum.at(best, t2, key)
        take = np.nonzero((key == best[t1]) & (key == best[t2]))[0]
        keep = np.ones(m, dtype=bool)
        keep[t1[take]] = keep[t2[take]] = False
        tets = np.concatenate([tets[keep], new[take].reshape(-1, 4)])
        total += int(take.size)
    return tets, total


#: Corners of the face opposite each corner.
_OPPOSITE = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])
