"""Compiled passes of the sharp-feature rebuild (`spatial.meshing.features`) over the candidate cells
alone: the QEF, the cells' faces and patch borders, the Gauss-Newton step and the facing test of the
new triangles (the walks of every vertex and triangle are in `feature_cells`)."""

from __future__ import annotations

import numba
import numpy as np

@numba.njit(cache=True, nogil=True, inline="always")
def _faces_badly(points, a, b, c, normal, index, n, min_facing):
    """Whether triangle (a, b, c) is degenerate or does not face its ordinary vertices' exact normals
    (`_facing_kernel`'s test of one triangle)."""
    ux = points[b, 0] - points[a, 0]; uy = points[b, 1] - points[a, 1]; uz = points[b, 2] - points[a, 2]
    vx = points[c, 0] - points[a, 0]; vy = points[c, 1] - points[a, 1]; vz = points[c, 2] - points[a, 2]
    cx = uy * vz - uz * vy; cy = uz * vx - ux * vz; cz = ux * vy - uy * vx
    area2 = np.sqrt(cx * cx + cy * cy + cz * cz)
    wx = points[a, 0] - points[c, 0]; wy = points[a, 1] - points[c, 1]; wz = points[a, 2] - points[c, 2]
    zx = points[c, 0] - points[b, 0]; zy = points[c, 1] - points[b, 1]; zz = points[c, 2] - points[b, 2]
    scale = max(ux * ux + uy * uy + uz * uz, zx * zx + zy * zy + zz * zz, wx * wx + wy * wy + wz * wz)
    if area2 <= 1e-6 * scale:
        return True
    bad = False
    best = -np.inf
    for k in range(3):
        v = a if k == 0 else (b if k == 1 else c)
        if v < n:
            e = index[v]
            cos = (cx * normal[e, 0] + cy * normal[e, 1] + cz * normal[e, 2]) / area2
            if cos < -min_facing:
                bad = True
            if cos > best:
                best = cos
    return bad or best < min_facing


@numba.njit(cache=True, nogil=True)
def _facing_kernel(points, faces, normal, index, n, min_facing):
    """`features._facing_badly`; the exact normal of ordinary vertex ``v`` is ``normal[index[v]]``."""
    m = faces.shape[0]
    bad = np.zeros(m, np.bool_)
    for t in range(m):
        bad[t] = _faces_badly(points, faces[t, 0], faces[t, 1], faces[t, 2], normal, index, n, min_facing)
    return bad


@numba.njit(cache=True, nogil=True, inline="always")
def _eigh3(a, w, u):
    """Eigenvalues `w` (ascending) and eigenvectors (columns of `u`) of the symmetric 3x3 `a`, by cyclic
    Jacobi rotations (a few sweeps reach round-off; the QEF needs no more than LAPACK's accuracy)."""
    for i in range(3):
        for j in range(3):
            u[i, j] = 1.0 if i == j else 0.0
    for _ in range(12):
        off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
        scale = a[0, 0] * a[0, 0] + a[1, 1] * a[1, 1] + a[2, 2] * a[2, 2]
        if off <= 1e-34 * scale or off == 0.0:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                t = (1.0 if theta >= 0 else -1.0) / (abs(theta) + np.sqrt(theta * theta + 1.0))
                c = 1.0 / np.sqrt(t * t + 1.0)
                s = t * c
                for k in range(3):
                    akp, akq = a[k, p], a[k, q]
                    a[k, p] = c * akp - s * akq
                    a[k, q] = s * akp + c * akq
                for k in range(3):
                    apk, aqk = a[p, k], a[q, k]
                    a[p, k] = c * apk - s * aqk
                    a[q, k] = s * apk + c * aqk
                for k in range(3):
                    ukp, ukq = u[k, p], u[k, q]
                    u[k, p] = c * ukp - s * ukq
                    u[k, q] = s * ukp + c * ukq
    for i in range(3):
        w[i] = a[i, i]


@numba.njit(cache=True, nogil=True)
def _qef(pts, pvert, normal, pinv, starts, cutoff, open_cells, c0, c1, x, rank):
    """Per cell: the QEF minimiser around the mass point of its vertices, with its rank.

    ``sum (n_i . (x - p_i))^2`` over the cell's (vertex, exact normal) pairs is
    minimised relative to the mass point by the pseudo-inverse of ``A^T A``
    whose eigenvalues under ``cutoff`` times the largest are dropped (what is
    left is the rank: 2 an edge, 3 a corner).  Only the `open_cells` of cells
    `c0:c1` are solved, into their rows of `x` and `rank`; the others are
    given rank 0 and the point 0.
    """
    mass = np.empty(3)
    a = np.empty((3, 3))
    u = np.empty((3, 3))
    w = np.empty(3)
    b = np.empty(3)
    for c in range(c0, c1):
        for j in range(3):
            x[c, j] = 0.0
        rank[c] = 0
        if not open_cells[c]:
            continue
        s0, s1 = starts[c], starts[c + 1]
        mass[:] = 0.0
        for i in range(s0, s1):
            for j in range(3):
                mass[j] += pts[pvert[i], j]
        for j in range(3):
            mass[j] /= s1 - s0
        a[:, :] = 0.0
        b[:] = 0.0
        for i in range(s0, s1):
            v = pvert[i]
            e = pinv[i]
            d = 0.0
            for j in range(3):
                d += normal[e, j] * (pts[v, j] - mass[j])
            for j in range(3):
                b[j] += normal[e, j] * d
                for k in range(3):
                    a[j, k] += normal[e, j] * normal[e, k]
        _eigh3(a, w, u)
        top = max(w[0], w[1], w[2])
        for j in range(3):
            x[c, j] = mass[j]
        for k in range(3):
            if w[k] > cutoff * top:
                rank[c] += 1
                ub = (u[0, k] * b[0] + u[1, k] * b[1] + u[2, k] * b[2]) / w[k]
                for j in range(3):
                    x[c, j] += u[j, k] * ub


@numba.njit(cache=True, nogil=True)
def _cell_labels(pinv, decider, starts):
    """Per cell: its faces (the deciding facets of its vertices), most frequent first then by index;
    the first three as labels (-1 unused) and how many there are."""
    n_cells = starts.shape[0] - 1
    labels = np.full((n_cells, 3), -1, np.int64)
    n_faces = np.zeros(n_cells, np.int64)
    fc = np.empty(64, np.int64)
    cnt = np.empty(64, np.int64)
    for c in range(n_cells):
        k = 0
        s0, s1 = starts[c], starts[c + 1]
        if s1 - s0 > fc.shape[0]:
            fc = np.empty(2 * (s1 - s0), np.int64)
            cnt = np.empty(2 * (s1 - s0), np.int64)
        for i in range(s0, s1):
            f = decider[pinv[i]]
            found = False
            for j in range(k):
                if fc[j] == f:
                    cnt[j] += 1
                    found = True
                    break
            if not found:
                fc[k] = f
                cnt[k] = 1
                k += 1
        # order by count (descending), then face (ascending): insertion sort of k (a handful)
        for i in range(1, k):
            f, m = fc[i], cnt[i]
            j = i
            while j > 0 and (cnt[j - 1] < m or (cnt[j - 1] == m and fc[j - 1] > f)):
                fc[j] = fc[j - 1]
                cnt[j] = cnt[j - 1]
                j -= 1
            fc[j] = f
            cnt[j] = m
        n_faces[c] = k
        for j in range(min(k, 3)):
            labels[c, j] = fc[j]
    return labels, n_faces


@numba.njit(cache=True, nogil=True)
def _cell_borders(faces, tri, tcell, feature, n, t0, t1, disc):
    """Border edges of every feature cell's patch, and whether the patch is one disc.

    The triangles ``faces[tri]`` come grouped by cell (`tcell` sorted).  An edge met once
    among a cell's triangles is on its border; the patch is one disc when
    ``V - E + F == 1`` and it has as many border vertices as border edges
    (one simple loop), at least three.  The border edges of the disc cells
    are returned in the cell's order, then by undirected key ``min * n + max``
    (the order of a lexsort by cell and key), as directed in their triangle.
    Only the triangles `t0:t1` (whole cells) are read, and the rows of
    `disc` of their cells written.
    """
    m = t1 - t0
    b0 = np.empty(3 * m, np.int64)
    b1 = np.empty(3 * m, np.int64)
    bc = np.empty(3 * m, np.int64)
    e0 = np.empty(48, np.int64)
    e1 = np.empty(48, np.int64)
    ek = np.empty(48, np.int64)
    once = np.empty(48, np.bool_)
    vs = np.empty(48, np.int64)
    r = 0
    t = t0
    while t < t1:
        c = tcell[t]
        u = t
        while u < t1 and tcell[u] == c:
            u += 1
        k = u - t
        disc[c] = False
        if feature[c]:
            if 3 * k > e0.shape[0]:
                e0 = np.empty(6 * k, np.int64); e1 = np.empty(6 * k, np.int64); ek = np.empty(6 * k, np.int64)
                once = np.empty(6 * k, np.bool_); vs = np.empty(6 * k, np.int64)
            q = 0
            for i in range(t, u):
                for j in range(3):
                    a, b = np.int64(faces[tri[i], j]), np.int64(faces[tri[i], (j + 1) % 3])
                    e0[q] = a
                    e1[q] = b
                    ek[q] = min(a, b) * n + max(a, b)
                    q += 1
            n_e = 0
            n_b = 0
            for i in range(q):
                first = True
                dup = False
                for j in range(q):
                    if j != i and ek[j] == ek[i]:
                        dup = True
                        if j < i:
                            first = False
                once[i] = not dup
                n_e += first
                n_b += not dup
            # distinct vertices, and distinct first ends of border edges
            n_v = 0
            for i in range(q):
                new = True
                for j in range(n_v):
                    if vs[j] == e0[i]:
                        new = False
                        break
                if new:
                    vs[n_v] = e0[i]
                    n_v += 1
            n_bv = 0
            for i in range(q):
                if once[i]:
                    new = True
                    for j in range(i):
                        if once[j] and e0[j] == e0[i]:
                            new = False
                            break
                    n_bv += new
            if n_v - n_e + k == 1 and n_b == n_bv and n_b >= 3:
                disc[c] = True
                # the border edges by key (distinct within the cell: insertion sort of a handful)
                r0 = r
                for i in range(q):
                    if once[i]:
                        j = r
                        while j > r0 and ek[bc[j - 1]] > ek[i]:
                            bc[j] = bc[j - 1]
                            j -= 1
                        bc[j] = i
                        r += 1
                for j in range(r0, r):
                    i = bc[j]
                    b0[j] = e0[i]
                    b1[j] = e1[i]
                    bc[j] = c
        t = u
    return b0[:r].copy(), b1[:r].copy(), bc[:r].copy()


@numba.njit(cache=True, nogil=True)
def _newton_step(q, jac, val, used):
    """One Gauss-Newton step per row, in place: ``q -= J^T (J J^T)^-1 f`` over the `used` facets.

    ``J J^T`` (identity on the unused rows) is factored with partial
    pivoting; rows whose determinant is under 1e-12 do not move.
    """
    k = jac.shape[1]
    a = np.empty((k, k))
    y = np.empty(k)
    for r in range(q.shape[0]):
        for i in range(k):
            for j in range(k):
                if used[r, i] and used[r, j]:
                    a[i, j] = jac[r, i, 0] * jac[r, j, 0] + jac[r, i, 1] * jac[r, j, 1] + jac[r, i, 2] * jac[r, j, 2]
                else:
                    a[i, j] = 1.0 if i == j else 0.0
            y[i] = val[r, i]
        det = 1.0
        for c in range(k):
            p = c
            for i in range(c + 1, k):
                if abs(a[i, c]) > abs(a[p, c]):
                    p = i
            if p != c:
                det = -det
                for j in range(k):
                    a[c, j], a[p, j] = a[p, j], a[c, j]
                y[c], y[p] = y[p], y[c]
            det *= a[c, c]
            if a[c, c] == 0.0:
                break
            for i in range(c + 1, k):
                f = a[i, c] / a[c, c]
                for j in range(c, k):
                    a[i, j] -= f * a[c, j]
                y[i] -= f * y[c]
        if not abs(det) > 1e-12:
            continue
        for i in range(k - 1, -1, -1):
            for j in range(i + 1, k):
                y[i] -= a[i, j] * y[j]
            y[i] /= a[i, i]
        for i in range(k):
            if used[r, i]:
                for j in range(3):
                    q[r, j] -= jac[r, i, j] * y[i]


# -- the pass's stages, each one compiled function (one cache load each in a fresh process) ------
# (written without numba's array expressions and `np.unique`: loading a kernel that uses them imports
# numba's ufunc and list modules, some 0.03 s of a fresh process that the plain mesh never pays)

@numba.njit(cache=True, nogil=True)
def _cell_faces(pinv, decider, starts, smooth, need):
    """`_cell_labels`, and the cells that may hold an edge: all but those whose vertices all lie on one
    smooth facet (a sphere, a plane...: `implicit.facets.SMOOTH_KINDS`), however much the face turns
    across them.  `need` (one per distinct vertex, False on entry) is set at the vertices of those cells:
    the only ones whose exact normals the pass reads."""
    labels, n_faces = _cell_labels(pinv, decider, starts)
    n_cells = starts.shape[0] - 1
    open_cells = np.empty(n_cells, np.bool_)
    for c in range(n_cells):
        open_cells[c] = not (n_faces[c] == 1 and smooth[max(labels[c, 0], 0)])
        if open_cells[c]:
            for i in range(starts[c], starts[c + 1]):
                need[pinv[i]] = True
    return labels, n_faces, open_cells


@numba.njit(cache=True, nogil=True)
def _solve_cells(pts, faces, tri, tcell, pvert, normal, pinv, starts, open_cells, cutoff, c0, c1, x, rank, disc,
                 edge):
    """`_qef` of the open cells of `c0:c1` and the `_cell_borders` of those of rank 2 or more, in one call:
    their rows of `x`, `rank`, `disc` and `edge` (work) written, their border edges returned.  The cells
    are independent: chunks of cells give the one call's result (`feature_threads`)."""
    _qef(pts, pvert, normal, pinv, starts, cutoff, open_cells, c0, c1, x, rank)
    for c in range(c0, c1):
        edge[c] = rank[c] >= 2
    # the cells' triangles: `tcell` is sorted, so those of `c0:c1` are one run of it
    t0 = np.searchsorted(tcell, c0)
    t1 = np.searchsorted(tcell, c1)
    for c in range(c0, c1):
        disc[c] = False
    return _cell_borders(faces, tri, tcell, edge, pts.shape[0], t0, t1, disc)


@numba.njit(cache=True, nogil=True)
def _fan_rows(b0, b1, bc, feature, n, x, newp):
    """The fans of the `feature` cells over their border edges ``(b0, b1)`` (cell `bc`): the triangles
    ``(k, 3)``, their cells ``(k, 2)`` (the second -1), the fanned cells and each triangle's undirected
    edge key ``min * n + max``; the feature vertices go into ``newp[n:]`` (``x`` of the fanned cells, in
    their order; the rows before are the caller's)."""
    n_cells = feature.shape[0]
    n_fan = 0
    vid = np.full(n_cells, -1, np.int64)
    for c in range(n_cells):
        if feature[c]:
            vid[c] = n + n_fan
            n_fan += 1
    fan_cells = np.empty(n_fan, np.int64)
    for c in range(n_cells):
        if feature[c]:
            i = vid[c] - n
            fan_cells[i] = c
            for j in range(3):
                newp[n + i, j] = x[c, j]
    r = 0
    for e in range(bc.shape[0]):
        r += feature[bc[e]]
    fan = np.empty((r, 3), np.int64)
    owner = np.empty((r, 2), np.int64)
    ekey = np.empty(r, np.int64)
    k = 0
    for e in range(bc.shape[0]):
        c = bc[e]
        if feature[c]:
            a, b = b0[e], b1[e]
            fan[k, 0], fan[k, 1], fan[k, 2] = a, b, vid[c]
            owner[k, 0], owner[k, 1] = c, -1
            ekey[k] = min(a, b) * n + max(a, b)
            k += 1
    return fan, owner, fan_cells, ekey


@numba.njit(cache=True, nogil=True)
def _flip_fans(fan, owner, ekey, order, n, n_cells, normal, index, newp, cos_sharp, min_facing):
    """The flips between the fans of `_fan_rows` (in place), and which of the triangles face badly.

    A border edge shared by two fans whose ends' exact normals differ
    (``cos < cos_sharp``) is flipped to join the two feature vertices, where
    no other such edge joins them and both new triangles face well: the
    twins are the consecutive equal keys in `order` (``np.argsort(ekey,
    kind="stable")``).
    """
    r = fan.shape[0]
    pi = np.empty(r, np.int64)
    pj = np.empty(r, np.int64)
    fk = np.empty(r, np.int64)
    n_pairs = 0
    span = n + n_cells
    for t in range(r - 1):
        i, j = order[t], order[t + 1]
        if ekey[i] != ekey[j]:
            continue
        ea, eb = index[fan[i, 0]], index[fan[i, 1]]
        # (numpy's einsum of three products sums the first and last, then the middle: the same bits)
        d = (normal[ea, 0] * normal[eb, 0] + normal[ea, 2] * normal[eb, 2]) + normal[ea, 1] * normal[eb, 1]
        if d < cos_sharp:
            f1, f2 = fan[i, 2], fan[j, 2]
            pi[n_pairs], pj[n_pairs] = i, j
            fk[n_pairs] = min(f1, f2) * span + max(f1, f2)
            n_pairs += 1
    # a pair of feature vertices joined by one such edge only
    by = np.argsort(fk[:n_pairs], kind="mergesort")
    single = np.zeros(n_pairs, np.bool_)
    t = 0
    while t < n_pairs:
        u = t
        while u < n_pairs and fk[by[u]] == fk[by[t]]:
            u += 1
        if u - t == 1:
            single[by[t]] = True
        t = u
    # (a, b, F1) and (b, a, F2) become (a, F2, F1) and (F2, b, F1) where both face well
    # (all from the fans as made, then written as numpy's fancy assignments would: every first triangle,
    # then every second, then the owners likewise; a twin in two pairs takes the last)
    flips = np.zeros((n_pairs, 6), np.int64)
    good = np.zeros(n_pairs, np.bool_)
    for q in range(n_pairs):
        if not single[q]:
            continue
        i, j = pi[q], pj[q]
        a, b, f1, f2 = fan[i, 0], fan[i, 1], fan[i, 2], fan[j, 2]
        if not (_faces_badly(newp, a, f2, f1, normal, index, n, min_facing)
                or _faces_badly(newp, f2, b, f1, normal, index, n, min_facing)):
            good[q] = True
            flips[q, 0], flips[q, 1], flips[q, 2], flips[q, 3] = a, b, f1, f2
            flips[q, 4], flips[q, 5] = owner[i, 0], owner[j, 0]
    for q in range(n_pairs):
        if good[q]:
            i = pi[q]
            fan[i, 0], fan[i, 1], fan[i, 2] = flips[q, 0], flips[q, 3], flips[q, 2]
    for q in range(n_pairs):
        if good[q]:
            j = pj[q]
            fan[j, 0], fan[j, 1], fan[j, 2] = flips[q, 3], flips[q, 1], flips[q, 2]
    for q in range(n_pairs):
        if good[q]:
            i = pi[q]
            owner[i, 0], owner[i, 1] = flips[q, 4], flips[q, 5]
    for q in range(n_pairs):
        if good[q]:
            j = pj[q]
            owner[j, 0], owner[j, 1] = flips[q, 4], flips[q, 5]
    bad = np.empty(r, np.bool_)
    for t in range(r):
        bad[t] = _faces_badly(newp, fan[t, 0], fan[t, 1], fan[t, 2], normal, index, n, min_facing)
    return bad
