"""Compiled walks of every vertex and triangle in the sharp-feature rebuild (`spatial.meshing.features`):
the vertices at lattice nodes, and the candidate cells found by runs of one cell's triangles and
grouped by one hash probe per run and a counting sort (the walks over the candidate cells alone are
in `feature_kernels`).  Each walk takes a chunk of the vertices, triangles or runs, and `nodes` and
`cells` run the chunks on two threads (`feature_threads`), with the serial walk's result bit for bit.
Small serial steps are folded into the walks beside them (the key frame, the later chunks' normal sums,
the merge of the last two chunks' keys, the offsets of the counting sort): each compiled function called
from Python is one cache load in a fresh process (some 2 ms each)."""

from __future__ import annotations

from functools import partial

import numba
import numpy as np

from .feature_threads import CHUNKS, on_threads, spans

@numba.njit(cache=True, nogil=True)
def _at_node(pts, v0, v1, origin, h, node_tol, at, axis):
    """Vertices `v0:v1` within `node_tol` voxels of a lattice node in every coordinate (into `at`), and
    the axis of each one's lattice edge (into `axis`: the coordinate farthest from the node; -1 when it
    sits on the node exactly)."""
    for v in range(v0, v1):
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
def _border_nodes(faces, t0, t1, at_node, axis, out):
    """Vertices at a node (on a lattice edge) in a triangle of `t0:t1` that also has an ordinary vertex
    (into `out`, all False: each chunk its own array, merged by the caller)."""
    for t in range(t0, t1):
        k = at_node[faces[t, 0]] + at_node[faces[t, 1]] + at_node[faces[t, 2]]
        if 0 < k < 3:
            for j in range(3):
                v = faces[t, j]
                if at_node[v] and axis[v] >= 0:
                    out[v] = True


@numba.njit(cache=True, nogil=True)
def _node_step(step, pts, faces, a, b, origin, h, node_tol, at, axis, out, vn, box):
    """`_at_node` of vertices `a:b` (step 0), `_border_nodes` of triangles `a:b` (step 1) or `_bounds` of
    vertices `a:b` (step 2; the other steps' arrays unread): one compiled function, one cache load in a
    fresh process."""
    if step == 0:
        _at_node(pts, a, b, origin, h, node_tol, at, axis)
    elif step == 1:
        _border_nodes(faces, a, b, at, axis, out)
    else:
        _bounds(pts, a, b, vn, box)


@numba.njit(cache=True, nogil=True, inline="always")
def _slot(k, mask):
    """Hash slot of a cell key (Fibonacci multiply, high bits folded down: keys come in runs)."""
    x = k * np.int64(-7046029254386353131)
    return (x ^ (x >> 31)) & mask


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
def _merge_unique(a, b):
    """The distinct values of two ascending arrays of distinct values, ascending."""
    out = np.empty(a.shape[0] + b.shape[0], a.dtype)
    i = j = k = 0
    while i < a.shape[0] or j < b.shape[0]:
        if j == b.shape[0] or (i < a.shape[0] and a[i] < b[j]):
            out[k] = a[i]
            i += 1
        elif i == a.shape[0] or b[j] < a[i]:
            out[k] = b[j]
            j += 1
        else:
            out[k] = a[i]
            i += 1
            j += 1
        k += 1
    return out[:k].copy()


# -- the candidate cells: chunks of vertices, triangles and runs ---------------------------------
# A run is a maximal stretch of consecutive triangles of one lattice cell (the merged mesh keeps a
# cell's triangles together: about one run per cell).  The chunk of triangles `t0:t1` writes its runs
# from row `t0` of the run arrays (a chunk has no more runs than triangles): its runs are rows
# ``t0:t0 + count`` and the last one ends at ``run_start[t0 + count]``.  A cell's triangles split
# across two chunks make two runs of one key, which group as the one run would.

@numba.njit(cache=True, nogil=True)
def _bounds(pts, v0, v1, vn, box):
    """The least and greatest coordinates of vertices `v0:v1` into `box` (2, 3) (inf and -inf for none),
    their rows of the vertex normals `vn` zeroed."""
    for j in range(3):
        box[0, j] = np.inf
        box[1, j] = -np.inf
    for v in range(v0, v1):
        for j in range(3):
            vn[v, j] = 0.0
            q = pts[v, j]
            if q < box[0, j]:
                box[0, j] = q
            if q > box[1, j]:
                box[1, j] = q


@numba.njit(cache=True, nogil=True)
def _key_frame(boxes, origin, h):
    """The corner and stride of the cell keys ``(i * s + j) * s + k`` from the chunks' bounds (k, 2, 3):
    a corner below every vertex, so that the keys' order is the cells' lexicographic order."""
    lo = np.empty(3, np.int64)
    s = np.int64(1)
    for j in range(3):
        bottom, top = np.inf, -np.inf
        for c in range(boxes.shape[0]):
            if boxes[c, 0, j] < bottom:
                bottom = boxes[c, 0, j]
            if boxes[c, 1, j] > top:
                top = boxes[c, 1, j]
        lo[j] = np.int64(np.floor((bottom - origin[j]) / h)) - 1
        span = np.int64(np.floor((top - origin[j]) / h)) - lo[j] + 2
        if span > s:
            s = span
    return lo, s


@numba.njit(cache=True, nogil=True)
def _walk(pts, faces, t0, t1, origin, h, boxes, vn, skip, run_start, run_key, run_marked):
    """Triangles `t0:t1`: their normals added to `vn` at the vertices no earlier triangle holds, and
    their runs (from row `t0`), keyed in the frame `_key_frame` makes of the chunks' `boxes` (every
    chunk makes the same).

    `skip` (n,) bool, all False, is set here for the vertices of the triangles before `t0`: those
    vertices' sums belong to an earlier chunk, which must add its triangles first, so the triangles
    of this chunk are added to them afterwards (`_normalize`) and each sum is made in triangle
    order, as one walk makes it.  Returns the number of runs, the first and last triangle holding
    a skipped vertex (``t1, t0 - 1`` for none) and the key frame ``lo, s``.
    """
    lo, s = _key_frame(boxes, origin, h)
    for t in range(t0):
        skip[faces[t, 0]] = True
        skip[faces[t, 1]] = True
        skip[faces[t, 2]] = True
    first, last = t1, t0 - 1
    third = 1.0 / 3.0
    n_runs = 0
    for t in range(t0, t1):
        # (unsigned indices: numba then skips the wrap-around test of negative ones at every access)
        a, b, c = np.uint64(faces[t, 0]), np.uint64(faces[t, 1]), np.uint64(faces[t, 2])
        cx, cy, cz = _tri_normal(pts, a, b, c)
        if skip[a] or skip[b] or skip[c]:
            if first == t1:
                first = t
            last = t
        if not skip[a]:
            vn[a, 0] += cx; vn[a, 1] += cy; vn[a, 2] += cz
        if not skip[b]:
            vn[b, 0] += cx; vn[b, 1] += cy; vn[b, 2] += cz
        if not skip[c]:
            vn[c, 0] += cx; vn[c, 1] += cy; vn[c, 2] += cz
        k = np.int64(0)
        for j in range(3):
            q = (pts[a, j] + pts[b, j] + pts[c, j]) * third
            k = k * s + np.int64(np.floor((q - origin[j]) / h)) - lo[j]
        if n_runs == 0 or run_key[t0 + n_runs - 1] != k:
            run_start[t0 + n_runs] = t
            run_key[t0 + n_runs] = k
            run_marked[t0 + n_runs] = False
            n_runs += 1
    # (a full chunk's end is the next chunk's first start, written there)
    if t0 + n_runs < t1:
        run_start[t0 + n_runs] = t1
    return n_runs, first, last, lo, s


@numba.njit(cache=True, nogil=True)
def _normalize(pts, faces, vn, v0, v1, index, first, last, skips):
    """Rows `v0:v1` of the vertex normals made unit (zero ones left), and of `index` set to -1; first, the
    rows' sums completed by the triangles of the later chunks (per chunk of triangles ``i`` from the
    second on: ``first[i]:last[i] + 1``, those holding a vertex it skipped, as `_walk` returns them, and
    its marks ``skips[i]``), chunk after chunk: each sum in triangle order, as one walk makes it."""
    for i in range(1, first.shape[0]):
        for t in range(first[i], last[i] + 1):
            a, b, c = np.uint64(faces[t, 0]), np.uint64(faces[t, 1]), np.uint64(faces[t, 2])
            for j in range(3):
                v = np.int64(faces[t, j])
                if v0 <= v < v1 and skips[i, v]:
                    cx, cy, cz = _tri_normal(pts, a, b, c)
                    vn[v, 0] += cx; vn[v, 1] += cy; vn[v, 2] += cz
    for v in range(v0, v1):
        index[v] = -1
        r = np.sqrt(vn[v, 0] ** 2 + vn[v, 1] ** 2 + vn[v, 2] ** 2)
        if r > 0:
            vn[v, 0] /= r; vn[v, 1] /= r; vn[v, 2] /= r


@numba.njit(cache=True, nogil=True)
def _mark(pts, faces, cos_limit, at_node, vn, run_start, run_key, run_marked, q0, q1):
    """Runs `q0:q1` holding a triangle whose normal departs from a vertex normal (`run_marked`); returns
    their distinct keys, ascending."""
    keys = np.empty(q1 - q0, np.int64)
    n_keys = 0
    for q in range(q0, q1):
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
                    keys[n_keys] = run_key[q]
                    n_keys += 1
                    break       # the run's cell is a candidate: its other triangles need no test
    return _sorted_unique(keys[:n_keys])


# -- the candidate cells' triangles and vertices, grouped by cell without a global sort ----------

@numba.njit(cache=True, nogil=True)
def _cell_table(a, b):
    """The candidate keys: the distinct values of the ascending `a` and `b` (`_merge_unique`), an
    open-addressing table of them (each slot a position in the keys, -1 free) and a bit per slot of a
    table 8 to 16 times as large, set for the candidates' keys: most runs are of no candidate and are
    told so by this small array (it stays in cache) without probing."""
    cells = _merge_unique(a, b)
    n_cells = cells.shape[0]
    size = 1
    while size < 2 * n_cells + 2:
        size *= 2
    table = np.full(size, -1, np.int64)
    bits = 8
    while bits < 8 * n_cells + 8:
        bits *= 2
    seen = np.zeros(bits >> 3, np.uint8)
    for c in range(n_cells):
        slot = _slot(cells[c], size - 1)
        while table[slot] >= 0:
            slot = (slot + 1) & (size - 1)
        table[slot] = c
        q = _slot(cells[c], bits - 1)
        seen[q >> 3] |= np.uint8(1 << (q & 7))
    return cells, table, seen


@numba.njit(cache=True, nogil=True)
def _probe(run_start, run_key, q0, q1, cells, table, seen, count):
    """Runs `q0:q1`: each one's key overwritten by its cell's position in `cells` (-1: no candidate),
    and the triangles of each cell counted into ``count[c + 1]`` (zeros)."""
    mask = table.shape[0] - 1
    fmask = 8 * seen.shape[0] - 1
    for q in range(q0, q1):
        k = run_key[q]
        here = -1
        b = _slot(k, fmask)
        if (seen[b >> 3] >> (b & 7)) & 1:
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


@numba.njit(cache=True, nogil=True)
def _offsets(counts):
    """From the chunks' counts (k, cells + 1): the first row of each cell, all chunks together (cells + 1,),
    and each chunk's first row in each cell (k, cells), chunk after chunk."""
    k, n1 = counts.shape
    start = np.zeros(n1, np.int64)
    for c in range(n1 - 1):
        total = 0
        for j in range(k):
            total += counts[j, c + 1]
        start[c + 1] = start[c] + total
    fill = np.empty((k, n1 - 1), np.int64)
    for c in range(n1 - 1):
        r = start[c]
        for j in range(k):
            fill[j, c] = r
            r += counts[j, c + 1]
    return start, fill


@numba.njit(cache=True, nogil=True)
def _fill(run_start, run_key, q0, q1, counts, chunk, tri, tcell):
    """The triangles of runs `q0:q1` (chunk `chunk` of those counted in `counts`) of a candidate cell into
    their rows of `tri` and `tcell` (the chunk's first row in each cell from `_offsets`)."""
    fill = _offsets(counts)[1][chunk]
    for q in range(q0, q1):
        c = run_key[q]
        if c >= 0:
            r = fill[c]
            for t in range(run_start[q], run_start[q + 1]):
                tri[r] = t
                tcell[r] = c
                r += 1
            fill[c] = r


@numba.njit(cache=True, nogil=True)
def _cell_vertices(tri, faces, counts, n_cells, index):
    """Each cell's distinct vertices, sorted (a cell holds a dozen at most: insertion sort), and the
    first of each cell (cells + 1,); ``index[v] = 0`` for those vertices (`_mark_vertices`).  `counts`:
    the chunks' triangle counts per cell (`_probe`)."""
    count = _offsets(counts)[0]
    buf = np.empty(3 * tri.shape[0], np.int64)
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
    _mark_vertices(pvert, index)
    return pvert, starts


@numba.njit(cache=True, nogil=True)
def _count_marked(index, v0, v1):
    """How many of `index[v0:v1]` are 0 (the vertices of some candidate cell)."""
    k = 0
    for v in range(v0, v1):
        k += index[v] == 0
    return k


@numba.njit(cache=True, nogil=True)
def _number(index, v0, v1, k, verts, count):
    """The marked vertices of `v0:v1` numbered from `k` in their order (into `index` and `verts`), the
    others' -1 left; with `count`, only how many they are (`_count_marked`)."""
    if count:
        return _count_marked(index, v0, v1)
    for v in range(v0, v1):
        if index[v] == 0:
            index[v] = k
            verts[k] = v
            k += 1
    return k


@numba.njit(cache=True, nogil=True)
def _mark_vertices(pvert, index):
    """``index[v] = 0`` for the vertices of the (cell, vertex) pairs."""
    for i in range(pvert.shape[0]):
        index[pvert[i]] = 0


# -- the pass's walks over every vertex and triangle, chunk by chunk on two threads --------------

# (the arrays a step of `_node_step` does not read)
_NO_VN, _NO_BOX, _NO_AXIS = np.empty((0, 3)), np.empty((2, 3)), np.empty(0, np.int8)


def nodes(pts, faces, origin, h, node_tol, at, axis, chunks=CHUNKS):
    """The vertices at lattice nodes (`_at_node`, into `at` and `axis`) and, returned (n,) bool, those of
    them in a triangle that also has an ordinary vertex (`_border_nodes`)."""
    n, m = pts.shape[0], faces.shape[0]
    found = [np.zeros(n, np.bool_) for _ in range(chunks)]
    on_threads([partial(_node_step, 0, pts, faces, a, b, origin, h, node_tol, at, axis, found[0], _NO_VN, _NO_BOX)
                for a, b in spans(n, chunks)])
    on_threads([partial(_node_step, 1, pts, faces, a, b, origin, h, node_tol, at, axis, found[i], _NO_VN, _NO_BOX)
                for i, (a, b) in enumerate(spans(m, chunks))])
    for more in found[1:]:
        np.logical_or(found[0], more, out=found[0])
    return found[0]


def cells(pts, faces, origin, h, cos_limit, at_node, vn, run_start, run_key, run_marked, index, chunks=CHUNKS):
    """The candidate cells and their triangles and vertices, grouped by cell.

    The vertex normals go into `vn` (n, 3) (overwritten); `run_start` (m + 1,),
    `run_key` (m,) and `run_marked` (m,) are work arrays, `index` (n,) int32 is
    left holding each vertex's position in `verts` (-1: none).  The walks run
    in `chunks` chunks of vertices, triangles or runs (`feature_threads`); the
    result is the same for every number of chunks.

    Returns
    -------
    cand : (c,) int64
        The candidate cells' keys ``(i * s + j) * s + k``, ascending (cell
        ``(i, j, k) + lo``).
    lo : (3,) int64
    s : int
    tri, tcell : (t,) int64
        The triangles in candidate cells, by cell (in triangle order within
        each), and the cell of each.
    pvert : (r,) int64
        The vertices of the (cell, vertex) pairs sorted (cell ``c``'s are
        ``starts[c]:starts[c + 1]``).
    starts : (c + 1,) int64
    verts, pinv : (u,) int64, (r,) int64
        The distinct vertices (sorted) and each pair's index among them.
    """
    n, m = pts.shape[0], faces.shape[0]
    vspans, tspans = spans(n, chunks), spans(m, chunks)
    boxes = np.empty((len(vspans), 2, 3))
    on_threads([partial(_node_step, 2, pts, faces, a, b, origin, float(h), 0.0, at_node, _NO_AXIS, at_node, vn,
                        boxes[i]) for i, (a, b) in enumerate(vspans)])
    skips = np.zeros((len(tspans), n), np.bool_)
    walked = on_threads([partial(_walk, pts, faces, a, b, origin, h, boxes, vn, skips[i], run_start, run_key,
                                 run_marked) for i, (a, b) in enumerate(tspans)])
    lo, s = walked[0][3], int(walked[0][4])
    first = np.array([w[1] for w in walked], np.int64)
    last = np.array([w[2] for w in walked], np.int64)
    run_start[m] = m
    rspans = [(a, a + w[0]) for (a, _), w in zip(tspans, walked)]
    on_threads([partial(_normalize, pts, faces, vn, a, b, index, first, last, skips) for a, b in vspans])
    del skips
    keys = on_threads([partial(_mark, pts, faces, cos_limit, at_node, vn, run_start, run_key, run_marked, q0, q1)
                       for q0, q1 in rspans])
    cand = keys[0]
    for k in keys[1:-1]:
        cand = _merge_unique(cand, k)
    empty = np.empty(0, np.int64)
    # (the last two merged with the table made of them: one compiled call)
    cand, table, seen = _cell_table(cand, keys[-1] if len(keys) > 1 else empty)
    if cand.shape[0] == 0:
        return cand, lo, s, empty, empty, empty, np.zeros(1, np.int64), empty, empty
    tri, tcell, pvert, starts, verts, pinv = group(run_start, run_key, rspans, cand, faces, index, vspans,
                                                   (table, seen))
    return cand, lo, s, tri, tcell, pvert, starts, verts, pinv


def group(run_start, run_key, rspans, cells, faces, index, vspans, table=None):
    """The candidate cells' triangles and (cell, vertex) pairs, grouped by cell without a global sort.

    `cells` is the sorted array of candidate cell keys; the runs are the
    rows ``q0:q1`` of `run_start` and `run_key` for each ``(q0, q1)`` of
    `rspans` (run ``q`` holds the triangles ``run_start[q]:run_start[q + 1]``).
    Each run whose key may be a candidate's finds its cell by one probe of an
    open-addressing table; a counting sort groups the triangles by cell, in
    triangle order within each, and each cell's few distinct vertices are
    sorted in place.  The result is what ``np.unique`` and a stable
    ``argsort`` of the triangles' cells would give.  Each span of runs, and
    of the vertices (`vspans`), is a chunk (`feature_threads`).

    Returns ``tri, tcell, pvert, starts, verts, pinv`` as `cells` does;
    `run_key` is overwritten (with each run's cell, -1 for none) and `index`
    (n,) int32, all -1, is left holding each vertex's position in `verts`.
    `table`: ``(table, seen)`` of `_cell_table` for `cells`, when made already.
    """
    n_cells = cells.shape[0]
    if table is None:
        _, *table = _cell_table(cells, cells[:0])
    table, seen = table
    counts = np.zeros((len(rspans), n_cells + 1), np.int64)
    on_threads([partial(_probe, run_start, run_key, q0, q1, cells, table, seen, counts[i])
                for i, (q0, q1) in enumerate(rspans)])
    total = int(counts.sum())
    tri, tcell = np.empty(total, np.int64), np.empty(total, np.int64)
    on_threads([partial(_fill, run_start, run_key, q0, q1, counts, i, tri, tcell) for i, (q0, q1) in enumerate(rspans)])
    pvert, starts = _cell_vertices(tri, faces, counts, n_cells, index)
    none = np.empty(0, np.int64)
    counted = on_threads([partial(_number, index, a, b, 0, none, True) for a, b in vspans])
    verts = np.empty(sum(counted), np.int64)
    first = np.cumsum([0] + counted[:-1])
    on_threads([partial(_number, index, a, b, int(first[i]), verts, False) for i, (a, b) in enumerate(vspans)])
    # (each pair's row among the vertices: numpy's gather, the same values as a compiled one, one cache load less)
    return tri, tcell, pvert, starts, verts, index[pvert].astype(np.int64)
