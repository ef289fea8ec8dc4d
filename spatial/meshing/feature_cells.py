"""Compiled walks of every vertex and triangle in the sharp-feature rebuild (`spatial.meshing.features`):
the vertices at lattice nodes, and the candidate cells found by runs of one cell's triangles and
grouped by one hash probe per run and a counting sort (the walks over the candidate cells alone are
in `feature_kernels`)."""

from __future__ import annotations

import numba
import numpy as np

@numba.njit(cache=True, nogil=True)
def _at_node(pts, origin, h, node_tol, at, axis):
    """Vertices within `node_tol` voxels of a lattice node in every coordinate (into `at`), and the axis
    of each one's lattice edge (into `axis`: the coordinate farthest from the node; -1 when it sits on
    the node exactly)."""
    n = pts.shape[0]
    for v in range(n):
        axis[v] = -1
        far = 0.0
        for j in range(3):
            u = (pts[v, j] - origin[j]) / h
            d = abs(u - np.floor(u + 0.5))
            if d > far:
                far = d
                axis[v] = j
        at[v] = far < node_tol


@numba.njit(cache=True, nogil=True, inline="always")
def _tri_normal(pts, a, b, c):
    """Cross product of the triangle (a, b, c)'s edges from `a` (twice its area, along its normal)."""
    ux = pts[b, 0] - pts[a, 0]; uy = pts[b, 1] - pts[a, 1]; uz = pts[b, 2] - pts[a, 2]
    vx = pts[c, 0] - pts[a, 0]; vy = pts[c, 1] - pts[a, 1]; vz = pts[c, 2] - pts[a, 2]
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


@numba.njit(cache=True, nogil=True)
def _candidate_cells(pts, faces, origin, h, cos_limit, at_node, vn, run_start, run_key, run_marked):
    """The runs of triangles of one lattice cell and whether one of a run's triangles departs from a
    vertex normal, in one pass each; the vertex normals go into `vn` (overwritten).

    A run is a maximal stretch of consecutive triangles of one cell (the
    merged mesh keeps a cell's triangles together: about one run per cell).
    Run ``r`` holds the triangles ``run_start[r]:run_start[r + 1]`` of cell
    key ``run_key[r]``; `run_marked` says whether one of them is marked.
    Returns the number of runs, the corner and the stride of the keys.
    """
    m = faces.shape[0]
    n = pts.shape[0]
    # cell keys ``(i * s + j) * s + k`` from a corner below every vertex: the order of the keys is the
    # cells' lexicographic order whatever the corner and the stride, as long as they cover the mesh
    lo = np.empty(3, np.int64)
    s = np.int64(1)
    bottom = np.full(3, np.inf)
    top = np.full(3, -np.inf)
    for v in range(n):
        for j in range(3):
            vn[v, j] = 0.0
            q = pts[v, j]
            if q < bottom[j]:
                bottom[j] = q
            if q > top[j]:
                top[j] = q
    for j in range(3):
        lo[j] = np.int64(np.floor((bottom[j] - origin[j]) / h)) - 1
        span = np.int64(np.floor((top[j] - origin[j]) / h)) - lo[j] + 2
        if span > s:
            s = span
    third = 1.0 / 3.0
    n_runs = 0
    for t in range(m):
        # (unsigned indices: numba then skips the wrap-around test of negative ones at every access)
        a, b, c = np.uint64(faces[t, 0]), np.uint64(faces[t, 1]), np.uint64(faces[t, 2])
        cx, cy, cz = _tri_normal(pts, a, b, c)
        vn[a, 0] += cx; vn[a, 1] += cy; vn[a, 2] += cz
        vn[b, 0] += cx; vn[b, 1] += cy; vn[b, 2] += cz
        vn[c, 0] += cx; vn[c, 1] += cy; vn[c, 2] += cz
        k = np.int64(0)
        for j in range(3):
            q = (pts[a, j] + pts[b, j] + pts[c, j]) * third
            k = k * s + np.int64(np.floor((q - origin[j]) / h)) - lo[j]
        if n_runs == 0 or run_key[n_runs - 1] != k:
            run_start[n_runs] = t
            run_key[n_runs] = k
            run_marked[n_runs] = False
            n_runs += 1
    run_start[n_runs] = m
    for v in range(n):
        r = np.sqrt(vn[v, 0] ** 2 + vn[v, 1] ** 2 + vn[v, 2] ** 2)
        if r > 0:
            vn[v, 0] /= r; vn[v, 1] /= r; vn[v, 2] /= r
    for q in range(n_runs):
        for t in range(run_start[q], run_start[q + 1]):
            # (the triangle's normal again, the same bits: cheaper than storing every one)
            a, b, c = np.uint64(faces[t, 0]), np.uint64(faces[t, 1]), np.uint64(faces[t, 2])
            cx, cy, cz = _tri_normal(pts, a, b, c)
            r = np.sqrt(cx ** 2 + cy ** 2 + cz ** 2)
            if r > 0:
                # the smallest cosine is the smallest dot product over `r` (rounding is monotone: the same
                # bits as the smallest of the three quotients), one division instead of three
                low = np.inf
                d = cx * vn[a, 0] + cy * vn[a, 1] + cz * vn[a, 2]
                if d < low:
                    low = d
                d = cx * vn[b, 0] + cy * vn[b, 1] + cz * vn[b, 2]
                if d < low:
                    low = d
                d = cx * vn[c, 0] + cy * vn[c, 1] + cz * vn[c, 2]
                if d < low:
                    low = d
                worst = min(1.0, low / r)
                n_node = at_node[a] + at_node[b] + at_node[c]
                # a triangle joining a node vertex to an ordinary one is the border of such a face: the
                # crossings on lattice edges lying in the face's plane are undefined there, and the chamfer
                # they leave may bend less than the normals' test sees
                if worst < cos_limit or (n_node > 0 and n_node < 3):
                    run_marked[q] = True
                    break       # the run's cell is a candidate: its other triangles need no test
    return n_runs, lo, s


@numba.njit(cache=True, nogil=True)
def _border_nodes(faces, at_node, axis):
    """Vertices at a node (on a lattice edge) in a triangle that also has an ordinary vertex."""
    out = np.zeros(at_node.shape[0], np.bool_)
    for t in range(faces.shape[0]):
        k = at_node[faces[t, 0]] + at_node[faces[t, 1]] + at_node[faces[t, 2]]
        if 0 < k < 3:
            for j in range(3):
                v = faces[t, j]
                if at_node[v] and axis[v] >= 0:
                    out[v] = True
    return out


@numba.njit(cache=True, nogil=True, inline="always")
def _slot(k, mask):
    """Hash slot of a cell key (Fibonacci multiply, high bits folded down: keys come in runs)."""
    x = k * np.int64(-7046029254386353131)
    return (x ^ (x >> 31)) & mask


@numba.njit(cache=True, nogil=True)
def _group_cells(run_start, run_key, n_runs, cells, faces, n, index):
    """The candidate cells' triangles and (cell, vertex) pairs, grouped by cell without a global sort.

    `cells` is the sorted array of candidate cell keys, the runs those of
    `_candidate_cells`.  Each run whose key may be a candidate's (a bit
    array says which may) finds its cell by one probe of an
    open-addressing table (the position in `cells` being the cell's index);
    a counting sort groups the triangles by cell, in triangle order within
    each, and each cell's few distinct vertices are sorted in place.  The
    result is what ``np.unique`` and a stable ``argsort`` of the triangles'
    cells would give.

    Returns
    -------
    tri, tcell : the triangles in candidate cells, by cell, and the cell of each
    pvert : the vertices of the (cell, vertex) pairs sorted (cell ``c``'s are ``starts[c]:starts[c + 1]``)
    starts : (cells + 1,) first pair of every cell
    verts, pinv : the distinct vertices (sorted) and each pair's index among them

    `run_key` is overwritten (with each run's cell, -1 for none); `index`
    (n,) int32 is left holding each vertex's position in `verts` (-1: none).
    """
    n_cells = cells.shape[0]
    size = 1
    while size < 2 * n_cells + 2:
        size *= 2
    mask = size - 1
    table = np.full(size, -1, np.int64)
    # a bit per slot of a table 8 to 16 times as large, set for the candidates' keys: most runs are of no
    # candidate and are told so by this small array (it stays in cache) without probing the table
    bits = 8
    while bits < 8 * n_cells + 8:
        bits *= 2
    fmask = bits - 1
    seen = np.zeros(bits >> 3, np.uint8)
    for c in range(n_cells):
        slot = _slot(cells[c], mask)
        while table[slot] >= 0:
            slot = (slot + 1) & mask
        table[slot] = c
        b = _slot(cells[c], fmask)
        seen[b >> 3] |= np.uint8(1 << (b & 7))
    count = np.zeros(n_cells + 1, np.int64)
    for q in range(n_runs):
        k = run_key[q]
        here = -1
        b = _slot(k, fmask)
        if not (seen[b >> 3] >> (b & 7)) & 1:
            run_key[q] = here
            continue
        slot = _slot(k, mask)
        while True:
            c = table[slot]
            if c < 0:
                break
            if cells[c] == k:
                here = c
                break
            slot = (slot + 1) & mask
        run_key[q] = here
        if here >= 0:
            count[here + 1] += run_start[q + 1] - run_start[q]
    for c in range(n_cells):
        count[c + 1] += count[c]
    n_tri = count[n_cells]
    tri = np.empty(n_tri, np.int64)
    tcell = np.empty(n_tri, np.int64)
    fill = count[:n_cells].copy()
    for q in range(n_runs):
        c = run_key[q]
        if c >= 0:
            for t in range(run_start[q], run_start[q + 1]):
                tri[fill[c]] = t
                tcell[fill[c]] = c
                fill[c] += 1
    # each cell's distinct vertices, sorted (a cell holds a dozen at most: insertion sort)
    buf = np.empty(3 * n_tri, np.int64)
    starts = np.empty(n_cells + 1, np.int64)
    r = 0
    for c in range(n_cells):
        starts[c] = r
        for q in range(count[c], count[c + 1]):
            t = tri[q]
            for j in range(3):
                v = np.int64(faces[t, j])
                i = r
                dup = False
                while i > starts[c] and buf[i - 1] >= v:
                    if buf[i - 1] == v:
                        dup = True
                        break
                    i -= 1
                if dup:
                    continue
                for s in range(r, i, -1):
                    buf[s] = buf[s - 1]
                buf[i] = v
                r += 1
    starts[n_cells] = r
    pvert = buf[:r]
    for v in range(n):
        index[v] = -1
    n_verts = 0
    for i in range(r):
        if index[pvert[i]] < 0:
            index[pvert[i]] = 0
            n_verts += 1
    # (numbered in one pass over the vertices, in their order: the distinct vertices come out sorted)
    verts = np.empty(n_verts, np.int64)
    k = 0
    for v in range(n):
        if index[v] == 0:
            index[v] = k
            verts[k] = v
            k += 1
    pinv = np.empty(r, np.int64)
    for i in range(r):
        pinv[i] = index[pvert[i]]
    return tri, tcell, pvert, starts, verts, pinv


# -- the pass's stages, each one compiled function (one cache load each in a fresh process) ------
# (written without numba's array expressions and `np.unique`: loading a kernel that uses them imports
# numba's ufunc and list modules, some 0.03 s of a fresh process that the plain mesh never pays)

@numba.njit(cache=True, nogil=True)
def _sorted_unique(a):
    """The distinct values of `a`, ascending (`np.unique`; `a` is sorted in place)."""
    a.sort()
    k = 0
    for i in range(a.shape[0]):
        if i == 0 or a[i] != a[k - 1]:
            a[k] = a[i]
            k += 1
    return a[:k].copy()


@numba.njit(cache=True, nogil=True)
def _nodes(pts, faces, origin, h, node_tol, at, axis):
    """`_at_node` (into `at`, `axis`) and `_border_nodes` in one call."""
    _at_node(pts, origin, h, node_tol, at, axis)
    return _border_nodes(faces, at, axis)


@numba.njit(cache=True, nogil=True)
def _cells(pts, faces, origin, h, cos_limit, at_node, vn, run_start, run_key, run_marked, index):
    """`_candidate_cells`, the sorted candidate keys and `_group_cells` in one call (the arrays after
    `at_node` are the work arrays of those two, made by the caller: `run_start` (m + 1,), `run_key`
    (m,), `run_marked` (m,), `index` (n,))."""
    n_runs, lo, s = _candidate_cells(pts, faces, origin, h, cos_limit, at_node, vn, run_start, run_key, run_marked)
    cand = _sorted_unique(run_key[:n_runs][run_marked[:n_runs]])
    tri, tcell, pvert, starts, verts, pinv = _group_cells(run_start, run_key, n_runs, cand, faces, pts.shape[0],
                                                          index)
    return cand, lo, s, tri, tcell, pvert, starts, verts, pinv
