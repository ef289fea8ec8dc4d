"""Pruning of a tape per spatial bin of points.

The points of a call are sorted into a grid of bins (`grid`, the counting
sort runs in `implicit.evaluate.compile`); for every bin, the operands of unions,
intersections and differences (sharp or smooth) that cannot change the
result anywhere in the bin's box are switched off (`operand_flags`).

References
----------
M. Keeter, "Massively Parallel Rendering of Complex Closed-Form Implicit
Surfaces", ACM Trans. Graph. 39(4), 2020, doi:10.1145/3386569.3392429.
"""

from __future__ import annotations

import threading
from typing import Callable

import numpy as np

from .tape import PRUNE_MODES, Tape

__all__ = ["grid", "operand_flags", "Workspace", "POINTS_PER_BIN", "MAX_BINS_PER_AXIS"]

#: Target number of points per bin of the pruning grid.
POINTS_PER_BIN = 256
#: Largest number of bins along one axis.
MAX_BINS_PER_AXIS = 64


def grid(lo: np.ndarray, hi: np.ndarray, n: int):
    """The binning grid for `n` points in the box `lo`..`hi`.

    Parameters
    ----------
    lo, hi : (3,) float
        Bounds of the points.
    n : int
        Number of points.

    Returns
    -------
    (g, scale) or None
        ``g`` (3,) int64 bins per axis (about `POINTS_PER_BIN` points a bin,
        near-cubic bins, a flat axis one bin thick) and ``scale`` (3,) bins
        per unit length; None when the box is not finite.

    Examples
    --------
    >>> g, scale = grid(np.zeros(3), np.array([2.0, 1.0, 0.0]), 50 * POINTS_PER_BIN)
    >>> g.tolist()
    [10, 5, 1]
    """
    ext = hi - lo
    if not (np.isfinite(ext).all() and np.isfinite(lo).all()):
        return None
    flat_axis = ext <= 1e-9 * max(float(ext.max()), 1e-300)
    active = ext[~flat_axis]
    g = np.ones(3, dtype=np.int64)
    if active.size:
        target = max(n / POINTS_PER_BIN, 1.0)
        h = (float(np.prod(active)) / target) ** (1.0 / active.size)
        g[~flat_axis] = np.clip(np.round(active / h), 1, MAX_BINS_PER_AXIS).astype(np.int64)
    scale = np.where(flat_axis, 0.0, g / np.where(flat_axis, 1.0, ext)) * (1.0 - 1e-12)
    return g, scale


def operand_flags(tape: Tape, lo: np.ndarray, hi: np.ndarray, record: Callable) -> np.ndarray:
    """Which operands of the tape each box needs.

    Parameters
    ----------
    tape : Tape
    lo, hi : (m, 3) float
        Boxes (the tight boxes of the bins' points).
    record : callable
        ``record(centres (m, 3)) -> (tape.nstore, m)``: the stored operand
        values of the recording tape at the boxes' centres.

    Returns
    -------
    (m, len(tape.flags)) bool
        False where the operand cannot change the result anywhere in the box.

    Notes
    -----
    An operand's value over a box lies within its value at the centre plus or
    minus its Lipschitz constant times the box's half-diagonal, measured in
    the operand's coordinates (the norm of the affine map above it); below
    coordinates that are no known affine image, nothing is pruned.  A union
    drops an operand whose lower bound exceeds the smallest upper bound of
    all operands (strictly, so the one that attains it stays); a smooth fold
    drops one that is at least the blend radius beyond the operands kept
    before it, where the smooth minimum returns the fold unchanged.
    """
    m = lo.shape[0]
    out = np.ones((m, len(tape.flags)), dtype=np.bool_)
    if not tape.flags or m == 0:
        return out
    centre = 0.5 * (lo + hi)
    radius = 0.5 * np.sqrt(np.einsum("ij,ij->i", hi - lo, hi - lo))
    # A little slack for rounding in the values compared.
    radius = radius * (1.0 + 1e-12) + 1e-12
    values = record(np.ascontiguousarray(centre))
    for (node, _, slots, entries), bounds in zip(tape.groups, tape.group_bounds):
        if bounds is None:
            continue
        norm, lips = bounds
        scale = radius * norm
        v = values[slots]
        vmin = v - lips * scale
        vmax = v + lips * scale
        mode = PRUNE_MODES[type(node)]
        if mode == "min":
            keep = ~(vmin > vmax.min(axis=0))
        elif mode == "max":
            keep = ~(vmax < vmin.max(axis=0))
        elif mode == "diff":
            # max(base, -tools): operand ranges [vmin, vmax] and [-vmax, -vmin].
            lower = np.concatenate([vmin[:1], -vmax[1:]])
            upper = np.concatenate([vmax[:1], -vmin[1:]])
            keep = ~(upper < lower.max(axis=0))
        else:
            keep = _smooth_keep(mode, vmin, vmax, float(node.blend))
        for index, col in entries:
            out[:, col] = keep[index]
    return out


def _smooth_keep(mode: str, vmin: np.ndarray, vmax: np.ndarray, k: float) -> np.ndarray:
    """Operands of a smooth fold that change it somewhere, shape ``(c, m)``.

    The fold ``acc = smin(acc, c_j)`` leaves ``acc`` unchanged (up to
    rounding) where ``c_j - acc >= k``; ``acc`` never exceeds the smallest
    value of the operands kept before ``j``.
    """
    keep = np.ones(vmin.shape, dtype=np.bool_)
    if mode == "smin":
        ceiling = vmax[0].copy()
        for j in range(1, vmin.shape[0]):
            keep[j] = ~(vmin[j] >= ceiling + k)
            np.minimum(ceiling, np.where(keep[j], vmax[j], np.inf), out=ceiling)
    elif mode == "smax":
        floor = vmin[0].copy()
        for j in range(1, vmin.shape[0]):
            keep[j] = ~(vmax[j] <= floor - k)
            np.maximum(floor, np.where(keep[j], vmin[j], -np.inf), out=floor)
    else:  # "sdiff": acc = -smin(-acc, c_j); unchanged where c_j + acc >= k
        floor = vmin[0].copy()
        for j in range(1, vmin.shape[0]):
            keep[j] = ~(vmin[j] + floor >= k)
            np.maximum(floor, np.where(keep[j], -vmax[j], -np.inf), out=floor)
    return keep


#: Binning buffers (40 bytes a point) are kept per thread for calls up to
#: this many points: fresh pages cost about 15 % of a pruned evaluation.
WORKSPACE_MAX_POINTS = 1 << 20
_LOCAL = threading.local()


class Workspace:
    """Per-thread buffers (cell, order, sorted points, values) for `n` points; fresh
    arrays when the thread's buffers are in use or `n` is large."""

    def __init__(self, n: int):
        self.n = n
        self.owned = False

    def __enter__(self):
        n = self.n
        if n > WORKSPACE_MAX_POINTS or getattr(_LOCAL, "busy", False):
            return np.empty(n, np.int32), np.empty(n, np.int32), np.empty((n, 3)), np.empty(n)
        buffers = getattr(_LOCAL, "buffers", None)
        if buffers is None or buffers[0].shape[0] < n:
            size = max(n, 1 << 16)
            buffers = (np.empty(size, np.int32), np.empty(size, np.int32), np.empty((size, 3)), np.empty(size))
            _LOCAL.buffers = buffers
        _LOCAL.busy = self.owned = True
        return tuple(b[:n] for b in buffers)

    def __exit__(self, *exc):
        if self.owned:
            _LOCAL.busy = False
        return False
