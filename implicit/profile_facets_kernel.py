"""The compiled loop of `implicit.profile_facets`: the facets' fields of a polygon's runs.

One pass over points and polygon edges (`run_fields` gives its meaning); a
module-level ``njit(cache=True)`` function, so that a process loads it from
numba's on-disk cache instead of compiling it.  Imported on first use only
(numba is not imported with `implicit`).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["run_kernel"]


@numba.njit(cache=True, nogil=True)
def run_kernel(px, py, vx, vy, s, group, vals, grads, near, dist):  # pragma: no cover - compiled
    m = vx.size
    r = s.size - 1
    for i in range(px.size):
        x, y = px[i], py[i]
        inside = False
        for j in range(m):
            k = j + 1 if j + 1 < m else 0
            ex, ey = vx[k] - vx[j], vy[k] - vy[j]
            wx, wy = x - vx[j], y - vy[j]
            c1, c2, c3 = y >= vy[j], y < vy[k], ex * wy > ey * wx
            if (c1 and c2 and c3) or (not c1 and not c2 and not c3):
                inside = not inside
        sign = -1.0 if inside else 1.0
        closest = np.inf
        for c in range(vals.shape[0]):
            vals[c, i] = np.inf
        for run in range(r):
            best, bgx, bgy = np.inf, 0.0, 0.0
            for j in range(s[run], s[run + 1]):
                k = j + 1 if j + 1 < m else 0
                ex, ey = vx[k] - vx[j], vy[k] - vy[j]
                wx, wy = x - vx[j], y - vy[j]
                ee = ex * ex + ey * ey
                t = min(max((wx * ex + wy * ey) / ee, 0.0), 1.0)
                bx, by = wx - t * ex, wy - t * ey
                d = np.sqrt(bx * bx + by * by)
                if d < best:
                    best = d
                    if d > 0.0:
                        bgx, bgy = sign * bx / d, sign * by / d
                    else:  # on the edge: its outward normal (counter-clockwise polygon)
                        le = np.sqrt(ee)
                        bgx, bgy = ey / le, -ex / le
            val = sign * best
            if best < closest:
                closest = best
                near[i] = group[run]
            # the rays continuing the first edge backwards and the last edge forwards
            for end in range(2):
                j = s[run] if end == 0 else s[run + 1] - 1
                k = j + 1 if j + 1 < m else 0
                ex, ey = vx[k] - vx[j], vy[k] - vy[j]
                le = np.sqrt(ex * ex + ey * ey)
                ux, uy = ex / le, ey / le
                ox, oy = (vx[j], vy[j]) if end == 0 else (vx[k], vy[k])
                wx, wy = x - ox, y - oy
                t = wx * ux + wy * uy
                if (end == 0 and t >= 0.0) or (end == 1 and t <= 0.0):
                    continue
                line = wx * uy - wy * ux          # along the outward normal (uy, -ux)
                if abs(line) < best:
                    best = abs(line)
                    val = line
                    bgx, bgy = uy, -ux
            c = group[run]
            if abs(val) < abs(vals[c, i]):
                vals[c, i] = val
                grads[c, i, 0] = bgx
                grads[c, i, 1] = bgy
        dist[i] = sign * closest
