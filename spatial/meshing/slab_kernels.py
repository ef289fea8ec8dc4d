"""Compiled steps of a slab's sampling (`slab._SlabJob.prepare`), a few long calls between its evaluations.

A slab is prepared on a second thread while this one runs scikit-image's marching cubes, which
holds the interpreter's lock.  Every return from a compiled call or numpy operation that let the
lock go is a wait for it (up to a switch interval, plus the rest of a marching-cubes call), so the
preparation's bookkeeping was some 35 such waits per slab at N=512: the merged nodes' ids, their
``np.unique`` and the previous slab's handoff, each pass's selection of nodes and the scatter of
its values, the crossing ends, the dense samples and the handoff of the upper plane.  Here they
are four calls: `merged_nodes`, `first_pass`, `second_pass` and `slab_samples`, each between two
of the slab's evaluations.

Module-level ``@njit(cache=True, nogil=True)`` functions; every result equals the numpy
expression it replaces, bit for bit (`np.unique` through a stable sort: its first indices are the
first occurrences, as numpy's own ``mergesort``).
"""

from __future__ import annotations

import numba
import numpy as np

from .kernels import crossing_ends, fill_values, node_ids, node_points

__all__ = []


@numba.njit(cache=True, nogil=True)
def _unique_first(ids):
    """``np.unique(ids, return_index=True, return_inverse=True)``: sorted ids, the row of each one's
    first occurrence, and each row's slot among them."""
    n = ids.shape[0]
    order = np.argsort(ids, kind="mergesort")
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
            pos = min(np.searchsorted(pid, uniq[u]), npid - 1)
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
                origin, h):
    """Pass 1's values `a` (single `rows`) and `b` (unique nodes `ru`) written with their signs and
    copied to every merged row; then the nodes of pass 2 -- the ends of crossing edges still without
    a value (`crossing_ends`, over the spent node codes `code`) -- as ``(single rows, unique merged
    nodes, their positions)``."""
    for i in range(rows.shape[0]):
        v_n[rows[i]] = a[i]
        s_n[rows[i]] = -1 if a[i] < 0 else 1
    for i in range(ru.shape[0]):
        v_u[ru[i]] = b[i]
        s_u[ru[i]] = -1 if b[i] < 0 else 1
    for t in range(m_idx.shape[0]):
        s_n[m_idx[t]] = s_u[back[t]]
        v_n[m_idx[t]] = v_u[back[t]]
    w_n = crossing_ends(code, flat, s_n, v_n, B)
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
