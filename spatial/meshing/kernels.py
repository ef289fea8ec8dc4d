"""Compiled kernels of the plain marching-cubes path: per-slab bookkeeping and the merge of blocks.

Module-level ``@njit(cache=True)`` functions (stable cache keys, compiled once per machine), each
doing in one pass what the numpy version did in several whole-array passes and temporaries.
Every kernel computes exactly what the numpy code it replaces computed (the meshes are pinned,
`tests/meshing/test_mesh_digest.py`).
"""

from __future__ import annotations

import numba
import numpy as np


__all__ = []

#: Axis code of a vertex inside a cube (the same as `blocks.INTERIOR`).
_INTERIOR = 3


@numba.njit(cache=True, nogil=True)
def take_block(verts, tri, values, b, xs, ys, zs, B, gx, gy, gz, stride, node, axis, f0, f1, shared, edge,
               faces, vat, fat, eat):
    """Append one block's marching-cubes output to the slab's buffers; returns the new fill counts.

    `verts` (n, 3) float32 and `tri` (3 f,) int32 come straight from scikit-image's Cython
    kernel: vertex columns in reversed axis order, triangles wound for ``ascent`` (reversed here
    for ``descent``).  ``(xs, ys, zs)`` is the corner of the block's box inside the block,
    ``(gx, gy, gz)`` the block's global lower node.  Each vertex gets the lower node of its
    lattice edge and the axis (`_INTERIOR` for Lewiner's vertex inside a cube: the cube's lower
    node), the samples at the edge's ends (`f1 = f0` inside a cube), whether it lies on an edge
    in a block face (then its global edge id ``3 * node + axis`` is appended to `edge`).
    """
    n = verts.shape[0]
    for i in range(n):
        # skimage's columns reversed: c0 is axis 0
        c0 = np.float64(verts[i, 2])
        c1 = np.float64(verts[i, 1])
        c2 = np.float64(verts[i, 0])
        r0, r1, r2 = np.rint(c0), np.rint(c1), np.rint(c2)
        d0, d1, d2 = abs(c0 - r0), abs(c1 - r1), abs(c2 - r2)
        offs = (c0 != r0) + (c1 != r1) + (c2 != r2)
        # np.argmax: the first of equal maxima
        ax = 0
        if d1 > d0:
            ax = 1
        if d2 > max(d0, d1):
            ax = 2
        if offs > 1:
            lx, ly, lz = np.int64(np.floor(c0)), np.int64(np.floor(c1)), np.int64(np.floor(c2))
            ax = _INTERIOR
        else:
            lx, ly, lz = np.int64(r0), np.int64(r1), np.int64(r2)
            if ax == 0:
                lx = np.int64(np.floor(c0))
            elif ax == 1:
                ly = np.int64(np.floor(c1))
            else:
                lz = np.int64(np.floor(c2))
        lx += xs
        ly += ys
        lz += zs
        j = vat + i
        node[j, 0] = lx + gx
        node[j, 1] = ly + gy
        node[j, 2] = lz + gz
        axis[j] = ax
        a = values[b, lx, ly, lz]
        f0[j] = a
        if ax == 0:
            f1[j] = values[b, lx + 1, ly, lz]
        elif ax == 1:
            f1[j] = values[b, lx, ly + 1, lz]
        elif ax == 2:
            f1[j] = values[b, lx, ly, lz + 1]
        else:
            f1[j] = a
        sh = False
        if ax != _INTERIOR:
            if ax != 0 and (lx == 0 or lx == B):
                sh = True
            if ax != 1 and (ly == 0 or ly == B):
                sh = True
            if ax != 2 and (lz == 0 or lz == B):
                sh = True
        shared[j] = sh
        if sh:
            edge[eat] = (((lx + gx) * stride + (ly + gy)) * stride + (lz + gz)) * 3 + ax
            eat += 1
    nf = tri.shape[0] // 3
    for f in range(nf):
        faces[fat + f, 0] = tri[3 * f + 2] + vat
        faces[fat + f, 1] = tri[3 * f + 1] + vat
        faces[fat + f, 2] = tri[3 * f] + vat
    return vat + n, fat + nf, eat


@numba.njit(cache=True, nogil=True)
def part_index(shared, inverse, shared_at, private_at, n_private, index):
    """Merged vertex of each of a part's vertices: its own slot among the private ones (in order
    from `private_at`), or ``n_private + inverse`` for one shared by blocks."""
    p = private_at
    s = shared_at
    for i in range(shared.shape[0]):
        if shared[i]:
            index[i] = n_private + inverse[s]
            s += 1
        else:
            index[i] = p
            p += 1


@numba.njit(cache=True, nogil=True)
def remap_faces(index, pfaces, faces, row):
    """``faces[row:row + k] = index[pfaces]``."""
    for f in range(pfaces.shape[0]):
        for k in range(3):
            faces[row + f, k] = index[pfaces[f, k]]


def scatter_rows(out, index, arr):
    """``out[index] = arr`` along the first axis; for a vertex found in two blocks both write the
    same data."""
    if arr.ndim == 1:
        _scatter_1d(out, index, arr)
    elif arr.ndim == 2:
        _scatter_2d(out, index, arr)
    else:
        out[index] = arr


@numba.njit(cache=True, nogil=True)
def _scatter_1d(out, index, arr):
    for i in range(arr.shape[0]):
        out[index[i]] = arr[i]


@numba.njit(cache=True, nogil=True)
def _scatter_2d(out, index, arr):
    for i in range(arr.shape[0]):
        j = index[i]
        for k in range(arr.shape[1]):
            out[j, k] = arr[i, k]


@numba.njit(cache=True, nogil=True)
def crossing_ends(sgn, flat, s_n, v_n, B, out):
    """Needed nodes that end an edge of the blocks crossed by the surface (signs of opposite
    strict signs) and still have no value, into `out` (as many as `flat`, every entry written).

    `sgn` is the slab's dense int8 scratch array, ``(nb, B+1, B+1, B+1)`` flattened: it is
    cleared and given the signs `s_n` of the needed nodes `flat` (sorted; 0 elsewhere).  The
    nodes are walked row by row (a row: fixed block, x and y), so their coordinates come without
    divisions.
    """
    n1 = B + 1
    sgn[:] = 0
    for i in range(flat.shape[0]):
        sgn[flat[i]] = s_n[i]
    out[:] = False
    nb = sgn.shape[0] // (n1 * n1 * n1)
    sx = n1 * n1
    i = 0
    m = flat.shape[0]
    for row in range(nb * n1 * n1):
        if i >= m:
            break
        start = row * n1
        if flat[i] >= start + n1:
            continue
        y = row % n1
        x = (row // n1) % n1
        while i < m and flat[i] < start + n1:
            q = flat[i]
            s = sgn[q]
            if s != 0 and np.isnan(v_n[i]):
                z = q - start
                hit = False
                if z > 0 and sgn[q - 1] * s < 0:
                    hit = True
                elif z < B and sgn[q + 1] * s < 0:
                    hit = True
                elif y > 0 and sgn[q - n1] * s < 0:
                    hit = True
                elif y < B and sgn[q + n1] * s < 0:
                    hit = True
                elif x > 0 and sgn[q - sx] * s < 0:
                    hit = True
                elif x < B and sgn[q + sx] * s < 0:
                    hit = True
                out[i] = hit
            i += 1


@numba.njit(cache=True, nogil=True)
def fill_values(values, flat, v_n, s_n, scale):
    """The slab's dense samples for marching cubes, in place: 1 at unused nodes, the value at
    sampled ones, ``sign * scale`` where only the sign is known."""
    values[:] = np.float32(1.0)
    for i in range(flat.shape[0]):
        v = v_n[i]
        if np.isnan(v):
            v = np.float32(s_n[i]) * scale
        values[flat[i]] = v


@numba.njit(cache=True, nogil=True)
def ring_to_nodes(state, ry0, rz0, P, out):
    """Node codes of every block from the cell states of its ring, ``out (nb, 2P+1, 2P+1, 2P+1)``.

    Block ``b``'s ring is ``state[0:P+2, ry0[b]:ry0[b]+P+2, rz0[b]:rz0[b]+P+2]`` (cells -1 .. P
    along each axis); node ``j`` along an axis lies in ring cells ``(j+1)//2`` and ``(j+2)//2``,
    and takes the OR of the codes of all the ring cells holding it, one axis at a time.
    """
    n1 = 2 * P + 1
    r = P + 2
    tz = np.empty((r, r, n1), np.uint8)
    ty = np.empty((r, n1, n1), np.uint8)
    for b in range(out.shape[0]):
        y0 = ry0[b]
        z0 = rz0[b]
        for i in range(r):
            for j in range(r):
                for k in range(n1):
                    tz[i, j, k] = state[i, y0 + j, z0 + (k + 1) // 2] | state[i, y0 + j, z0 + (k + 2) // 2]
        for i in range(r):
            for j in range(n1):
                ja = (j + 1) // 2
                jb = (j + 2) // 2
                for k in range(n1):
                    ty[i, j, k] = tz[i, ja, k] | tz[i, jb, k]
        for i in range(n1):
            ia = (i + 1) // 2
            ib = (i + 2) // 2
            for j in range(n1):
                for k in range(n1):
                    out[b, i, j, k] = ty[ia, j, k] | ty[ib, j, k]


@numba.njit(cache=True, nogil=True)
def edge_points(nodes, axis, origin, h, rows, active, t, q):
    """``q[m] = origin + (nodes[r] + t[i] e_axis[r]) h`` for ``i = active[m]``, ``r = rows[i]``
    (the point at parameter `t` along each active vertex's edge)."""
    for m in range(active.shape[0]):
        i = active[m]
        r = rows[i]
        for k in range(3):
            q[m, k] = nodes[r, k] * h + origin[k]
        q[m, axis[r]] += t[i] * h


@numba.njit(cache=True, nogil=True)
def illinois_step(active, ft, t, a, b, fa, fb, side, step, tol_h, accept_h):
    """One Illinois regula-falsi update of the active vertices from their values `ft`, in place;
    returns the vertices still active (value above `accept_h`).

    A vertex with ``|f| <= tol_h`` keeps its parameter; one with ``|f| <= accept_h`` takes this
    last update and stops.
    """
    keep = np.empty(active.shape[0], np.int64)
    n = 0
    for m in range(active.shape[0]):
        f = ft[m]
        if not abs(f) > tol_h:
            continue
        i = active[m]
        ta = t[i]
        left = (f > 0) == (fa[i] > 0)
        if left:
            aa, ba, nfa, nfb = ta, b[i], f, fb[i]
        else:
            aa, ba, nfa, nfb = a[i], ta, fa[i], f
        if step:  # Illinois: halve the value of an end kept twice in a row
            if left and side[i] == 1:
                nfb = 0.5 * nfb
            if not left and side[i] == -1:
                nfa = 0.5 * nfa
        denom = nfb - nfa
        if denom != 0:
            tn = (aa * nfb - ba * nfa) / denom
        else:
            tn = 0.5 * (aa + ba)
        t[i] = min(max(tn, aa), ba)
        a[i], b[i], fa[i], fb[i] = aa, ba, nfa, nfb
        side[i] = 1 if left else -1
        if abs(f) > accept_h:
            keep[n] = i
            n += 1
    return keep[:n]


@numba.njit(cache=True, nogil=True)
def block_boxes(inv, lx, ly, lz, nb, P):
    """Per block, the box ``[lows, highs)`` (cell units, block-local) of its cells ``(lx, ly, lz)``
    (block `inv`); ``(P, P, P)`` / ``(0, 0, 0)`` for a block without cells."""
    lows = np.full((nb, 3), P, np.int64)
    highs = np.zeros((nb, 3), np.int64)
    for i in range(inv.shape[0]):
        b = inv[i]
        lows[b, 0] = min(lows[b, 0], lx[i])
        lows[b, 1] = min(lows[b, 1], ly[i])
        lows[b, 2] = min(lows[b, 2], lz[i])
        highs[b, 0] = max(highs[b, 0], lx[i] + 1)
        highs[b, 1] = max(highs[b, 1], ly[i] + 1)
        highs[b, 2] = max(highs[b, 2], lz[i] + 1)
    return lows, highs


@numba.njit(cache=True, nogil=True)
def place_rows(nodes, axis, t, h, origin, p, a, b):
    """Positions ``origin + nodes * h`` of the vertices ``a .. b-1`` moved ``t * h`` along their edge's axis, into the rows of `p`."""
    for i in range(a, b):
        for k in range(3):
            p[i, k] = nodes[i, k] * h + origin[k]
        p[i, axis[i]] += t[i] * h


@numba.njit(cache=True, nogil=True, inline="always")
def _block_node(q, n1):
    """Block and node ``(b, x, y, z)`` of the flat position `q` in the blocks' ``(B+1)^3`` arrays."""
    b = q // (n1 * n1 * n1)
    r = q - b * (n1 * n1 * n1)
    x = r // (n1 * n1)
    r -= x * (n1 * n1)
    y = r // n1
    return b, x, y, r - y * n1


@numba.njit(cache=True, nogil=True)
def node_points(flat, rows, B, x0, ybase, zbase, origin, h):
    """Positions of the slab's needed nodes ``flat[rows]`` (flat positions in the blocks' arrays;
    block `b` starts at global node ``(x0, ybase[b], zbase[b])``)."""
    n1 = B + 1
    pts = np.empty((rows.shape[0], 3))
    for m in range(rows.shape[0]):
        b, x, y, z = _block_node(np.int64(flat[rows[m]]), n1)
        pts[m, 0] = origin[0] + (x + x0) * h
        pts[m, 1] = origin[1] + (ybase[b] + y) * h
        pts[m, 2] = origin[2] + (zbase[b] + z) * h
    return pts


@numba.njit(cache=True, nogil=True)
def node_ids(flat, rows, B, x0, ybase, zbase, stride):
    """Global ids ``(x * stride + y) * stride + z`` of the slab's needed nodes ``flat[rows]``."""
    n1 = B + 1
    out = np.empty(rows.shape[0], np.int64)
    for m in range(rows.shape[0]):
        b, x, y, z = _block_node(np.int64(flat[rows[m]]), n1)
        out[m] = ((x + x0) * stride + (ybase[b] + y)) * stride + (zbase[b] + z)
    return out


@numba.njit(cache=True, nogil=True)
def block_input(values, cells, b, xs, ys, zs, nx, ny, nz, c, vol, mask, with_values):
    """One block's box for marching cubes, written into the flat scratch arrays `vol` / `mask`
    (their first ``(nx+1)(ny+1)(nz+1)`` entries, every one of them written).

    ``vol`` holds ``values[b, xs:xs+nx+1, ys:ys+ny+1, zs:zs+nz+1]`` (left alone unless
    `with_values`); ``mask[i+1, j+1, k+1]`` is the cell (of `c` voxels) holding voxel ``(xs+i,
    ys+j, zs+k)``, the lower planes False (scikit-image's convention for the voxel with lower node
    ``(i, j, k)``).  A mask row (or plane) whose voxels lie in the same cells as the previous
    one's is a copy of it: of every `c` rows one is read from the cells.
    """
    my = ny + 1
    mz = nz + 1
    plane = my * mz
    if with_values:
        n1 = values.shape[3]
        src = values.reshape(-1)   # flat offsets: no view made per row
        for i in range(nx + 1):
            for j in range(my):
                row = (i * my + j) * mz
                at = ((b * values.shape[1] + xs + i) * values.shape[2] + ys + j) * n1 + zs
                for k in range(mz):
                    vol[row + k] = src[at + k]
    for k in range(plane):
        mask[k] = False
    for i in range(1, nx + 1):
        base = i * plane
        ci = (xs + i - 1) // c
        if i > 1 and (xs + i - 2) // c == ci:
            for k in range(plane):
                mask[base + k] = mask[base - plane + k]
            continue
        for k in range(mz):
            mask[base + k] = False
        for j in range(1, my):
            row = base + j * mz
            cj = (ys + j - 1) // c
            if j > 1 and (ys + j - 2) // c == cj:
                for k in range(mz):
                    mask[row + k] = mask[row - mz + k]
                continue
            held = cells[b, ci, cj]
            mask[row] = False
            if c == 2:
                for k in range(1, mz):
                    mask[row + k] = held[(zs + k - 1) >> 1]
            else:
                for k in range(1, mz):
                    mask[row + k] = held[(zs + k - 1) // c]


@numba.njit(cache=True, nogil=True)
def count_needed(code):
    """How many nodes of the slab's flat node codes have bit 0 (`NEEDED`) set."""
    n = 0
    for q in range(code.shape[0]):
        n += code[q] & 1
    return n


@numba.njit(cache=True, nogil=True)
def needed_nodes(code, B, flat, s_n, maybe, upper):
    """The needed nodes of the slab's flat node codes in one pass, into arrays sized by `count_needed`.

    ``flat``: their flat positions (increasing); ``s_n``: the sign the code's bits give
    (``POSITIVE`` bit 1, ``NEGATIVE`` bit 2; 0 when unknown); ``maybe``: whether another block
    may hold the node too (on a y/z face of its block or on its lower x plane); ``upper``:
    whether it lies on the block's upper x plane (handed to the next slab).
    """
    n1 = B + 1
    nb = code.shape[0] // (n1 * n1 * n1)
    m = 0
    q = 0
    # nested loops instead of dividing each position back into (x, y, z): y % B == 0 is y in (0, B)
    for _ in range(nb):
        for x in range(n1):
            for y in range(n1):
                y_face = y == 0 or y == B
                for z in range(n1):
                    c = code[q]
                    if c & 1:
                        flat[m] = q
                        s_n[m] = ((c >> 1) & 1) - ((c >> 2) & 1)
                        maybe[m] = y_face or z == 0 or z == B or x == 0
                        upper[m] = x == B
                        m += 1
                    q += 1


@numba.njit(cache=True, nogil=True)
def index_positions(flat, where):
    """``where[flat[i]] = i``: each needed node's row at its flat position (the other entries of
    `where` are left as they were: read them only through `put_sampled`'s check)."""
    for i in range(flat.shape[0]):
        where[flat[i]] = i


@numba.njit(cache=True, nogil=True)
def put_sampled(flat, where, b_, x_, y_, z_, v, n1, v_n):
    """``v_n[i] = v[j]`` for every sampled node ``j`` (block `b_`, position ``x_, y_, z_``) that is
    needed node ``i``: its flat position found through `where` (`index_positions`) and checked
    against `flat` (so stale entries of `where` are never taken), in the order of the samples."""
    n = flat.shape[0]
    for j in range(v.shape[0]):
        q = ((np.int64(b_[j]) * n1 + x_[j]) * n1 + y_[j]) * n1 + z_[j]
        i = where[q]
        if 0 <= i < n and flat[i] == q:
            v_n[i] = v[j]


@numba.njit(cache=True, nogil=True)
def paint_parents(state, idx, sgn, x0, y0, z0, negative, positive):
    """OR the sign of uniform cells twice as large (`idx`, `sgn`) into the cell states over their
    eight children, ``state[child - (x0, y0, z0)]``, those inside `state` only (one pass over the
    cells instead of painting them at their own scale and repeating the array along each axis)."""
    s0, s1, s2 = state.shape
    for i in range(idx.shape[0]):
        g = negative if sgn[i] < 0 else positive
        bx = 2 * np.int64(idx[i, 0]) - x0
        by = 2 * np.int64(idx[i, 1]) - y0
        bz = 2 * np.int64(idx[i, 2]) - z0
        for x in range(max(bx, 0), min(bx + 2, s0)):
            for y in range(max(by, 0), min(by + 2, s1)):
                for z in range(max(bz, 0), min(bz + 2, s2)):
                    state[x, y, z] |= g


# -- the per-block steps of the meshing thread, holding the interpreter's lock ------------------
# The slab loop runs scikit-image's marching cubes (which holds the lock) block after block while a
# second thread prepares the next slab.  A kernel that lets the lock go for a few microseconds costs
# the meshing thread a wait for it afterwards -- the preparing thread takes it and keeps it up to a
# switch interval -- once or more per block; these wrappers run the same compiled loops without
# letting it go.

@numba.njit(cache=True)
def block_mask_held(values, cells, b, xs, ys, zs, nx, ny, nz, c, mask):
    """`block_input`'s mask of block `b`'s box (no values copied), keeping the interpreter's lock."""
    block_input(values, cells, b, xs, ys, zs, nx, ny, nz, c, values.reshape(-1)[:0], mask, False)


@numba.njit(cache=True)
def take_block_held(verts, tri, values, b, xs, ys, zs, B, gx, gy, gz, stride, node, axis, f0, f1, shared,
                    edge, faces, vat, fat, eat):
    """`take_block`, keeping the interpreter's lock."""
    return take_block(verts, tri, values, b, xs, ys, zs, B, gx, gy, gz, stride, node, axis, f0, f1, shared,
                      edge, faces, vat, fat, eat)
