"""Compiled element scores for the sliver removal: one pass over the elements, no temporaries.

The smoothing of `slivers.improve` scores every trial position of every
moving vertex against all the elements around it; in numpy each score is a
dozen array passes (crosses, norms, arc cosines) over ``(m, 4, 3)`` copies,
which made two thirds of a tetrahedral mesh's time.  These numba kernels
compute, per element and in one loop, the same score as
`slivers.element_score`: the smallest dihedral angle, the largest one mapped
onto the same scale, the radius-edge ratio and gmsh's gamma, each scaled to
degrees of the minimum dihedral angle.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["best_trials", "corner_measures", "corner_volumes", "element_scores", "moved_scores", "radius_edge", "smoothing_set"]

_OPP = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]], dtype=np.int64)
_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]], dtype=np.int64)
_EDGE_FACES = np.array([[2, 3], [0, 3], [1, 3], [1, 2], [0, 2], [0, 1]], dtype=np.int64)


@njit(cache=True, nogil=True)
def _face_normals(x, opp, n):
    """Unit normals ``n`` (4, 3) of the faces of the tetrahedron ``x`` (4, 3), face ``i`` opposite
    corner ``i`` and pointing towards it (zero for a corner on its face's plane)."""
    for i in range(4):
        a, b, c = opp[i, 0], opp[i, 1], opp[i, 2]
        u0, u1, u2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
        v0, v1, v2 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
        n0, n1, n2 = u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0
        s = n0 * (x[i, 0] - x[a, 0]) + n1 * (x[i, 1] - x[a, 1]) + n2 * (x[i, 2] - x[a, 2])
        sg = 1.0 if s > 0 else (-1.0 if s < 0 else 0.0)
        norm = max(math.sqrt(n0 * n0 + n1 * n1 + n2 * n2), 1e-300)
        n[i, 0], n[i, 1], n[i, 2] = sg * n0 / norm, sg * n1 / norm, sg * n2 / norm


@njit(cache=True, nogil=True)
def _score(x, min_d, hi_scale, re, min_g, opp, edges, edge_faces):
    """Score and signed volume of the tetrahedron with corners ``x`` (4, 3)."""
    n = np.empty((4, 3))
    _face_normals(x, opp, n)
    # The dihedral angle 180 - acos(cos) grows with the cosine of the face normals: two arc cosines
    # (of the extreme cosines) instead of six.
    cmin, cmax = 1.0, -1.0
    for e in range(6):
        f, g = edge_faces[e, 0], edge_faces[e, 1]
        cos = n[f, 0] * n[g, 0] + n[f, 1] * n[g, 1] + n[f, 2] * n[g, 2]
        cos = min(1.0, max(-1.0, cos))
        cmin = min(cmin, cos)
        cmax = max(cmax, cos)
    lo = 180.0 - math.degrees(math.acos(cmin))
    hi = 180.0 - math.degrees(math.acos(cmax))
    sc = min(lo, (180.0 - hi) * hi_scale)
    a0, a1, a2 = x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2]
    b0, b1, b2 = x[2, 0] - x[0, 0], x[2, 1] - x[0, 1], x[2, 2] - x[0, 2]
    c0, c1, c2 = x[3, 0] - x[0, 0], x[3, 1] - x[0, 1], x[3, 2] - x[0, 2]
    bc0, bc1, bc2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
    det = a0 * bc0 + a1 * bc1 + a2 * bc2
    if re > 0 or min_g > 0:
        ca0, ca1, ca2 = c1 * a2 - c2 * a1, c2 * a0 - c0 * a2, c0 * a1 - c1 * a0
        ab0, ab1, ab2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
        aa, bb, cc = a0 * a0 + a1 * a1 + a2 * a2, b0 * b0 + b1 * b1 + b2 * b2, c0 * c0 + c1 * c1 + c2 * c2
        m0 = aa * bc0 + bb * ca0 + cc * ab0
        m1 = aa * bc1 + bb * ca1 + cc * ab1
        m2 = aa * bc2 + bb * ca2 + cc * ab2
        circum = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2) / max(2.0 * abs(det), 1e-300)
        if re > 0:
            emin = np.inf
            for e in range(6):
                p, q = edges[e, 0], edges[e, 1]
                d0, d1, d2 = x[q, 0] - x[p, 0], x[q, 1] - x[p, 1], x[q, 2] - x[p, 2]
                emin = min(emin, math.sqrt(d0 * d0 + d1 * d1 + d2 * d2))
            ratio = circum / max(emin, 1e-300)
            sc = min(sc, min_d * re / max(ratio, 1e-300))
        if min_g > 0:
            area = 0.0
            for i in range(4):
                a, b, c = opp[i, 0], opp[i, 1], opp[i, 2]
                u0, u1, u2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
                v0, v1, v2 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
                w0, w1, w2 = u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0
                area += 0.5 * math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
            inradius = 0.5 * abs(det) / max(area, 1e-300)
            sc = min(sc, min_d * (3.0 * inradius / max(circum, 1e-300)) / min_g)
    return sc, det / 6.0


@njit(cache=True, nogil=True)
def _element_scores(points, tets, min_d, hi_scale, re, min_g, opp, edges, edge_faces):
    m = tets.shape[0]
    out = np.empty(m)
    x = np.empty((4, 3))
    for t in range(m):
        for k in range(4):
            for d in range(3):
                x[k, d] = points[tets[t, k], d]
        out[t] = _score(x, min_d, hi_scale, re, min_g, opp, edges, edge_faces)[0]
    return out


@njit(cache=True, nogil=True)
def _moved_scores(points, tets, moving, which, trials, min_d, hi_scale, re, min_g, opp, edges, edge_faces):
    """Scores ``(t, k)`` of elements ``tets`` (k, 4) with node ``moving[i]`` at each trial
    position ``trials[:, which[i]]``; an element inverted or flattened there scores -inf."""
    nt, k = trials.shape[0], tets.shape[0]
    out = np.empty((nt, k))
    x = np.empty((4, 3))
    for i in range(k):
        for j in range(nt):
            for c in range(4):
                node = tets[i, c]
                for d in range(3):
                    x[c, d] = trials[j, which[i], d] if node == moving[i] else points[node, d]
            sc, vol = _score(x, min_d, hi_scale, re, min_g, opp, edges, edge_faces)
            out[j, i] = sc if vol > 0 else -np.inf
    return out


def _scales(min_dihedral, max_dihedral, radius_edge, min_gamma):
    return (float(min_dihedral), float(min_dihedral) / (180.0 - float(max_dihedral)),
            0.0 if radius_edge is None else float(radius_edge), float(min_gamma or 0.0))


def element_scores(points, tets, min_dihedral, max_dihedral, radius_edge=None, min_gamma=0.25):
    """`slivers.element_score` of every element ``(m,)``, compiled.

    Examples
    --------
    >>> p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    >>> round(float(element_scores(p, np.array([[0, 1, 2, 3]]), 10.0, 165.0, min_gamma=0.0)[0]), 4)
    70.5288
    """
    pts = np.ascontiguousarray(points, dtype=np.float64)
    t = np.ascontiguousarray(np.asarray(tets)[:, :4], dtype=np.int64)
    return _element_scores(pts, t, *_scales(min_dihedral, max_dihedral, radius_edge, min_gamma), _OPP, _EDGES,
                           _EDGE_FACES)


def moved_scores(points, tets, moving, which, trials, min_dihedral, max_dihedral, radius_edge=None, min_gamma=0.25):
    """Scores ``(t, k)`` of the elements ``tets`` (k, 4) with node ``moving[i]`` of element
    ``i`` moved to ``trials[j, which[i]]`` (trials ``(t, v, 3)``); -inf where that inverts
    the element."""
    return _moved_scores(np.ascontiguousarray(points, dtype=np.float64),
                         np.ascontiguousarray(tets, dtype=np.int64), np.ascontiguousarray(moving, dtype=np.int64),
                         np.ascontiguousarray(which, dtype=np.int64),
                         np.ascontiguousarray(trials, dtype=np.float64),
                         *_scales(min_dihedral, max_dihedral, radius_edge, min_gamma), _OPP, _EDGES, _EDGE_FACES)


@njit(cache=True, nogil=True)
def _best_trials(points, tets, moving, seg, counts, trials, min_d, hi_scale, re, min_g, opp, edges, edge_faces):
    """For each vertex ``v`` (node ``moving[v]``, elements ``tets[seg[v]:seg[v] + counts[v]]``) the
    first trial whose worst element beats the best of the earlier ones by more than 1e-9, and that
    worst score.  A trial stops at its first element no better than the best so far (its worst
    can only be lower), the element worst at trial 0 first: most trials end after one or two."""
    nt, nv = trials.shape[0], trials.shape[1]
    best = np.zeros(nv, dtype=np.int64)
    best_score = np.empty(nv)
    x = np.empty((4, 3))
    for v in range(nv):
        s0, c, node = seg[v], counts[v], moving[v]
        top = np.inf
        first = s0
        for j in range(nt):
            running = np.inf
            for r in range(c):
                # trial 0 in order (finding its worst element), the others from that element on
                i = s0 + r if j == 0 else (first + r if first + r < s0 + c else first + r - c)
                for k in range(4):
                    nk = tets[i, k]
                    for d in range(3):
                        x[k, d] = trials[j, v, d] if nk == node else points[nk, d]
                sc, vol = _score(x, min_d, hi_scale, re, min_g, opp, edges, edge_faces)
                if not vol > 0:
                    sc = -np.inf
                if sc != sc:
                    running = np.nan  # the worst is undefined: never better (as numpy's min propagates it)
                    break
                if sc < running:
                    running = sc
                    if j == 0:
                        first = i
                if j > 0 and not running > top + 1e-9:
                    break
            if j == 0:
                top = running
                if top != top:
                    break  # an undefined current score: no trial counts as better
            elif running > top + 1e-9:
                top = running
                best[v] = j
        best_score[v] = top
    return best, best_score


def best_trials(points, tets, moving, seg, counts, trials, min_dihedral, max_dihedral, radius_edge=None,
                min_gamma=0.25):
    """The best trial position of each moving vertex and its worst element score.

    Parameters
    ----------
    points : (n, 3) float
    tets : (k, 4) int
        The elements around the moving vertices, those of vertex ``v`` at rows
        ``seg[v] .. seg[v] + counts[v] - 1``.
    moving : (v,) int
        The node moved, one per vertex.
    seg, counts : (v,) int
    trials : (t, v, 3) float
        Trial positions; trial 0 is the current one.
    min_dihedral, max_dihedral, radius_edge, min_gamma
        As for `element_scores`.

    Returns
    -------
    best : (v,) int
        The first trial whose worst element (`moved_scores`, -inf where inverted) is more than
        1e-9 above that of every earlier trial kept, 0 when none is.
    score : (v,) float
        That trial's worst element score.

    Examples
    --------
    >>> p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    >>> trials = np.array([[[0.2, 0.2, 0.2]], [[1.0, 1.0, 1.0]], [[-2.0, -2.0, -2.0]]])
    >>> b, s = best_trials(p, np.array([[0, 1, 3, 2]]), np.array([0]), np.array([0]), np.array([1]), trials,
    ...                    10.0, 165.0, min_gamma=0.0)
    >>> int(b[0]), round(float(s[0]), 4)
    (1, 70.5288)
    """
    return _best_trials(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(tets, dtype=np.int64),
                        np.ascontiguousarray(moving, dtype=np.int64), np.ascontiguousarray(seg, dtype=np.int64),
                        np.ascontiguousarray(counts, dtype=np.int64), np.ascontiguousarray(trials, dtype=np.float64),
                        *_scales(min_dihedral, max_dihedral, radius_edge, min_gamma), _OPP, _EDGES, _EDGE_FACES)


@njit(cache=True, nogil=True)
def _smoothing_set(points, tets, starts, tet_of, cand, prio):
    n = cand.shape[0]
    moves = np.zeros(n, dtype=np.bool_)
    k = 0
    p = 0
    for v in range(n):
        if not cand[v]:
            continue
        ok = True
        for r in range(starts[v], starts[v + 1]):
            t = tet_of[r]
            for c in range(4):
                u = tets[t, c]
                if u != v and cand[u] and prio[u] < prio[v]:
                    ok = False
                    break
            if not ok:
                break
        if ok:
            moves[v] = True
            k += 1
            p += starts[v + 1] - starts[v]
    verts = np.empty(k, dtype=np.int64)
    counts = np.empty(k, dtype=np.int64)
    pair_tet = np.empty(p, dtype=np.int64)
    nbr_mean = np.zeros((k, 3))
    edge = np.zeros(k)
    i = 0
    q = 0
    for v in range(n):
        if not moves[v]:
            continue
        verts[i] = v
        counts[i] = starts[v + 1] - starts[v]
        for r in range(starts[v], starts[v + 1]):
            t = tet_of[r]
            pair_tet[q] = t
            q += 1
            # the same sums, in the same order, as the numpy form (corners summed, minus v, added up)
            for d in range(3):
                s = points[tets[t, 0], d] + points[tets[t, 1], d]
                s = s + points[tets[t, 2], d]
                s = s + points[tets[t, 3], d]
                nbr_mean[i, d] += s - points[v, d]
            for c in range(4):
                u = tets[t, c]
                d0 = points[u, 0] - points[v, 0]
                d1 = points[u, 1] - points[v, 1]
                d2 = points[u, 2] - points[v, 2]
                edge[i] = max(edge[i], math.sqrt(d0 * d0 + d1 * d1 + d2 * d2))
        for d in range(3):
            nbr_mean[i, d] /= 3.0 * counts[i]
        i += 1
    return verts, counts, pair_tet, nbr_mean, edge


def smoothing_set(points, tets, starts, tet_of, cand, prio):
    """The vertices one smoothing round moves and what their trials need, in one compiled pass.

    A candidate vertex (`cand`) moves when its priority (`prio`) is the smallest of the candidates
    of every element around it (no two moving vertices share an element).  The elements around
    vertex ``v`` are ``tet_of[starts[v]:starts[v + 1]]``.

    Returns
    -------
    verts : (k,) int
        The moving vertices, ascending.
    counts : (k,) int
        Their number of elements.
    pair_tet : (p,) int
        Their elements, vertex after vertex.
    nbr_mean : (k, 3) float
        The mean of the other corners of their elements.
    edge : (k,) float
        Their longest edge.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=float)
    >>> t = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
    >>> flat = t.reshape(-1); order = np.argsort(flat, kind="stable")
    >>> starts = np.searchsorted(flat[order], np.arange(6))
    >>> cand = np.array([True, False, False, False, True])
    >>> v, c, pt, mean, edge = smoothing_set(p, t, starts, order // 4, cand, np.array([1, 0, 2, 3, 4]))
    >>> v.tolist(), c.tolist(), pt.tolist(), mean.round(4).tolist(), edge.round(4).tolist()
    ([0, 4], [1, 1], [0, 1], [[0.3333, 0.3333, 0.3333], [0.3333, 0.3333, 0.3333]], [1.0, 1.4142])
    """
    return _smoothing_set(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(tets, dtype=np.int64),
                          np.ascontiguousarray(starts, dtype=np.int64), np.ascontiguousarray(tet_of, dtype=np.int64),
                          np.ascontiguousarray(cand, dtype=np.bool_), np.ascontiguousarray(prio, dtype=np.int64))


@njit(cache=True, nogil=True)
def _corner_measures(points, tets, opp, edge_faces):
    m = tets.shape[0]
    dmin, dmax = np.empty(m), np.empty(m)
    re, sj, vol = np.empty(m), np.empty(m), np.empty(m)
    x = np.empty((4, 3))
    nrm = np.empty((4, 3))
    for t in range(m):
        for k in range(4):
            for d in range(3):
                x[k, d] = points[tets[t, k], d]
        _face_normals(x, opp, nrm)
        lo, hi = 180.0, 0.0
        for e in range(6):
            f, g = edge_faces[e, 0], edge_faces[e, 1]
            cos = nrm[f, 0] * nrm[g, 0] + nrm[f, 1] * nrm[g, 1] + nrm[f, 2] * nrm[g, 2]
            ang = 180.0 - math.degrees(math.acos(min(1.0, max(-1.0, cos))))
            lo = min(lo, ang)
            hi = max(hi, ang)
        dmin[t], dmax[t] = lo, hi
        a0, a1, a2 = x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2]
        b0, b1, b2 = x[2, 0] - x[0, 0], x[2, 1] - x[0, 1], x[2, 2] - x[0, 2]
        c0, c1, c2 = x[3, 0] - x[0, 0], x[3, 1] - x[0, 1], x[3, 2] - x[0, 2]
        bc0, bc1, bc2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
        ca0, ca1, ca2 = c1 * a2 - c2 * a1, c2 * a0 - c0 * a2, c0 * a1 - c1 * a0
        ab0, ab1, ab2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
        det = a0 * bc0 + a1 * bc1 + a2 * bc2
        aa, bb, cc = a0 * a0 + a1 * a1 + a2 * a2, b0 * b0 + b1 * b1 + b2 * b2, c0 * c0 + c1 * c1 + c2 * c2
        m0 = aa * bc0 + bb * ca0 + cc * ab0
        m1 = aa * bc1 + bb * ca1 + cc * ab1
        m2 = aa * bc2 + bb * ca2 + cc * ab2
        circum = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2) / max(2.0 * abs(det), 1e-300)
        short = 1e300
        for i in range(4):
            for j in range(i + 1, 4):
                d0, d1, d2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
                short = min(short, math.sqrt(d0 * d0 + d1 * d1 + d2 * d2))
        re[t] = circum / max(short, 1e-300)
        # Scaled Jacobian: the smallest corner Jacobian over the product of that corner's three edges.
        best = np.inf
        for k in range(4):
            prod = 1.0
            for j in range(3):
                o = opp[k, j]
                d0, d1, d2 = x[o, 0] - x[k, 0], x[o, 1] - x[k, 1], x[o, 2] - x[k, 2]
                prod *= math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            best = min(best, det / max(prod, 1e-300))
        sj[t] = best * math.sqrt(2.0)
        vol[t] = det / 6.0
    return dmin, dmax, re, sj, vol


def corner_measures(points, tets):
    """Smallest and largest dihedral angle (degrees), radius-edge ratio, scaled Jacobian and signed
    volume of each corner tetrahedron, in one compiled pass: five ``(m,)`` arrays, equal to
    `quality.dihedral_angles` (min, max), `radius_edge_ratio`, the 4-node `scaled_jacobian` and
    `tet_volumes` to rounding.

    Examples
    --------
    >>> p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    >>> [round(float(a[0]), 4) for a in corner_measures(p, np.array([[0, 1, 3, 2]]))]
    [70.5288, 70.5288, 0.6124, 1.0, 2.6667]
    """
    pts = np.ascontiguousarray(points, dtype=np.float64)
    t = np.ascontiguousarray(np.asarray(tets)[:, :4], dtype=np.int64)
    return _corner_measures(pts, t, _OPP, _EDGE_FACES)


@njit(cache=True, nogil=True)
def _radius_edge(points, tets, edges):
    m = tets.shape[0]
    out = np.empty(m)
    for t in range(m):
        p0, p1, p2, p3 = tets[t, 0], tets[t, 1], tets[t, 2], tets[t, 3]
        a0, a1, a2 = points[p1, 0] - points[p0, 0], points[p1, 1] - points[p0, 1], points[p1, 2] - points[p0, 2]
        b0, b1, b2 = points[p2, 0] - points[p0, 0], points[p2, 1] - points[p0, 1], points[p2, 2] - points[p0, 2]
        c0, c1, c2 = points[p3, 0] - points[p0, 0], points[p3, 1] - points[p0, 1], points[p3, 2] - points[p0, 2]
        # numpy's einsum sums a row of three as (x0 + x2) + x1; its norm as (x0 + x1) + x2
        aa = (a0 * a0 + a2 * a2) + a1 * a1
        bb = (b0 * b0 + b2 * b2) + b1 * b1
        cc = (c0 * c0 + c2 * c2) + c1 * c1
        bc0, bc1, bc2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
        ca0, ca1, ca2 = c1 * a2 - c2 * a1, c2 * a0 - c0 * a2, c0 * a1 - c1 * a0
        ab0, ab1, ab2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
        n0 = aa * bc0 + bb * ca0 + cc * ab0
        n1 = aa * bc1 + bb * ca1 + cc * ab1
        n2 = aa * bc2 + bb * ca2 + cc * ab2
        det = 2.0 * ((a0 * bc0 + a2 * bc2) + a1 * bc1)
        r = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2) / max(abs(det), 1e-300)
        emin = np.inf
        for e in range(6):
            p, q = tets[t, edges[e, 0]], tets[t, edges[e, 1]]
            d0, d1, d2 = points[q, 0] - points[p, 0], points[q, 1] - points[p, 1], points[q, 2] - points[p, 2]
            length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            if length < emin or length != length:
                emin = length  # a NaN edge makes the minimum NaN, as numpy's
                if length != length:
                    break
        out[t] = r / max(emin, 1e-300)
    return out


def radius_edge(points, tets):
    """`quality.radius_edge_ratio` of the corner tetrahedra ``(m,)`` in one compiled pass, numpy's bits.

    Examples
    --------
    >>> p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    >>> round(float(radius_edge(p, np.array([[0, 1, 2, 3]]))[0]), 4)
    0.6124
    """
    return _radius_edge(np.ascontiguousarray(points, dtype=np.float64),
                        np.ascontiguousarray(np.asarray(tets)[:, :4], dtype=np.int64), _EDGES)


@njit(cache=True, nogil=True)
def _corner_volumes(points, tets):
    m = tets.shape[0]
    out = np.empty(m)
    for t in range(m):
        p0, p1, p2, p3 = tets[t, 0], tets[t, 1], tets[t, 2], tets[t, 3]
        a0, a1, a2 = points[p1, 0] - points[p0, 0], points[p1, 1] - points[p0, 1], points[p1, 2] - points[p0, 2]
        b0, b1, b2 = points[p2, 0] - points[p0, 0], points[p2, 1] - points[p0, 1], points[p2, 2] - points[p0, 2]
        c0, c1, c2 = points[p3, 0] - points[p0, 0], points[p3, 1] - points[p0, 1], points[p3, 2] - points[p0, 2]
        bc0, bc1, bc2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
        # numpy's einsum order over a row of three, from a sum of +0.0 (no -0.0 volume)
        out[t] = (((0.0 + a0 * bc0) + a2 * bc2) + a1 * bc1) / 6.0
    return out


def corner_volumes(points, tets):
    """Signed volumes ``(m,)`` of the corner tetrahedra, `quality.tet_volumes`'s numpy bits in one pass.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    >>> corner_volumes(p, np.array([[0, 1, 2, 3], [0, 2, 1, 3]])).round(6).tolist()
    [0.166667, -0.166667]
    """
    return _corner_volumes(np.ascontiguousarray(points, dtype=np.float64),
                           np.ascontiguousarray(np.asarray(tets)[:, :4], dtype=np.int64))
