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


@numba.njit(cache=True, nogil=True)
def polygon_signed_distance(px, py, vx, vy, out):  # pragma: no cover - compiled
    """Signed distance of the points ``(px, py)`` to the closed polygon ``(vx, vy)``, into `out`."""
    m = vx.size
    for i in range(px.size):
        x, y = px[i], py[i]
        best = np.inf
        inside = False
        for j in range(m):
            k = j + 1 if j + 1 < m else 0
            ex, ey = vx[k] - vx[j], vy[k] - vy[j]
            wx, wy = x - vx[j], y - vy[j]
            t = (wx * ex + wy * ey) / (ex * ex + ey * ey)
            t = min(max(t, 0.0), 1.0)
            bx, by = wx - t * ex, wy - t * ey
            best = min(best, bx * bx + by * by)
            c1, c2, c3 = y >= vy[j], y < vy[k], ex * wy > ey * wx
            if (c1 and c2 and c3) or (not c1 and not c2 and not c3):
                inside = not inside
        d = np.sqrt(best)
        out[i] = -d if inside else d


def polygon_kernel():
    """The compiled form of `polygon_distance` (`polygon_signed_distance`)."""
    return polygon_signed_distance
