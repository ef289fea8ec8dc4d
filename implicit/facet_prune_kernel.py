"""The compiled loop of `implicit.facet_prune`: the first operand attaining a Boolean's min or max.

The operands' values are computed by numpy, each at the points of the bins
it may decide (`implicit.facet_prune._Walk`); this pass only compares and
copies them, point by point in the operands' order, so its result is that
of the walk over the operands one by one.  A module-level
``njit(cache=True)`` function, loaded from numba's on-disk cache; imported
on first use only (numba is not imported with `implicit`).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["first_best"]


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
