"""The compiled loops of `implicit.facet_prune`: the first operand attaining a Boolean's min or max,
and runs of capsule operands evaluated over their rows.

The operands' values are computed by numpy, each at the points of the bins
it may decide (`implicit.facet_prune._Walk`); `first_best` only compares and
copies them, point by point in the operands' order, so its result is that
of the walk over the operands one by one.  A Boolean's consecutive capsule
operands (a lattice's struts) are evaluated by one loop over all their rows
(`capsules_at`, `capsule_gradients_at`), each row by the arithmetic of the
capsule's own loop (`implicit.primitive_kernels`): the same bits, without a
call per capsule.  `bin_points` sorts the points into their bins.  Module-level ``njit(cache=True)`` functions, loaded from
numba's on-disk cache; imported on first use only (numba is not imported
with `implicit`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .primitive_kernels import _from_segment

__all__ = ["bin_keys", "bin_points", "capsule_gradients_at", "capsules_at", "first_best", "point_range"]


@numba.njit(cache=True, nogil=True)
def first_best(rows, values, decs, smaller, cur, dec, filled):  # pragma: no cover - compiled
    """Fold the operand values ``values[k]`` (deciding facets ``decs[k]``) at rows ``rows[k]``,
    operands in order, into ``cur`` / ``dec`` / ``filled``: a value replaces the row's where the row
    has none yet, where it is strictly smaller (`smaller`) or larger, or where it is a NaN and the
    row's is not (``argmin`` / ``argmax`` return the first NaN)."""
    for k in range(rows.shape[0]):
        i = rows[k]
        v = values[k]
        c = cur[i]
        if filled[i]:
            if smaller:
                take = v < c
            else:
                take = v > c
            if not take:
                take = np.isnan(v) and not np.isnan(c)
        else:
            take = True
            filled[i] = True
        if take:
            cur[i] = v
            dec[i] = decs[k]


@numba.njit(cache=True, nogil=True)
def capsules_at(p, rows, which, a, ab, ab2, r, out):  # pragma: no cover - compiled
    """``out[k]``: the field of capsule ``which[k]`` (segment ``a[c] .. a[c] + ab[c]``, ``ab2[c] = ab[c] .
    ab[c]``, radius ``r[c]``) at point ``p[rows[k]]``, as `implicit.primitive_kernels.capsule_distance`."""
    for k in range(rows.shape[0]):
        c = which[k]
        wx, wy, wz = _from_segment(p, rows[k], a[c], ab[c], ab2[c])
        out[k] = math.sqrt(wx * wx + wy * wy + wz * wz) - r[c]


@numba.njit(cache=True, nogil=True)
def capsule_gradients_at(p, rows, which, a, ab, ab2, grad):  # pragma: no cover - compiled
    """``grad[k]``: the gradient of capsule ``which[k]`` at ``p[rows[k]]`` (`capsules_at`'s capsules), as
    `implicit.primitive_kernels.capsule_gradient`."""
    for k in range(rows.shape[0]):
        c = which[k]
        wx, wy, wz = _from_segment(p, rows[k], a[c], ab[c], ab2[c])
        d = math.sqrt(wx * wx + wy * wy + wz * wz)
        if d > 0.0:
            grad[k, 0], grad[k, 1], grad[k, 2] = wx / d, wy / d, wz / d
        else:
            grad[k, 0], grad[k, 1], grad[k, 2] = 0.0, 0.0, 0.0


@numba.njit(cache=True, nogil=True)
def bin_points(key, n_keys):  # pragma: no cover - compiled
    """The stable order of `key` (each in ``0 .. n_keys - 1``) by a counting sort, as
    ``np.argsort(key, kind="stable")``, and the first sorted position of every occupied key and the end."""
    n = key.shape[0]
    count = np.zeros(n_keys + 1, np.int64)
    for i in range(n):
        count[key[i] + 1] += 1
    occupied = 0
    for b in range(n_keys):
        occupied += count[b + 1] > 0
        count[b + 1] += count[b]
    starts = np.empty(occupied + 1, np.int64)
    r = 0
    for b in range(n_keys):
        if count[b + 1] > count[b]:
            starts[r] = count[b]
            r += 1
    starts[occupied] = n
    order = np.empty(n, np.int64)
    for i in range(n):
        b = key[i]
        order[count[b]] = i
        count[b] += 1
    return order, starts


@numba.njit(cache=True, nogil=True)
def point_range(p):  # pragma: no cover - compiled
    """The smallest and largest coordinates of the points ``(3,), (3,)``, in one pass."""
    lo = np.empty(3)
    hi = np.empty(3)
    for j in range(3):
        lo[j] = p[0, j]
        hi[j] = p[0, j]
    for i in range(p.shape[0]):
        for j in range(3):
            v = p[i, j]
            if v < lo[j]:
                lo[j] = v
            if v > hi[j]:
                hi[j] = v
    return lo, hi


@numba.njit(cache=True, nogil=True)
def bin_keys(p, lo, scale, g):  # pragma: no cover - compiled
    """Each point's bin ``(i * g1 + j) * g2 + k``, its cell along each axis ``min(int((x - lo) * scale),
    g - 1)`` (numpy's ``astype(np.int64)`` truncates as this does)."""
    key = np.empty(p.shape[0], np.int64)
    for i in range(p.shape[0]):
        k = np.int64(0)
        for j in range(3):
            c = np.int64((p[i, j] - lo[j]) * scale[j])
            if c > g[j] - 1:
                c = g[j] - 1
            k = k * g[j] + c
        key[i] = k
    return key
