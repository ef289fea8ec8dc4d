"""Incidences of a mesh's nodes, each by one compiled counting sort.

The cells around every node (`node_cells`) and the element sides that belong to one element
only (`single_sides`) were built by sorting every entry of the connectivity (``np.argsort``
with a ``np.searchsorted`` for the starts; a sort of one integer code per side): a node's
cells are its entries' positions, and the nodes are few compared to the entries, so counting
them and placing each entry at its node's next free slot gives the same, stable order in two
passes.  A side is single when no other side has its three corners: each side's sorted corners
go into a hash table once (open addressing), a side meeting its key there marks both.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["node_cells", "single_sides"]


@njit(cache=True, nogil=True)
def _node_cells(flat, n):
    """Positions of `flat` grouped by value (stable) and the groups' starts; ok False when a
    value lies outside ``0 .. n - 1``."""
    starts = np.zeros(n + 1, dtype=np.int64)
    for i in range(flat.size):
        v = flat[i]
        if v < 0 or v >= n:
            return np.empty(0, dtype=np.int64), starts, False
        starts[v + 1] += 1
    for v in range(n):
        starts[v + 1] += starts[v]
    free = starts[:n].copy()
    order = np.empty(flat.size, dtype=np.int64)
    for i in range(flat.size):
        v = flat[i]
        order[free[v]] = i
        free[v] += 1
    return order, starts, True


def node_cells(cells, n):
    """The cells around each of `n` nodes: ``(order, starts)``.

    Parameters
    ----------
    cells : (m, k) int
        Node numbers of each cell (triangles, tetrahedra, mid-edge nodes ...), in ``0 .. n - 1``.
    n : int
        Number of nodes.

    Returns
    -------
    order : (m k,) int
        Positions into ``cells.reshape(-1)``, node after node and ascending within a node
        (``order // k`` are the cells): ``np.argsort(cells.reshape(-1), kind="stable")``.
    starts : (n + 1,) int
        Node ``v``'s positions are ``order[starts[v]:starts[v + 1]]``:
        ``np.searchsorted(cells.reshape(-1)[order], np.arange(n + 1))``.

    Raises
    ------
    ValueError
        When a node number lies outside ``0 .. n - 1``.

    Examples
    --------
    >>> order, starts = node_cells(np.array([[0, 1, 2], [2, 1, 3]]), 4)
    >>> order.tolist(), starts.tolist()
    ([0, 1, 4, 2, 3, 5], [0, 1, 3, 5, 6])
    """
    flat = np.ascontiguousarray(cells, dtype=np.int64).reshape(-1)
    n = int(n)
    if n < 0:
        raise ValueError(f"n: expected a number of nodes >= 0, got {n}")
    order, starts, ok = _node_cells(flat, n)
    if not ok:
        raise ValueError(f"cells: expected node numbers in 0 .. {n - 1}, got {int(flat.min())} .. {int(flat.max())}")
    return order, starts


@njit(cache=True, nogil=True)
def _single_sides(tets, side_nodes):
    """Whether each side ``(element, side)`` of `tets` (flat, element after element) is in no other element."""
    m = tets.shape[0]
    s = side_nodes.shape[0]
    total = m * s
    size = 1
    while size < 2 * total:
        size *= 2
    mask = size - 1
    slot = np.full(size, -1, dtype=np.int64)  # open addressing: the first side seen with each key
    key = np.empty((total, 3), dtype=np.int64)
    single = np.ones(total, dtype=np.bool_)
    for t in range(m):
        for k in range(s):
            a, b, c = tets[t, side_nodes[k, 0]], tets[t, side_nodes[k, 1]], tets[t, side_nodes[k, 2]]
            if a > b:
                a, b = b, a
            if b > c:
                b, c = c, b
            if a > b:
                a, b = b, a
            i = t * s + k
            key[i, 0], key[i, 1], key[i, 2] = a, b, c
            h = ((a * 73856093) ^ (b * 19349663) ^ (c * 83492791)) & mask
            while True:
                j = slot[h]
                if j < 0:
                    slot[h] = i
                    break
                if key[j, 0] == a and key[j, 1] == b and key[j, 2] == c:
                    single[i] = False
                    single[j] = False
                    break
                h = (h + 1) & mask
    return single


def single_sides(tets, side_nodes):
    """Which sides of the elements belong to that element only, ``(m * s,)`` bool.

    Parameters
    ----------
    tets : (m, c) int
        Elements.
    side_nodes : (s, 3) int
        Columns of `tets` that make each side.

    Returns
    -------
    (m * s,) bool
        Side ``k`` of element ``t`` at ``t * s + k``: True when no other side, of any element, has
        the same three nodes (in any order).

    Examples
    --------
    >>> sides = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]])
    >>> single_sides(np.array([[0, 1, 2, 3], [1, 2, 3, 4]]), sides).reshape(2, 4).tolist()
    [[True, True, False, True], [False, True, True, True]]
    """
    tets = np.ascontiguousarray(tets, dtype=np.int64)
    side_nodes = np.ascontiguousarray(side_nodes, dtype=np.int64)
    if tets.ndim != 2:
        raise ValueError(f"tets: expected an (m, c) array of node numbers, got shape {tets.shape}")
    if side_nodes.ndim != 2 or side_nodes.shape[1] != 3 or (side_nodes.size and (
            side_nodes.min() < 0 or side_nodes.max() >= tets.shape[1])):
        raise ValueError(f"side_nodes: expected (s, 3) columns of tets, got {side_nodes.tolist()}")
    return _single_sides(tets, side_nodes)
