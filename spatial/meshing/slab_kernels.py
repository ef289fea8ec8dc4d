"""Compiled steps of a slab's sampling (`slab._SlabJob.prepare`), a few long calls between its evaluations.

A slab is prepared on a second thread while the meshing thread runs scikit-image's marching cubes,
which holds the interpreter's lock.  Every return from a compiled call or numpy operation that let
the lock go is a wait for it (up to a switch interval, plus the rest of a marching-cubes call): the
preparation's bookkeeping was a few dozen such steps per slab.  Here it is a few calls, each between
two of the slab's evaluations: `slab_blocks` (the active blocks), `slab_codes` (the node codes from
the ring and the samples' signs), `slab_needed` (the needed nodes and their known values),
`merged_nodes` (the nodes two blocks share, by id, and the previous slab's handoff), `first_pass`
and `second_pass` (each pass's nodes and the scatter of the values before), `slab_samples` (the
dense samples and the handoff of the upper plane) and `blocks_with_ties` (the blocks whose boxes
hold a tie of marching cubes, so that the meshing thread looks for ties only there).  The node and
edge ids are sorted by a radix sort (`stable_argsort`), a pass's values nudged off the level in
one pass (`nudged_float32`).

Module-level ``@njit(cache=True, nogil=True)`` functions; every result equals the numpy
expression it replaces, bit for bit (`np.unique` through a stable sort: its first indices are the
first occurrences, as numpy's own ``mergesort``).
"""

from __future__ import annotations

import numba
import numpy as np

from .kernels import (crossing_ends, fill_values, index_positions, needed_nodes, node_ids, node_points,
                      paint_parents, put_sampled, ring_to_nodes)

__all__ = []


#: Bits of the key sorted per pass of `stable_argsort` (256 buckets: their write positions stay in cache).
_RADIX_BITS = 8


@numba.njit(cache=True, nogil=True, inline="always")
def _left(sorted_keys, key):
    """``np.searchsorted(sorted_keys, key)`` (left side) by bisection: numba's own searchsorted lives in
    ``numba.np.arraymath``, whose load imports scipy.linalg for its BLAS check."""
    lo, hi = 0, sorted_keys.shape[0]
    while lo < hi:
        mid = (lo + hi) >> 1
        if sorted_keys[mid] < key:
            lo = mid + 1
        else:
            hi = mid
    return lo


@numba.njit(cache=True, nogil=True)
def stable_argsort(keys):
    """``np.argsort(keys, kind="stable")`` of non-negative int64 keys: a least-significant-digit radix
    sort, `_RADIX_BITS` bits per pass, as many passes as the largest key needs, the keys carried along
    with the permutation (no gather through it).  Each pass is a stable counting sort, so the
    permutation is the stable one, the same as numpy's; four to five times faster on the lattice's
    node and edge ids."""
    n = keys.shape[0]
    order = np.arange(n)
    if n < 2:
        return order
    top = keys[0]
    for i in range(n):
        top = max(top, keys[i])
    width = 1 << _RADIX_BITS
    mask = width - 1
    cur = keys.copy()
    nxt = np.empty(n, np.int64)
    other = np.empty(n, np.int64)
    count = np.empty(width + 1, np.int64)
    shift = 0
    while shift == 0 or (top >> shift) > 0:
        count[:] = 0
        for i in range(n):
            count[((cur[i] >> shift) & mask) + 1] += 1
        for d in range(width):
            count[d + 1] += count[d]
        for i in range(n):
            d = (cur[i] >> shift) & mask
            p = count[d]
            nxt[p] = cur[i]
            other[p] = order[i]
            count[d] = p + 1
        cur, nxt = nxt, cur
        order, other = other, order
        shift += _RADIX_BITS
    return order


@numba.njit(cache=True, nogil=True)
def _unique_first(ids):
    """``np.unique(ids, return_index=True, return_inverse=True)``: sorted ids, the row of each one's
    first occurrence, and each row's slot among them (ids non-negative)."""
    n = ids.shape[0]
    order = stable_argsort(ids)
    nu = 0
    for t in range(n):
        if t == 0 or ids[order[t]] != ids[order[t - 1]]:
            nu += 1
    uniq = np.empty(nu, np.int64)
    first = np.empty(nu, np.int64)
    back = np.empty(n, np.int64)
    u = -1
    for t in range(n):
        o = order[t]
        if t == 0 or ids[o] != ids[order[t - 1]]:
            u += 1
            uniq[u] = ids[o]
            first[u] = o
        back[o] = u
    return uniq, first, back


@numba.njit(cache=True, nogil=True)
def nudged_float32(vals, eps, tie):
    """``(arrays._nudge(vals, h).astype(np.float32), True)`` in one pass when no value is a tie
    (``|v| <= tie``), else ``(empty, False)``: the caller then settles the ties first
    (`arrays._settle_ties`).  `eps` is ``ZERO_NUDGE * h``, `tie` ``ZERO_TIE * h``."""
    n = vals.shape[0]
    for i in range(n):
        if abs(vals[i]) <= tie:
            return np.empty(0, np.float32), False
    out = np.empty(n, np.float32)
    for i in range(n):
        v = vals[i]
        if not abs(v) >= eps:   # (NaN too: a field undefined there is pushed outside)
            v = -eps if v < 0 else eps
        out[i] = np.float32(v)
    return out, True


@numba.njit(cache=True, nogil=True)
def unique_inverse(keys):
    """``np.unique(keys, return_inverse=True)`` of non-negative int64 keys, by `stable_argsort` (the
    merge's shared edge ids: a radix sort in place of numpy's comparison sort)."""
    n = keys.shape[0]
    order = stable_argsort(keys)
    nu = 0
    for t in range(n):
        if t == 0 or keys[order[t]] != keys[order[t - 1]]:
            nu += 1
    uniq = np.empty(nu, np.int64)
    inverse = np.empty(n, np.int64)
    u = -1
    for t in range(n):
        o = order[t]
        if t == 0 or keys[o] != keys[order[t - 1]]:
            u += 1
            uniq[u] = keys[o]
        inverse[o] = u
    return uniq, inverse


@numba.njit(cache=True, nogil=True)
def _rows_where(mask):
    """``np.flatnonzero(mask)`` (int64)."""
    n = 0
    for i in range(mask.shape[0]):
        n += mask[i]
    out = np.empty(n, np.int64)
    j = 0
    for i in range(mask.shape[0]):
        if mask[i]:
            out[j] = i
            j += 1
    return out


# Bits of a node's code while a slab is sampled.
_NEEDED, _POSITIVE, _NEGATIVE = 1, 2, 4


@numba.njit(cache=True, nogil=True)
def slab_blocks(sc, slab, P, nbz):
    """The slab's active blocks from its cells `sc` (lattice units of cells, ``P`` per block side).

    Returns ``(keys, inv, lx, ly, lz, cells)``: the blocks' keys ``by * nbz + bz`` in increasing
    order, each cell's block and its position in it, and the blocks' ``(nb, P, P, P)`` cell
    occupancy.  The keys are few (``nbz**2``): found by counting, not sorting.
    """
    n = sc.shape[0]
    present = np.zeros(nbz * nbz, np.bool_)
    for i in range(n):
        present[(sc[i, 1] // P) * nbz + sc[i, 2] // P] = True
    rank = np.empty(nbz * nbz, np.int64)
    nb = 0
    for k in range(nbz * nbz):
        rank[k] = nb
        nb += present[k]
    keys = np.empty(nb, np.int64)
    for k in range(nbz * nbz):
        if present[k]:
            keys[rank[k]] = k
    inv = np.empty(n, np.int64)
    lx = np.empty(n, np.int64)
    ly = np.empty(n, np.int64)
    lz = np.empty(n, np.int64)
    cells = np.zeros((nb, P, P, P), np.bool_)
    for i in range(n):
        by = sc[i, 1] // P
        bz = sc[i, 2] // P
        b = rank[by * nbz + bz]
        inv[i] = b
        lx[i] = sc[i, 0] - slab * P
        ly[i] = sc[i, 1] - by * P
        lz[i] = sc[i, 2] - bz * P
        cells[b, lx[i], ly[i], lz[i]] = True
    return keys, inv, lx, ly, lz, cells


@numba.njit(cache=True, nogil=True, inline="always")
def _known_sign(flat, base, v, infer, steps, thresholds):
    """OR the sign bit of a sampled node's value `v` into its code (flat position `base`) and, with
    `infer`, into those of the neighbours it is farther from the level than (the Lipschitz bound to each
    neighbour, ``abs(v) > thresholds[o]``)."""
    g = np.uint8(_NEGATIVE) if v < 0 else np.uint8(_POSITIVE)
    if infer:
        m = abs(v)
        for o in range(steps.shape[0]):
            if m > thresholds[o]:
                flat[base + steps[o]] |= g
    flat[base] |= g


@numba.njit(cache=True, nogil=True)
def slab_codes(sc, inv, lx, ly, lz, keys, nbz, slab, P, ring_idx, ring_sgn, par_idx, par_sgn, given, extra_idx,
               extra_val, infer, steps, thresholds, code):
    """What each node of the slab's blocks is known to be, into `code` ``(nb, 2P+1, 2P+1, 2P+1)``
    uint8 (cells of 2 voxels), and which sampled nodes lie in the blocks.

    Bit `_NEEDED` marks the nodes of boundary cells, `_POSITIVE` / `_NEGATIVE` a known sign: from a
    uniform cell of the ring ``(ring_idx, ring_sgn)`` holding the node (cells twice as large
    ``(par_idx, par_sgn)`` over their children first), the codes going from cells to nodes by an
    OR (`ring_to_nodes`); then from the samples at the cells' centres `given` (none when empty)
    and the sampled nodes ``(extra_idx, extra_val)`` strictly inside an active block, each with
    its neighbours when `infer` (`_known_sign`).  Returns the latter as ``(b, x, y, z, value)``
    block-local rows, and the number of needed nodes.
    """
    nb = keys.shape[0]
    B = 2 * P
    n1 = B + 1
    by_lo, by_hi = keys[0] // nbz, keys[0] // nbz
    bz_lo, bz_hi = keys[0] % nbz, keys[0] % nbz
    for k in range(nb):
        by_lo = min(by_lo, keys[k] // nbz)
        by_hi = max(by_hi, keys[k] // nbz)
        bz_lo = min(bz_lo, keys[k] % nbz)
        bz_hi = max(bz_hi, keys[k] % nbz)
    y0, y1 = by_lo * P - 1, (by_hi + 1) * P + 1
    z0, z1 = bz_lo * P - 1, (bz_hi + 1) * P + 1
    xc = slab * P - 1
    state = np.zeros((P + 2, y1 - y0, z1 - z0), np.uint8)
    if par_idx.shape[0]:
        paint_parents(state, par_idx, par_sgn, xc, y0, z0, np.uint8(_NEGATIVE), np.uint8(_POSITIVE))
    for i in range(ring_idx.shape[0]):
        y = np.int64(ring_idx[i, 1])
        z = np.int64(ring_idx[i, 2])
        if y0 <= y < y1 and z0 <= z < z1:
            state[np.int64(ring_idx[i, 0]) - xc, y - y0, z - z0] = _NEGATIVE if ring_sgn[i] < 0 else _POSITIVE
    for i in range(sc.shape[0]):
        state[sc[i, 0] - xc, sc[i, 1] - y0, sc[i, 2] - z0] = _NEEDED
    ry0 = np.empty(nb, np.int64)
    rz0 = np.empty(nb, np.int64)
    for k in range(nb):
        ry0[k] = (keys[k] // nbz) * P - 1 - y0
        rz0[k] = (keys[k] % nbz) * P - 1 - z0
    ring_to_nodes(state, ry0, rz0, P, code)
    flat = code.reshape(-1)
    for j in range(given.shape[0]):
        base = ((inv[j] * n1 + 2 * lx[j] + 1) * n1 + 2 * ly[j] + 1) * n1 + 2 * lz[j] + 1
        _known_sign(flat, base, given[j], infer, steps, thresholds)
    # the sampled nodes strictly inside an active block (never on a y/z block face)
    m = extra_idx.shape[0]
    hit = np.zeros(m, np.bool_)
    pos = np.empty(m, np.int64)
    k = 0
    for j in range(m):
        key = (extra_idx[j, 1] // B) * nbz + extra_idx[j, 2] // B
        p = min(_left(keys, key), nb - 1)
        pos[j] = p
        if keys[p] == key and extra_idx[j, 1] % B != 0 and extra_idx[j, 2] % B != 0:
            hit[j] = True
            k += 1
    eb = np.empty(k, np.int64)
    ex = np.empty(k, np.int64)
    ey = np.empty(k, np.int64)
    ez = np.empty(k, np.int64)
    ev = np.empty(k, extra_val.dtype)
    k = 0
    for j in range(m):
        if hit[j]:
            eb[k] = pos[j]
            ex[k] = extra_idx[j, 0] - slab * B
            ey[k] = extra_idx[j, 1] % B
            ez[k] = extra_idx[j, 2] % B
            ev[k] = extra_val[j]
            k += 1
    for j in range(k):
        _known_sign(flat, ((eb[j] * n1 + ex[j]) * n1 + ey[j]) * n1 + ez[j], ev[j], infer, steps, thresholds)
    n = 0
    for q in range(flat.shape[0]):
        n += flat[q] & 1
    return eb, ex, ey, ez, ev, n


@numba.njit(cache=True, nogil=True)
def slab_needed(code, B, flat, s_n, maybe, upper, inv, lx, ly, lz, given, eb, ex, ey, ez, ev, where, v_n):
    """The needed nodes of the slab's flat codes (`needed_nodes`, into arrays sized by `slab_codes`)
    and their values where already sampled -- at the cells' centres `given` (none when empty), then
    the nodes ``(eb, ex, ey, ez, ev)`` -- found through the flat scratch `where` (`put_sampled`):
    into ``v_n`` (as many as `flat`; NaN where not sampled, every entry written)."""
    needed_nodes(code, B, flat, s_n, maybe, upper)
    v_n[:] = np.nan
    if given.shape[0] or eb.shape[0]:
        index_positions(flat, where)
        if given.shape[0]:
            put_sampled(flat, where, inv, 2 * lx + 1, 2 * ly + 1, 2 * lz + 1, given, B + 1, v_n)
        if eb.shape[0]:
            put_sampled(flat, where, eb, ex, ey, ez, ev, B + 1, v_n)


@numba.njit(cache=True, nogil=True)
def merged_nodes(flat, maybe, s_n, B, x0, ybase, zbase, stride, pid, pval, psgn):
    """The needed nodes another block may hold too (`maybe`), merged by their global id.

    Returns ``(m_idx, ufirst, back, s_u, v_u)``: the rows of those nodes, the row (among them) of
    each unique node's first occurrence, each row's unique node, the unique nodes' signs (any
    known copy's; OR the previous slab's handoff ``(pid, pval, psgn)``) and values (the handoff's,
    else NaN).
    """
    m_idx = _rows_where(maybe)
    uniq, ufirst, back = _unique_first(node_ids(flat, m_idx, B, x0, ybase, zbase, stride))
    nu = uniq.shape[0]
    s_u = np.zeros(nu, np.int8)
    for t in range(m_idx.shape[0]):
        s = s_n[m_idx[t]]
        if s != 0:
            s_u[back[t]] = s
    v_u = np.full(nu, np.nan, np.float32)
    npid = pid.shape[0]
    if npid:
        for u in range(nu):
            pos = min(_left(pid, uniq[u]), npid - 1)
            if pid[pos] == uniq[u]:
                v_u[u] = pval[pos]
                s_u[u] |= psgn[pos]
    return m_idx, ufirst, back, s_u, v_u


@numba.njit(cache=True, nogil=True)
def _picked_points(flat, rows, ru, m_idx, ufirst, B, x0, ybase, zbase, origin, h):
    """Positions of the single nodes `rows` and then of the unique merged nodes `ru` (each at its
    first occurrence)."""
    pick = np.empty(rows.shape[0] + ru.shape[0], np.int64)
    pick[:rows.shape[0]] = rows
    for i in range(ru.shape[0]):
        pick[rows.shape[0] + i] = m_idx[ufirst[ru[i]]]
    return node_points(flat, pick, B, x0, ybase, zbase, origin, h)


@numba.njit(cache=True, nogil=True)
def first_pass(flat, maybe, s_n, m_idx, ufirst, s_u, B, x0, ybase, zbase, origin, h):
    """The nodes of pass 1 (no sign known): ``(single rows, unique merged nodes, their positions)``."""
    n = flat.shape[0]
    k = 0
    for i in range(n):
        if not maybe[i] and s_n[i] == 0:
            k += 1
    rows = np.empty(k, np.int64)
    k = 0
    for i in range(n):
        if not maybe[i] and s_n[i] == 0:
            rows[k] = i
            k += 1
    ru = _rows_where(s_u == 0)
    return rows, ru, _picked_points(flat, rows, ru, m_idx, ufirst, B, x0, ybase, zbase, origin, h)


@numba.njit(cache=True, nogil=True)
def second_pass(a, b, rows, ru, flat, maybe, s_n, v_n, m_idx, ufirst, back, s_u, v_u, code, B, x0, ybase, zbase,
                origin, h, w_n):
    """Pass 1's values `a` (single `rows`) and `b` (unique nodes `ru`) written with their signs and
    copied to every merged row; then the nodes of pass 2 -- the ends of crossing edges still without
    a value (`crossing_ends`, over the spent node codes `code`, into `w_n`: as many as `flat`) -- as
    ``(single rows, unique merged nodes, their positions)``."""
    for i in range(rows.shape[0]):
        v_n[rows[i]] = a[i]
        s_n[rows[i]] = -1 if a[i] < 0 else 1
    for i in range(ru.shape[0]):
        v_u[ru[i]] = b[i]
        s_u[ru[i]] = -1 if b[i] < 0 else 1
    for t in range(m_idx.shape[0]):
        s_n[m_idx[t]] = s_u[back[t]]
        v_n[m_idx[t]] = v_u[back[t]]
    crossing_ends(code, flat, s_n, v_n, B, w_n)
    w_u = np.zeros(s_u.shape[0], np.bool_)
    for t in range(m_idx.shape[0]):
        if w_n[m_idx[t]]:
            w_u[back[t]] = True
    for i in range(w_n.shape[0]):
        if maybe[i]:
            w_n[i] = False
    rows2 = _rows_where(w_n)
    ru2 = _rows_where(w_u)
    return rows2, ru2, _picked_points(flat, rows2, ru2, m_idx, ufirst, B, x0, ybase, zbase, origin, h)


@numba.njit(cache=True, nogil=True)
def slab_samples(a, b, rows, ru, flat, v_n, s_n, m_idx, back, v_u, values, scale, upper, B, x0, ybase, zbase,
                 stride):
    """Pass 2's values written and copied to every merged row, the slab's dense samples filled
    (`fill_values`), and the handoff of its upper plane: ``(sorted unique ids, values, signs)``
    of the nodes `upper` marks (each id's first occurrence)."""
    for i in range(rows.shape[0]):
        v_n[rows[i]] = a[i]
    for i in range(ru.shape[0]):
        v_u[ru[i]] = b[i]
    for t in range(m_idx.shape[0]):
        v_n[m_idx[t]] = v_u[back[t]]
    fill_values(values, flat, v_n, s_n, scale)
    top = _rows_where(upper)
    hid, first, _ = _unique_first(node_ids(flat, top, B, x0, ybase, zbase, stride))
    hval = np.empty(hid.shape[0], np.float32)
    hsgn = np.empty(hid.shape[0], np.int8)
    for u in range(hid.shape[0]):
        hval[u] = v_n[top[first[u]]]
        hsgn[u] = s_n[top[first[u]]]
    return hid, hval, hsgn


# -- the blocks holding a tie of marching cubes (`saddles`) ---------------------------------------

@numba.njit(cache=True, nogil=True, inline="always")
def _face_tie(a, b, c, d):
    """Whether the face with corners a, b, c, d in order is a tie of `saddles` (its diagonal pattern,
    the products of its diagonals' values equal)."""
    if (a < 0) != (c < 0) or (b < 0) != (d < 0) or (a < 0) == (b < 0):
        return False
    return np.float64(a) * np.float64(c) == np.float64(b) * np.float64(d)


@numba.njit(cache=True, nogil=True)
def _sign_rows(v, i, rows):
    """``rows[j]``: bit ``k`` set where ``v[i, j, k] < 0`` (a row of at most 64 nodes)."""
    for j in range(v.shape[1]):
        r = np.uint64(0)
        for k in range(v.shape[2]):
            if v[i, j, k] < 0:
                r |= np.uint64(1) << np.uint64(k)
        rows[j] = r


@numba.njit(cache=True, nogil=True, inline="always")
def _cube_tie(v, i, j, k):
    """Whether `saddles`' tie finder marks a corner of cube ``(i, j, k)``: a face at a tie, or (two
    opposite corners inside, all eight equally far) the tie of the interior test."""
    i1, j1, k1 = i + 1, j + 1, k + 1
    neg = 0
    for di in range(2):
        for dj in range(2):
            for dk in range(2):
                neg += v[i + di, j + dj, k + dk] < 0
    if neg < 2 or neg > 6:
        return False
    for z in (k, k1):
        if _face_tie(v[i, j, z], v[i1, j, z], v[i1, j1, z], v[i, j1, z]):
            return True
    for y in (j, j1):
        if _face_tie(v[i, y, k], v[i1, y, k], v[i1, y, k1], v[i, y, k1]):
            return True
    for x in (i, i1):
        if _face_tie(v[x, j, k], v[x, j1, k], v[x, j1, k1], v[x, j, k1]):
            return True
    if neg != 2:
        return False
    mag = abs(v[i, j, k])
    for di in range(2):
        for dj in range(2):
            for dk in range(2):
                if abs(v[i + di, j + dj, k + dk]) != mag:
                    return False
    for di in range(2):
        for dj in range(2):
            for dk in range(2):
                if v[i + di, j + dj, k + dk] < 0 and v[i1 - di, j1 - dj, k1 - dk] < 0:
                    return True
    return False


@numba.njit(cache=True, nogil=True)
def has_tie(v):
    """Whether `saddles`' tie finder marks anything in the box `v`: the same cubes tested
    (`_cube_tie`), those of one sign skipped by the sign bits of their rows (rows of at most 64
    nodes; longer rows test every cube)."""
    nx, ny, nz = v.shape
    if nz > 64:
        for i in range(nx - 1):
            for j in range(ny - 1):
                for k in range(nz - 1):
                    if _cube_tie(v, i, j, k):
                        return True
        return False
    lower = np.empty(ny, np.uint64)
    upper = np.empty(ny, np.uint64)
    one = np.uint64(1)
    cubes = (one << np.uint64(nz - 1)) - one
    _sign_rows(v, 0, lower)
    for i in range(nx - 1):
        _sign_rows(v, i + 1, upper)
        for j in range(ny - 1):
            every = lower[j] & lower[j + 1] & upper[j] & upper[j + 1]
            some = lower[j] | lower[j + 1] | upper[j] | upper[j + 1]
            # cube k is of one sign when its two z ends are: all inside, or none
            mixed = ~((every & (every >> one)) | (~some & (~some >> one))) & cubes
            k = 0
            while mixed:
                if mixed & one and _cube_tie(v, i, j, k):
                    return True
                mixed >>= one
                k += 1
        lower, upper = upper, lower
    return False


@numba.njit(cache=True, nogil=True)
def blocks_with_ties(values, lows, highs, c):
    """Which blocks' boxes ``values[b, lows*c : highs*c + 1]`` hold an exact tie of marching cubes
    (`has_tie`: what `saddles`' tie finder would mark there).

    Run where a slab is prepared, so that the meshing thread looks for ties (and deepens their
    corners, `saddles.break_ties_marked`) only in the few blocks that hold one.
    """
    nb = values.shape[0]
    out = np.zeros(nb, np.bool_)
    for b in range(nb):
        xs, ys, zs = lows[b, 0] * c, lows[b, 1] * c, lows[b, 2] * c
        nx, ny, nz = (highs[b, 0] - lows[b, 0]) * c, (highs[b, 1] - lows[b, 1]) * c, (highs[b, 2] - lows[b, 2]) * c
        if nx <= 0 or ny <= 0 or nz <= 0:
            continue
        out[b] = has_tie(values[b, xs:xs + nx + 1, ys:ys + ny + 1, zs:zs + nz + 1])
    return out
