"""Topological sliver removal: edge removal (3-2, 4-4 ... flips, 2-2 flips of planar boundary
diagonals), edge splits, and the rounds of the whole sliver pass after TetGen (`remove_slivers`).

TetGen's output turns on the last bits of the surface's coplanar points; smoothing alone
cannot lift an element whose nodes all lie on the boundary, or one pinned between a face
and its neighbours.  Changing the elements around a bad element's edges can.

References
----------
J. R. Shewchuk, "Two discrete optimization algorithms for the topological improvement
of tetrahedral meshes", 2002 (edge removal).
B. M. Klingner, J. R. Shewchuk, "Aggressive tetrahedral mesh improvement", IMR 2007
(smoothing, flips and vertex insertion in one schedule).
"""

from __future__ import annotations

import numpy as np

from .slivers import _orient, boundary_faces, element_score, flip23, improve

__all__ = ["longest_interior_edges", "remove_edges", "remove_slivers", "split_edges"]


def _triangulations(verts):
    """Every triangulation of the polygon `verts` (a list), as lists of vertex triples."""
    if len(verts) < 3:
        return [[]]
    out = []
    # The triangle on the side (first, last) has its apex at some j; the two sides of it recurse.
    for j in range(1, len(verts) - 1):
        for left in _triangulations(verts[:j + 1]):
            for right in _triangulations(verts[j:]):
                out.append(left + right + [(verts[0], verts[j], verts[-1])])
    return out


#: Largest ring the edge removal tries (its triangulations: 1, 2, 5, 14, 42 for polygons of 3 .. 7).
EDGE_RING_MAX = 6
_TRIANGULATIONS = {k: np.array(_triangulations(list(range(k))), dtype=np.int64) for k in range(3, EDGE_RING_MAX + 2)}
_PAIRS = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
_OTHERS = np.array([[2, 3], [1, 3], [1, 2], [0, 3], [0, 2], [0, 1]])


def _edge_rings(tets, edges):
    """The elements around each edge ``(e, 2)`` of `edges` and the ring of their far vertices.

    Returns ``{(k, closed): (edge rows, elements (r, k), ring vertices (r, k + (not closed)))}``
    for rings of k elements, 1 <= k <= `EDGE_RING_MAX`, in cyclic order; an edge on the
    boundary has an open ring whose first and last vertices are those of its two boundary sides.
    """
    n = int(tets.max(initial=0)) + 1
    ea = np.sort(tets[:, _PAIRS], axis=2).reshape(-1, 2)
    code = ea[:, 0] * n + ea[:, 1]
    want = edges[:, 0] * n + edges[:, 1]
    sel = np.nonzero(np.isin(code, want))[0]
    sel = sel[np.argsort(code[sel], kind="stable")]
    cs = code[sel]
    uniq_w, first_w = np.unique(want, return_index=True)
    edge_row = first_w[np.searchsorted(uniq_w, cs)]
    start = np.r_[0, np.nonzero(cs[1:] != cs[:-1])[0] + 1] if cs.size else np.zeros(0, dtype=np.int64)
    count = np.diff(np.r_[start, cs.size])
    tet_of = sel // 6
    link = tets[tet_of[:, None], _OTHERS[sel % 6]]  # (s, 2) the far edge of each element
    out = {}
    for k in range(1, EDGE_RING_MAX + 1):
        g = np.nonzero(count == k)[0]
        if g.size == 0:
            continue
        idx = start[g][:, None] + np.arange(k)[None, :]
        lk = link[idx]  # (r, k, 2)
        el = tet_of[idx]
        rows = np.arange(g.size)
        # An open ring starts at a far vertex seen once (an end of the path), a closed one anywhere.
        flat = lk.reshape(g.size, 2 * k)
        seen = (flat[:, :, None] == flat[:, None, :]).sum(axis=2)
        ends = seen == 1
        n_ends = ends.sum(axis=1)
        slot = np.where(n_ends > 0, ends.argmax(axis=1), 0)
        e0 = slot // 2
        ring = np.empty((g.size, k + 1), dtype=np.int64)
        ring[:, 0] = flat[rows, slot]
        ring[:, 1] = flat[rows, slot ^ 1]
        used = np.zeros((g.size, k), dtype=bool)
        used[rows, e0] = True
        elems = np.empty((g.size, k), dtype=np.int64)
        elems[:, 0] = el[rows, e0]
        ok = (n_ends == 0) | (n_ends == 2)
        for j in range(1, k):
            last = ring[:, j]
            hit = ((lk[:, :, 0] == last[:, None]) | (lk[:, :, 1] == last[:, None])) & ~used
            ok &= hit.sum(axis=1) == 1
            nxt = hit.argmax(axis=1)
            used[rows, nxt] = True
            elems[:, j] = el[rows, nxt]
            ring[:, j + 1] = np.where(lk[rows, nxt, 0] == last, lk[rows, nxt, 1], lk[rows, nxt, 0])
        closed = ok & (n_ends == 0) & (ring[:, k] == ring[:, 0])
        opened = ok & (n_ends == 2) & (ring[:, k] != ring[:, 0])
        if k >= 3 and closed.any():
            out[(k, True)] = (edge_row[start[g]][closed], elems[closed], ring[closed, :k])
        if k >= 2 and k < EDGE_RING_MAX and opened.any():
            out[(k, False)] = (edge_row[start[g]][opened], elems[opened], ring[opened])
    return out


def remove_edges(points, tets, min_dihedral, max_dihedral, radius_edge=None, rounds=4, boundary=True):
    """Remove edges of bad elements: the k elements around an edge are replaced by the elements
    joining its two ends to a triangulation of the ring of their far vertices (3-2 flips for
    k = 3, 4-4 for k = 4, up to k = `EDGE_RING_MAX`), where that raises the worst score of the ring.

    An edge on the boundary goes only when its two boundary sides lie in one plane (to
    rounding): the surface then keeps its shape and its nodes, with the diagonal of those two
    triangles flipped (2-2 on the boundary), unless the new diagonal is an edge already.
    ``boundary=False`` keeps the boundary as it is.  Each round takes an independent set of
    removals (no element in two), best gains first.  Returns the new elements and the number
    of edges removed.

    References
    ----------
    J. R. Shewchuk, "Two discrete optimization algorithms for the topological improvement
    of tetrahedral meshes", 2002 (edge removal).

    Examples
    --------
    >>> p = np.array([[0, 0, -1], [0, 0, 1], [0.5, 0, 0], [-0.25, 0.433, 0], [-0.25, -0.433, 0]])
    >>> t = np.array([[0, 1, 2, 3], [0, 1, 3, 4], [0, 1, 4, 2]])  # three needles around the edge 0-1
    >>> new, removed = remove_edges(p, t, 10.0, 170.0, boundary=False)
    >>> removed, len(new)
    (1, 2)
    """
    tets = np.asarray(tets, dtype=np.int64)
    total = 0
    target = min_dihedral + 1.0
    n = points.shape[0]
    for _ in range(rounds):
        sc = element_score(points, tets, min_dihedral, max_dihedral, radius_edge)
        bad = np.nonzero(sc < target)[0]
        if bad.size == 0:
            break
        edges = np.unique(np.sort(tets[bad][:, _PAIRS].reshape(-1, 2), axis=1), axis=0)
        rings = _edge_rings(tets, edges)
        existing = None
        ops_old, ops_new, ops_gain = [], [], []
        for (k, closed), (erow, elems, ring) in rings.items():
            if not closed and not boundary:
                continue
            a, b = edges[erow, 0], edges[erow, 1]
            if not closed:
                # The two boundary sides (a, b, first) and (a, b, last) in one plane, and no edge first-last yet.
                x = points
                flat = np.abs(_orient(x, np.stack([a, b, ring[:, 0], ring[:, -1]], axis=1)))
                span = np.linalg.norm(x[a] - x[b], axis=1) * np.maximum(
                    np.linalg.norm(x[ring[:, 0]] - x[a], axis=1), np.linalg.norm(x[ring[:, -1]] - x[a], axis=1))
                planar = flat <= 1e-10 * span * np.linalg.norm(x[ring[:, 0]] - x[ring[:, -1]], axis=1)
                if existing is None:
                    ee = np.sort(tets[:, _PAIRS].reshape(-1, 2), axis=1)
                    existing = np.unique(ee[:, 0] * n + ee[:, 1])
                diag = np.sort(ring[:, [0, -1]], axis=1)
                planar &= ~np.isin(diag[:, 0] * n + diag[:, 1], existing)
                erow, elems, ring, a, b = erow[planar], elems[planar], ring[planar], a[planar], b[planar]
                if erow.size == 0:
                    continue
            old = sc[elems].min(axis=1)
            tri = _TRIANGULATIONS[ring.shape[1]]  # (T, ring - 2, 3)
            r = ring[:, tri]  # (e, T, ring - 2, 3)
            e_, t_, c_ = r.shape[:3]
            ta = np.concatenate([np.broadcast_to(a[:, None, None, None], (e_, t_, c_, 1)), r], axis=3)
            tb = np.concatenate([np.broadcast_to(b[:, None, None, None], (e_, t_, c_, 1)), r], axis=3)
            va = _orient(points, ta.reshape(-1, 4)).reshape(e_, t_, c_)
            vb = _orient(points, tb.reshape(-1, 4)).reshape(e_, t_, c_)
            # Valid: every triangle of the ring separates the two ends (a on one side, b on the other).
            pos = (va > 0).all(axis=2) & (vb < 0).all(axis=2)
            neg = (va < 0).all(axis=2) & (vb > 0).all(axis=2)
            if not closed:
                # Same volume as the elements replaced (the triangles cover the ring's polygon once).
                vol_old = np.abs(_orient(points, tets[elems].reshape(-1, 4))).reshape(e_, -1).sum(axis=1)
                vol_new = np.abs(va).sum(axis=2) + np.abs(vb).sum(axis=2)
                same = np.abs(vol_new - vol_old[:, None]) <= 1e-9 * vol_old[:, None]
                pos &= same
                neg &= same
            valid = pos | neg
            if not valid.any():
                continue
            ta = np.where(neg[:, :, None, None], ta[..., [1, 0, 2, 3]], ta)
            tb = np.where(pos[:, :, None, None], tb[..., [1, 0, 2, 3]], tb)
            new = np.concatenate([ta, tb], axis=2)  # (e, T, 2 (ring - 2), 4)
            nsc = element_score(points, new.reshape(-1, 4), min_dihedral, max_dihedral,
                                radius_edge).reshape(e_, t_, -1).min(axis=2)
            nsc = np.where(valid, nsc, -np.inf)
            best = nsc.argmax(axis=1)
            gain = nsc[np.arange(e_), best] - old
            ok = gain > 1e-6
            if not ok.any():
                continue
            ops_old.extend(elems[ok])
            ops_new.extend(new[np.arange(e_), best][ok])
            ops_gain.extend(gain[ok])
        if not ops_gain:
            break
        gain = np.asarray(ops_gain)
        # Independent set: a removal goes ahead when it is the best of every removal touching its
        # elements; two boundary flips sharing no element may still share a diagonal, hence one
        # removal per node of the edge too.
        key = gain * (1 + 1e-9) + np.arange(gain.size) * 1e-12
        olds = [np.asarray(o) for o in ops_old]
        flat_old = np.concatenate(olds)
        op_of = np.repeat(np.arange(gain.size), [o.size for o in olds])
        best = np.full(len(tets), -np.inf)
        np.maximum.at(best, flat_old, key[op_of])
        nodes_of = np.concatenate([np.unique(tets[o]) for o in olds])
        node_op = np.repeat(np.arange(gain.size), [np.unique(tets[o]).size for o in olds])
        best_node = np.full(n, -np.inf)
        np.maximum.at(best_node, nodes_of, key[node_op])
        won = np.ones(gain.size, dtype=bool)
        np.logical_and.at(won, op_of, best[flat_old] == key[op_of])
        np.logical_and.at(won, node_op, best_node[nodes_of] == key[node_op])
        take = np.nonzero(won)[0]
        keep = np.ones(len(tets), dtype=bool)
        keep[np.concatenate([olds[i] for i in take])] = False
        tets = np.concatenate([tets[keep]] + [np.asarray(ops_new[i]) for i in take])
        total += int(take.size)
    return tets, total


def split_edges(points, tets, edges):
    """Insert a point at the middle of each interior edge ``(e, 2)`` (no two in one element): every
    element around an edge is cut in two.  Returns new points (the middles appended) and elements.

    The halves keep their element's orientation and half its volume; the new points are free to
    be smoothed (the last resort for a sliver whose nodes all lie on the boundary).

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    >>> q, t = split_edges(p, np.array([[0, 1, 2, 3]]), np.array([[0, 1]]))
    >>> q[-1].tolist(), t.tolist()
    ([0.5, 0.0, 0.0], [[4, 1, 2, 3], [0, 4, 2, 3]])
    """
    tets = np.asarray(tets, dtype=np.int64)
    edges = np.sort(np.asarray(edges, dtype=np.int64).reshape(-1, 2), axis=1)
    if edges.size == 0:
        return points, tets
    n = points.shape[0]
    code = np.unique(edges[:, 0] * n + edges[:, 1])
    pairs = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
    te = np.sort(tets[:, pairs], axis=2)
    tcode = te[:, :, 0] * n + te[:, :, 1]  # (m, 6)
    # One split per element: of edges sharing an element the one of smallest code goes ahead (two
    # in one element would leave a hanging node on the neighbours' side).
    while True:
        pos = np.minimum(np.searchsorted(code, tcode), code.size - 1)
        hit = code[pos] == tcode
        many = np.nonzero(hit.sum(axis=1) > 1)[0]
        if many.size == 0:
            break
        r = np.where(hit[many], pos[many], code.size)
        r.sort(axis=1)
        drop = np.unique(r[:, 1:][r[:, 1:] < code.size])
        code = np.delete(code, drop)
    t_idx, e_idx = np.nonzero(hit)
    mid = n + pos[t_idx, e_idx]
    new_pts = 0.5 * (points[code // n] + points[code % n])
    i, j = pairs[e_idx, 0], pairs[e_idx, 1]
    rows = np.arange(t_idx.size)
    h1 = tets[t_idx].copy()
    h2 = tets[t_idx].copy()
    h1[rows, i] = mid
    h2[rows, j] = mid
    keep = np.ones(len(tets), dtype=bool)
    keep[t_idx] = False
    return np.concatenate([points, new_pts]), np.concatenate([tets[keep], h1, h2])


def longest_interior_edges(points, tets, bad):
    """The longest edge of each element where `bad` that is not on the boundary ``(e, 2)``,
    sorted ends; elements with all six edges on the boundary give none."""
    bfaces, _, _ = boundary_faces(tets)
    n = points.shape[0]
    pairs = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
    bedges = np.sort(np.concatenate([bfaces[:, [0, 1]], bfaces[:, [1, 2]], bfaces[:, [2, 0]]]), axis=1)
    bcode = np.unique(bedges[:, 0] * n + bedges[:, 1])
    e = np.sort(tets[np.asarray(bad)][:, pairs], axis=2)  # (b, 6, 2)
    length = np.linalg.norm(points[e[:, :, 0]] - points[e[:, :, 1]], axis=2)
    length = np.where(np.isin(e[:, :, 0] * n + e[:, :, 1], bcode), -1.0, length)
    pick = length.argmax(axis=1)
    rows = np.nonzero(length.max(axis=1) > 0)[0]
    return np.unique(e[rows, pick[rows]], axis=0)


def remove_slivers(points, tets, movable, min_dihedral, max_dihedral, *, radius_edge=None, seed=0, solid=None,
                   slide=None, rounds=3):
    """Rounds of topological and geometric repair while an element scores under `min_dihedral`.

    Each round: 2-3 flips of the bad elements' interior faces, removal of their edges
    (`remove_edges`: 3-2, 4-4 ... and 2-2 on planar boundary), and smoothing of the movable
    vertices (`improve`, boundary vertices where `slide` sliding on `solid`).  Last, for bad
    elements none of whose nodes may move, a point in the middle of their longest interior
    edge (`split_edges`), smoothed, kept when fewer elements score under `min_dihedral` and the
    worst score is no lower.  Returns the points,
    the elements and the counts ``{"flips", "inserted_points"}``.

    Examples
    --------
    A Delaunay mesh of a jittered lattice (nearly cospherical points) is full of slivers:

    >>> from scipy.spatial import Delaunay
    >>> from spatial.fea.quality import dihedral_angles, tet_volumes
    >>> g = np.linspace(0.0, 1.0, 4)
    >>> p = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    >>> free = (p > 0) & (p < 1)
    >>> p += np.where(free, np.random.default_rng(0).normal(scale=1e-3, size=p.shape), 0.0)
    >>> t = Delaunay(p).simplices
    >>> t[tet_volumes(p, t) < 0] = t[tet_volumes(p, t) < 0][:, [0, 2, 1, 3]]
    >>> bool(dihedral_angles(p, t).min() < 1.0)
    True
    >>> q, t2, counts = remove_slivers(p, t, free.all(axis=1), 10.0, 165.0, radius_edge=3.0)
    >>> bool(dihedral_angles(q, t2).min() >= 10.0), round(float(tet_volumes(q, t2).sum()), 12)
    (True, 1.0)
    """
    movable = np.asarray(movable, dtype=bool)
    slide = np.zeros(len(points), dtype=bool) if slide is None else np.asarray(slide, dtype=bool)
    counts = {"flips": 0, "inserted_points": 0}
    tets = np.asarray(tets, dtype=np.int64)
    for extra in range(rounds):
        sc = element_score(points, tets, min_dihedral, max_dihedral, radius_edge)
        if not np.any(sc < min_dihedral):
            return points, tets, counts
        tets, flips = flip23(points, tets, min_dihedral, max_dihedral, radius_edge)
        tets, removed = remove_edges(points, tets, min_dihedral, max_dihedral, radius_edge)
        counts["flips"] += flips + removed
        points = improve(points, tets, movable, min_dihedral, max_dihedral, seed=seed + extra, solid=solid,
                         slide=slide if slide.any() else None, rounds=80, jitter=1.0 + extra, radius_edge=radius_edge)
    # Last resort, where smoothing cannot help (bad elements none of whose nodes may move): a point in the
    # middle of their longest interior edge, smoothed, kept only when fewer elements are then bad.
    sc = element_score(points, tets, min_dihedral, max_dihedral, radius_edge)
    stuck = (sc < min_dihedral) & ~movable[tets].any(axis=1)
    if np.any(stuck):
        q, t2 = split_edges(points, tets, longest_interior_edges(points, tets, stuck))
        added = len(q) - len(points)
        if added:
            mov = np.r_[movable, np.ones(added, dtype=bool)]
            sl = np.r_[slide, np.zeros(added, dtype=bool)]
            t2, removed = remove_edges(q, t2, min_dihedral, max_dihedral, radius_edge)
            q = improve(q, t2, mov, min_dihedral, max_dihedral, seed=seed + rounds, solid=solid,
                        slide=sl if sl.any() else None, rounds=80, jitter=1.0, radius_edge=radius_edge)
            # Judged on the bad elements, not only on the worst: one elsewhere that no split can
            # reach (a flat element of good angles, scored by its gamma) would hide every repair.
            sc2 = element_score(q, t2, min_dihedral, max_dihedral, radius_edge)
            if sc2.min() >= sc.min() and np.count_nonzero(sc2 < min_dihedral) < np.count_nonzero(sc < min_dihedral):
                counts["inserted_points"] += added
                counts["flips"] += removed
                points, tets = q, t2
    return points, tets, counts
