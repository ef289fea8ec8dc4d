"""Fewer triangles from the sharp-feature fans: one vertex of each fanned cell taken by its feature vertex.

A fan over a cell's polygon of ``b`` vertices has ``b`` triangles where
marching cubes had ``b - 2``: two more per feature cell, a share of the mesh
that falls as ``1/N`` (18 % more triangles on the benchmark part at N=40).
Collapsing the edge from the feature vertex to the nearest vertex of its
polygon removes that vertex and the two fan triangles beside it, so a fanned
cell costs no triangle.  The feature vertex keeps its place (on the exact
edge or corner); the polygon vertex moves there, and the triangles around it
outside the cell follow.

A collapse is made only where it keeps the mesh a closed oriented
2-manifold and moves no triangle much:

* the link condition: the feature vertex and the polygon vertex have
  exactly two common neighbours (the two fan triangles of the edge);
* collapses are made one after another on the mesh as the earlier ones left it
  (a feature vertex takes one vertex at most), so each link condition is read
  on the current mesh;
* every triangle that moves keeps an area over a millionth of its longest
  edge squared and turns by less than ``acos(cos_move)`` from where it was;
* the vertex taken joins a vertex beyond the fans (of a face's plain mesh):
  a speck made of fans alone could be turned inside out by collapses that
  each turn its triangles little; and it joins no feature vertex the
  feature vertex does not join already, so the edges between feature
  vertices, the feature curves, are kept as the fans and flips made them.

Cells are taken in order and, in each, the polygon's vertices nearest the
feature vertex first: the result is deterministic.
"""

from __future__ import annotations

from functools import partial

import numba
import numpy as np

from .feature_threads import on_threads, spans

__all__ = ["collapse_fans", "finish"]

#: A triangle moved by a collapse must keep ``cos > COS_MOVE`` between its new and old normals.
COS_MOVE = 0.5


def collapse_fans(points, faces, n, cos_move=COS_MOVE):
    """Collapse, for each feature vertex (index ``>= n``), one ordinary neighbour into it.

    Parameters
    ----------
    points : (p, 3) float
        Vertices; those from `n` on are feature vertices.
    faces : (m, 3) int
        Closed oriented triangles over `points`.
    n : int
        Number of ordinary vertices.
    cos_move : float

    Returns
    -------
    faces : (m - 2 c, 3) int64
        The triangles after ``c`` collapses, those without a feature vertex
        first (the collapsed vertices no longer used; not renumbered).
    collapsed : int
        ``c``.

    Examples
    --------
    >>> import numpy as np
    >>> pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.3, 0.3, 0.4]], float)
    >>> # a tetrahedron whose face (1, 2, 3) is a fan around vertex 4, collapsed into a triangle again
    >>> fan = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4], [2, 3, 4], [3, 1, 4]])
    >>> out, c = collapse_fans(pts, fan, 4)
    >>> c, out.shape
    (1, (4, 3))
    """
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    new = (faces >= n).any(axis=1)
    out, _, c, _ = finish(points, faces[~new], np.zeros(int((~new).sum()), np.bool_), faces[new], n,
                          cos_move, renumber=False)
    return out, c


def finish(points, faces, drop, new_faces, n, cos_move=COS_MOVE, renumber=True, dtype=np.int64,
           overwrite_points=False, overwrite_faces=False, work=None):
    """The feature mesh's triangles: `faces` not in `drop`, then `new_faces`, with the fans collapsed.

    Parameters
    ----------
    points : (p, 3) float
        Vertices; those from `n` on are the feature vertices of `new_faces`.
    faces : (m, 3) int
        Marching cubes' triangles (over the first `n` points).
    drop : (m,) bool
        The triangles the fans replace.
    new_faces : (k, 3) int
        The fans (and their flips).
    n : int
    cos_move : float
    renumber : bool
        Renumber the vertices to those used (in order).
    dtype : {numpy.int64, numpy.int32}
        Integer type of the triangles returned (int32 needs fewer than 2**31 points).
    overwrite_points : bool
        Gather the points used at the front of `points` itself (a float64
        array) and return a view of them, instead of a copy.
    overwrite_faces : bool
        Write the triangles into the rows of `faces` itself and return a
        view of them, where `faces` is a C-contiguous array of `dtype` with
        rows enough (each row is written after the rows it is read from);
        else into a new array.
    work : (into, start), optional
        Work arrays of ``p`` and ``p + 1`` integers, of the type the points'
        count takes (int32 below 2**31 - 1 points, else int64), overwritten;
        else they are made here.

    Returns
    -------
    faces : (m', 3) `dtype`
    used : (p,) bool
        The points the triangles use (the vertices taken by a collapse, and
        marching cubes' inner vertices of the fanned cells, are not).
    collapsed : int
    points : (p', 3) float
        The points used (all of them when not renumbering).
    """
    f = np.ascontiguousarray(faces)
    if f.dtype not in (np.int32, np.int64):
        f = f.astype(np.int64)
    new = np.ascontiguousarray(new_faces, dtype=np.int64).reshape(-1, 3)
    p = np.ascontiguousarray(points, dtype=np.float64)
    if overwrite_points and p is not points:
        raise ValueError("points: overwrite_points needs a C-contiguous float64 array")
    drop = np.ascontiguousarray(drop, dtype=np.bool_)
    n_p = p.shape[0]
    dtype = np.dtype(dtype)
    if dtype not in (np.int32, np.int64):
        raise ValueError(f"dtype: expected numpy.int32 or numpy.int64, got {dtype}")
    if dtype == np.int32 and n_p >= 2 ** 31:
        raise ValueError(f"dtype: int32 triangles cannot index {n_p} points")
    # the arrays over every point or triangle are made here and handed to the kernels; the triangles'
    # array is the input's own where it may be and has rows enough, else one of the exact length
    ix = np.int32 if n_p < 2 ** 31 - 1 else np.int64
    # (the points are gathered forwards, each to a row at or before its own: in place is safe)
    pout = p if overwrite_points or not renumber else np.empty((n_p, 3))
    if work is not None and all(w.dtype == ix and w.flags.c_contiguous for w in work) and \
            work[0].shape == (n_p,) and work[1].shape == (n_p + 1,):
        into, start = work
    else:
        into, start = np.empty(n_p, ix), np.empty(n_p + 1, ix)
    # the vertices near the fans (those of the new triangles), then one walk of the triangles in two chunks
    # on two threads (`feature_threads`): the triangles kept beside the fans, and the vertices of replaced
    # triangles on no new one marked unused
    near = np.zeros(n_p, np.bool_)
    near[new.reshape(-1)] = True
    used = np.ones(n_p, np.bool_)
    tspans = spans(f.shape[0])
    # (the walks and the writes below are steps of one compiled function: one cache load in a fresh process)
    none = np.empty(0, np.int64)
    scans = on_threads([partial(_write, p, f, drop, none.reshape(0, 3), none, 0, none.astype(np.bool_), used,
                                bool(renumber), into, start, np.empty((0, 3), dtype), pout, 0, a, b, near)
                        for a, b in tspans])
    source = np.concatenate([sc[0] for sc in scans]) if len(scans) > 1 else scans[0][0]
    n_kept = sum(sc[1] for sc in scans)
    local, dropped, c, n_dropped = _collapse_local(p, f, source, new, np.int64(n), near, float(cos_move), into, start,
                                                   used, bool(renumber))
    n_out = n_kept + new.shape[0] - n_dropped
    out = _room(f, n_out) if overwrite_faces and f is faces and f.dtype == dtype else None
    if out is None:
        out = np.empty((n_out, 3), dtype)
    # the triangles on this thread, the points used on the other (`start` holds each point's new index)
    n_near = source.shape[0]
    n_used = on_threads([partial(_write, p, f, drop, local, source, n_near, dropped, used, bool(renumber), into,
                                 start, out, pout, step, 0, 0, near) for step in (1, 2)])[1][1]
    return out[:n_out], used, c, pout[:n_used]


def _room(f, rows):
    """`f` (C-contiguous, its rows in order) or the array it is the first rows of, when that has `rows`
    rows (the mesher leaves room behind its triangles and points: `merge_blocks(spare=)`,
    `features.point_room`); else None."""
    if rows <= f.shape[0]:
        return f
    base = f.base
    if (isinstance(base, np.ndarray) and base.dtype == f.dtype and base.ndim == 2 and base.shape[1] == f.shape[1]
            and f.flags.c_contiguous and base.flags.c_contiguous and base.shape[0] >= rows
            and base.__array_interface__["data"][0] == f.__array_interface__["data"][0]):
        return base
    return None


@numba.njit(cache=True, nogil=True)
def _normal(p, a, b, c, ax, ay, az):
    """Cross product of the triangle (a, b, c) with vertex `a` placed at (ax, ay, az)."""
    ux = p[b, 0] - ax; uy = p[b, 1] - ay; uz = p[b, 2] - az
    vx = p[c, 0] - ax; vy = p[c, 1] - ay; vz = p[c, 2] - az
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


@numba.njit(cache=True, nogil=True)
def _scan(f, t0, t1, drop, near, used):
    """Triangles `t0:t1` of `finish`: those kept beside the fans (`near`: the new triangles' vertices),
    returned with the count of triangles kept; the vertices of the replaced triangles on no new one
    (inner vertices of a cell's patch, whose whole star was replaced) marked in `used` (False only is
    written: chunks may share vertices)."""
    # (room for every triangle, of which only the pages written are touched: an array grown in the loop
    # would have numba count its references at every step, six times the walk's own cost)
    source = np.empty(t1 - t0, np.int64)
    n_near = 0
    n_kept = 0
    for t in range(t0, t1):
        # (unsigned indices: numba then skips the wrap-around test of negative ones at every access)
        a, b, c = np.uint64(f[t, 0]), np.uint64(f[t, 1]), np.uint64(f[t, 2])
        if drop[t]:
            if not near[a]:
                used[a] = False
            if not near[b]:
                used[b] = False
            if not near[c]:
                used[c] = False
            continue
        n_kept += 1
        if near[a] or near[b] or near[c]:
            source[n_near] = t
            n_near += 1
    return source[:n_near].copy(), n_kept


@numba.njit(cache=True, nogil=True)
def _collapse_local(p, f, source, new, n, near, cos_move, into, start, used, renumber):
    """The collapses of `finish` on the triangles near the fans (gathered: `local`, the rows `source` of
    `f` then the new ones), into `into` (p,) and with `start` (p + 1,) as work; returns them, the local
    triangles dropped, the count of collapses and of local triangles dropped.  `used` is cleared for
    the vertices taken, and `start` left holding each point's index among those written."""
    n_p = p.shape[0]
    n_near = source.shape[0]
    k = n_near + new.shape[0]
    faces = np.empty((k, 3), np.int64)
    for r in range(n_near):
        for j in range(3):
            faces[r, j] = f[source[r], j]
    r = n_near
    for t in range(new.shape[0]):
        for j in range(3):
            faces[r, j] = new[t, j]
        r += 1
    dropped, c = _collapse(p, faces, n, near, cos_move, into, start)
    for v in range(n_p):
        if into[v] != v:
            used[v] = False
    n_dropped = 0
    for s in range(k):
        n_dropped += dropped[s]
    # (`start` is free once the collapses are made)
    q = 0
    for v in range(n_p):
        start[v] = q if renumber else v
        q += used[v]
    return faces, dropped, c, n_dropped


@numba.njit(cache=True, nogil=True)
def _write(p, f, drop, faces, source, n_near, dropped, used, renumber, into, index, out, pout, step, t0, t1, near):
    """A walk of `finish`: `_scan` of triangles `t0:t1` (step 0: returns its triangles and count), the
    triangles into `out` (step 1; `out` may be `f` itself: row ``r`` is written once rows ``<= r`` of `f`
    are read) or the points used into `pout` (step 2; `index`: each point's new index; returns their
    count with an empty array)."""
    if step == 0:
        return _scan(f, t0, t1, drop, near, used)
    m = f.shape[0]
    n_p = p.shape[0]
    k = faces.shape[0]
    if step == 1:
        r = 0
        s = 0     # next local triangle that came from `f`
        for t in range(m):
            if drop[t]:
                continue
            if s < n_near and source[s] == t:
                if not dropped[s]:
                    for j in range(3):
                        out[r, j] = index[into[faces[s, j]]]
                    r += 1
                s += 1
            else:
                a, b, c = np.uint64(f[t, 0]), np.uint64(f[t, 1]), np.uint64(f[t, 2])
                out[r, 0] = index[a]
                out[r, 1] = index[b]
                out[r, 2] = index[c]
                r += 1
        for s in range(n_near, k):
            if not dropped[s]:
                for j in range(3):
                    out[r, j] = index[into[faces[s, j]]]
                r += 1
    # the points used, in order (all of them when not renumbering)
    q = 0
    if step == 2:
        for v in range(n_p):
            if used[v] or not renumber:
                pout[q, 0] = p[v, 0]; pout[q, 1] = p[v, 1]; pout[q, 2] = p[v, 2]
                q += 1
    return source[:0].copy(), q


@numba.njit(cache=True, nogil=True)
def _collapse(p, faces, n, near, cos_move, into, start):
    """Collapses on the local triangles `faces`: the vertex each point went into (`into`, filled), the
    triangles dropped.  `start` (p + 1,) is a work array."""
    m = faces.shape[0]
    n_p = p.shape[0]
    start[:] = 0
    for t in range(m):
        for j in range(3):
            if near[faces[t, j]]:
                start[faces[t, j] + 1] += 1
    for v in range(n_p):
        start[v + 1] += start[v]
    star = np.empty(start[n_p], np.int64)
    # each vertex's triangles in order, its `start` used as the cursor, then shifted back
    for t in range(m):
        for j in range(3):
            v = faces[t, j]
            if near[v]:
                star[start[v]] = t
                start[v] += 1
    for v in range(n_p, 0, -1):
        start[v] = start[v - 1]
    start[0] = 0
    # the mesh as it is after the collapses made so far: a collapsed vertex is read as the feature
    # vertex it went into (a feature vertex takes one at most), dropped triangles are skipped
    for v in range(n_p):
        into[v] = v
    dropped = np.zeros(m, np.bool_)
    tri = np.empty(128, np.int64)
    ring = np.empty(64, np.int64)
    dist = np.empty(64)
    # the buffers of `_can_collapse`, made once (an allocation per trial cost a third of the pass)
    tv = np.empty(128, np.int64)
    common = np.empty(16, np.int64)
    nb = np.empty(3 * tri.shape[0], np.int64)
    c = 0
    for fv in range(n, n_p):
        # ordinary neighbours of the feature vertex, nearest first
        k = 0
        n_t = _live_star(star, start, dropped, fv, tri)
        for q in range(n_t):
            t = tri[q]
            for j in range(3):
                w = into[faces[t, j]]
                if w < n:
                    dup = False
                    for i in range(k):
                        if ring[i] == w:
                            dup = True
                            break
                    if not dup and k < ring.shape[0]:
                        d = 0.0
                        for a in range(3):
                            d += (p[w, a] - p[fv, a]) ** 2
                        i = k
                        while i > 0 and (dist[i - 1] > d or (dist[i - 1] == d and ring[i - 1] > w)):
                            ring[i] = ring[i - 1]
                            dist[i] = dist[i - 1]
                            i -= 1
                        ring[i] = w
                        dist[i] = d
                        k += 1
        # the feature vertex's neighbours (each corner of its live star, mapped), read by every trial
        n_nb = 0
        for q in range(n_t):
            t = tri[q]
            for j in range(3):
                w = into[faces[t, j]]
                dup = False
                for i in range(n_nb):
                    if nb[i] == w:
                        dup = True
                        break
                if not dup and n_nb < nb.shape[0]:
                    nb[n_nb] = w
                    n_nb += 1
        for i in range(k):
            v = ring[i]
            if _can_collapse(p, faces, star, start, dropped, into, near, n, v, fv, cos_move, tv, nb, n_nb, common):
                n_t = _live_star(star, start, dropped, v, tri)
                for q in range(n_t):
                    t = tri[q]
                    if into[faces[t, 0]] == fv or into[faces[t, 1]] == fv or into[faces[t, 2]] == fv:
                        dropped[t] = True
                into[v] = fv
                c += 1
                break
    return dropped, c


@numba.njit(cache=True, nogil=True)
def _live_star(star, start, dropped, x, out):
    """The triangles around vertex `x` not dropped.  (Only stars of vertices not collapsed and of feature
    vertices not yet given one are read: those are their first stars less the dropped triangles.)"""
    k = 0
    for q in range(start[x], start[x + 1]):
        t = star[q]
        if not dropped[t] and k < out.shape[0]:
            out[k] = t
            k += 1
    return k


@numba.njit(cache=True, nogil=True, inline="always")
def _among(values, count, w):
    """Whether `w` is one of the first `count` `values` (a feature vertex's neighbours: whether one of
    its live triangles has a corner that maps to `w`)."""
    for s in range(count):
        if values[s] == w:
            return True
    return False


@numba.njit(cache=True, nogil=True)
def _can_collapse(p, faces, star, start, dropped, into, near, n, v, fv, cos_move, tv, nb, n_nb, common):
    """Whether moving `v` onto the feature vertex `fv` (and dropping their two triangles) is safe
    (`tv`, `common`: buffers of 128 and 16; the first `n_nb` of `nb` are the distinct corners of the live
    star of `fv`, mapped)."""
    n_v = _live_star(star, start, dropped, v, tv)
    # `v` must join a vertex beyond the fans (a face's plain mesh: a speck made of fans alone can be
    # turned inside out by collapses that each turn its triangles little); and no feature vertex that
    # `fv` does not join already, so that the edges between feature vertices (the feature curves) stay
    # as the fans and flips made them
    beyond = False
    for q in range(n_v):
        t = tv[q]
        for j in range(3):
            w = into[faces[t, j]]
            if not near[w]:
                beyond = True
            if w >= n and w != fv and not _among(nb, n_nb, w):
                return False
    if not beyond:
        return False
    # the link condition: exactly two triangles hold the edge, and the two ends share no other neighbour
    shared = 0
    for q in range(n_v):
        t = tv[q]
        if into[faces[t, 0]] == fv or into[faces[t, 1]] == fv or into[faces[t, 2]] == fv:
            shared += 1
    if shared != 2:
        return False
    n_common = 0
    for q in range(n_v):
        t = tv[q]
        for j in range(3):
            w = into[faces[t, j]]
            if w == v or w == fv:
                continue
            if _among(nb, n_nb, w):
                new = True
                for i in range(n_common):
                    if common[i] == w:
                        new = False
                if new:
                    if n_common == common.shape[0]:
                        return False
                    common[n_common] = w
                    n_common += 1
    if n_common != 2:
        return False
    # every triangle that moves stays a triangle and turns little
    x0, x1, x2 = p[fv, 0], p[fv, 1], p[fv, 2]
    for q in range(n_v):
        t = tv[q]
        j = 0
        while into[faces[t, j]] != v:
            j += 1
        a, b, c = v, into[faces[t, (j + 1) % 3]], into[faces[t, (j + 2) % 3]]
        if b == fv or c == fv:
            continue
        ox, oy, oz = _normal(p, a, b, c, p[v, 0], p[v, 1], p[v, 2])
        nx, ny, nz = _normal(p, a, b, c, x0, x1, x2)
        area = np.sqrt(nx * nx + ny * ny + nz * nz)
        old = np.sqrt(ox * ox + oy * oy + oz * oz)
        e_bc = (p[b, 0] - p[c, 0]) ** 2 + (p[b, 1] - p[c, 1]) ** 2 + (p[b, 2] - p[c, 2]) ** 2
        e_b = (p[b, 0] - x0) ** 2 + (p[b, 1] - x1) ** 2 + (p[b, 2] - x2) ** 2
        e_c = (p[c, 0] - x0) ** 2 + (p[c, 1] - x1) ** 2 + (p[c, 2] - x2) ** 2
        e = max(e_bc, e_b, e_c)
        if not area > 1e-6 * e or not (nx * ox + ny * oy + nz * oz) > cos_move * area * old:
            return False
    return True
