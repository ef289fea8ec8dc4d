"""The signed distance to a polygon of many edges, as a compiled loop.

`implicit.profiles.polygon_distance` measures polygons of many edges (a
gear's outline) with this kernel: the same arithmetic as its vectorized
form, one point at a time, without the ``(points x edges)`` temporaries.
A module-level ``njit(cache=True)`` function, so that a process loads it
from numba's on-disk cache instead of compiling it again; the module is
imported on first use only (numba is not imported with `implicit`).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["polygon_kernel", "polygon_signed_distance"]


#: Consecutive edges per bounding box: a box farther than the nearest edge found so far is passed
#: over, and one the point's row does not cross adds no crossing (the gear's 240 edges: 30 boxes).
CHUNK = 8


@numba.njit(cache=True, nogil=True)
def _edge_terms(x, y, vx, vy, j, k):  # pragma: no cover - compiled
    """Squared distance from ``(x, y)`` to edge ``j -> k`` and whether the +x ray crosses it."""
    ex, ey = vx[k] - vx[j], vy[k] - vy[j]
    wx, wy = x - vx[j], y - vy[j]
    t = (wx * ex + wy * ey) / (ex * ex + ey * ey)
    t = min(max(t, 0.0), 1.0)
    bx, by = wx - t * ex, wy - t * ey
    c1, c2, c3 = y >= vy[j], y < vy[k], ex * wy > ey * wx
    return bx * bx + by * by, (c1 and c2 and c3) or (not c1 and not c2 and not c3)


@numba.njit(cache=True, nogil=True)
def polygon_signed_distance(px, py, vx, vy, out):  # pragma: no cover - compiled
    """Signed distance of the points ``(px, py)`` to the closed polygon ``(vx, vy)``, into `out`.

    The edges go in boxes of `CHUNK`; a box is measured only where it can matter: its edges are
    the nearest's candidates while the box is nearer than the nearest edge so far (the nearest box
    first), and they can flip the crossing parity only where the
    point's ``y`` lies in the box's ``[ymin, ymax)`` (every other edge has ``c1 == c2``: no flip).
    The figures are those of the loop over all edges, to rounding of the skip test's margin.
    """
    m = vx.size
    nb = (m + CHUNK - 1) // CHUNK
    box = np.empty((nb, 4))
    for b in range(nb):
        x0, x1, y0, y1 = np.inf, -np.inf, np.inf, -np.inf
        for j in range(b * CHUNK, min((b + 1) * CHUNK, m) + 1):
            k = j if j < m else 0
            x0, x1 = min(x0, vx[k]), max(x1, vx[k])
            y0, y1 = min(y0, vy[k]), max(y1, vy[k])
        box[b, 0], box[b, 1], box[b, 2], box[b, 3] = x0, x1, y0, y1
    lb = np.empty(nb)
    for i in range(px.size):
        x, y = px[i], py[i]
        first = 0
        for b in range(nb):
            dx = max(box[b, 0] - x, 0.0, x - box[b, 1])
            dy = max(box[b, 2] - y, 0.0, y - box[b, 3])
            lb[b] = dx * dx + dy * dy
            if lb[b] < lb[first]:
                first = b
        # the nearest box first: a tight bound for the others
        best = np.inf
        for j in range(first * CHUNK, min((first + 1) * CHUNK, m)):
            d2, flip = _edge_terms(x, y, vx, vy, j, j + 1 if j + 1 < m else 0)
            best = min(best, d2)
        # rounding of an edge's squared distance: a relative 1e-9 and an absolute 1e-12 of the squares
        slack = 1e-12 * (x * x + y * y + 1.0)
        inside = False
        for b in range(nb):
            crosses = box[b, 2] <= y < box[b, 3]
            close = b != first and lb[b] * (1.0 - 1e-9) - slack <= best
            if not (crosses or close):
                continue
            for j in range(b * CHUNK, min((b + 1) * CHUNK, m)):
                d2, flip = _edge_terms(x, y, vx, vy, j, j + 1 if j + 1 < m else 0)
                if close and d2 < best:
                    best = d2
                if crosses and flip:
                    inside = not inside
        d = np.sqrt(best)
        out[i] = -d if inside else d


def polygon_kernel():
    """The compiled form of `polygon_distance` (`polygon_signed_distance`)."""
    return polygon_signed_distance
