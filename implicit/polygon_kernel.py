"""The signed distance to a polygon of many edges, as a compiled loop.

`implicit.profiles.polygon_distance` measures polygons of many edges (a
gear's outline) with this kernel: the same arithmetic as its vectorized
form, one point at a time, without the ``(points x edges)`` temporaries.
numba is imported and the loop compiled on first use only.
"""

from __future__ import annotations

import numpy as np

__all__ = ["polygon_kernel"]
_KERNEL = []


def polygon_kernel():
    """The compiled form of `polygon_distance` (built on first use: numba is imported lazily)."""
    if not _KERNEL:
        import numba

        @numba.njit(cache=False)
        def kernel(px, py, vx, vy, out):  # pragma: no cover - compiled
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

        _KERNEL.append(kernel)
    return _KERNEL[0]
