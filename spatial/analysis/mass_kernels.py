"""The compiled per-triangle sums of `spatial.analysis.mass_solid` (one pass, no temporaries).

Module-level ``njit(cache=True)`` functions, so that a process loads them from numba's on-disk
cache: built as closures inside a function, their cache key held the pickled inner dispatcher,
which differs in every process, and each process compiled them again (about 1.5 s of CPU per
mass-properties run, and one more cache entry on disk each time).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["level", "shell", "centroids", "shell_error", "BLOCK"]

# The sums run in blocks of BLOCK terms, each block's sum added to the total with Neumaier's
# compensation: the rounding no longer grows with the number of triangles (a plain running sum over
# the 0.9 M triangles of N=256 is off by 5e-12 of the volume), so the sum over a mesh cut in parts
# (`spatial.distributed`) is the sum over the whole to rounding.
BLOCK = 512


@numba.njit(cache=True, fastmath=False, inline="always")
def _flush(out, comp, blk):  # pragma: no cover - compiled
    for q in range(blk.shape[0]):
        s, x = out[q], blk[q]
        t = s + x
        if abs(s) >= abs(x):
            comp[q] += (s - t) + x
        else:
            comp[q] += (x - t) + s
        out[q] = t
        blk[q] = 0.0



@numba.njit(cache=True, fastmath=False, inline="always")
def _close(out, comp, blk):  # pragma: no cover - compiled
    """The last block added, the compensation folded in, and the symmetric products copied."""
    _flush(out, comp, blk)
    out += comp
    out[7] = out[5]
    out[10] = out[6]
    out[11] = out[9]

@numba.njit(cache=True, fastmath=False)
def level(pts, tri, c0):  # pragma: no cover - compiled
    m = tri.shape[0]
    out = np.zeros(14)
    comp = np.zeros(14)
    blk = np.zeros(14)
    mids = np.empty((3 * m, 3))
    weights = np.empty(3 * m)
    for k in range(m):
        i, j, l = tri[k, 0], tri[k, 1], tri[k, 2]
        ax, ay, az = pts[i, 0] - c0[0], pts[i, 1] - c0[1], pts[i, 2] - c0[2]
        bx, by, bz = pts[j, 0] - c0[0], pts[j, 1] - c0[1], pts[j, 2] - c0[2]
        cx, cy, cz = pts[l, 0] - c0[0], pts[l, 1] - c0[1], pts[l, 2] - c0[2]
        ux, uy, uz = bx - ax, by - ay, bz - az
        vx, vy, vz = cx - ax, cy - ay, cz - az
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        area = 0.5 * np.sqrt(nx * nx + ny * ny + nz * nz)
        det = ax * nx + ay * ny + az * nz
        sx, sy, sz = ax + bx + cx, ay + by + cy, az + bz + cz
        blk[0] += det / 6.0
        blk[1] += det * sx / 24.0
        blk[2] += det * sy / 24.0
        blk[3] += det * sz / 24.0
        d = det / 120.0
        blk[4] += d * (sx * sx + ax * ax + bx * bx + cx * cx)
        blk[5] += d * (sx * sy + ax * ay + bx * by + cx * cy)
        blk[6] += d * (sx * sz + ax * az + bx * bz + cx * cz)
        blk[8] += d * (sy * sy + ay * ay + by * by + cy * cy)
        blk[9] += d * (sy * sz + ay * az + by * bz + cy * cz)
        blk[12] += d * (sz * sz + az * az + bz * bz + cz * cz)
        blk[13] += area
        w = area / 3.0
        for q in range(3):
            weights[3 * k + q] = w
        mids[3 * k, 0] = 0.5 * (ax + bx) + c0[0]
        mids[3 * k, 1] = 0.5 * (ay + by) + c0[1]
        mids[3 * k, 2] = 0.5 * (az + bz) + c0[2]
        mids[3 * k + 1, 0] = 0.5 * (bx + cx) + c0[0]
        mids[3 * k + 1, 1] = 0.5 * (by + cy) + c0[1]
        mids[3 * k + 1, 2] = 0.5 * (bz + cz) + c0[2]
        mids[3 * k + 2, 0] = 0.5 * (cx + ax) + c0[0]
        mids[3 * k + 2, 1] = 0.5 * (cy + ay) + c0[1]
        mids[3 * k + 2, 2] = 0.5 * (cz + az) + c0[2]
        if k % BLOCK == BLOCK - 1:
            _flush(out, comp, blk)
    _close(out, comp, blk)
    return out, mids, weights


@numba.njit(cache=True, fastmath=False)
def shell(mids, w, c0):  # pragma: no cover - compiled
    out = np.zeros(13)
    comp = np.zeros(13)
    blk = np.zeros(13)
    for k in range(mids.shape[0]):
        x, y, z = mids[k, 0] - c0[0], mids[k, 1] - c0[1], mids[k, 2] - c0[2]
        q = w[k]
        blk[0] += q
        blk[1] += q * x
        blk[2] += q * y
        blk[3] += q * z
        blk[4] += q * x * x
        blk[5] += q * x * y
        blk[6] += q * x * z
        blk[8] += q * y * y
        blk[9] += q * y * z
        blk[12] += q * z * z
        if k % BLOCK == BLOCK - 1:
            _flush(out, comp, blk)
    _close(out, comp, blk)
    return out


@numba.njit(cache=True, fastmath=False)
def centroids(pts, tri):  # pragma: no cover - compiled
    """The triangles' centroids, (m, 3)."""
    m = tri.shape[0]
    out = np.empty((m, 3))
    for k in range(m):
        i, j, l = tri[k, 0], tri[k, 1], tri[k, 2]
        for q in range(3):
            out[k, q] = (pts[i, q] + pts[j, q] + pts[l, q]) / 3.0
    return out


@numba.njit(cache=True, fastmath=False)
def shell_error(pts, tri, w, t_mid, t_vert, t_cen):  # pragma: no cover - compiled
    """Sums over the triangles of ``|q2 - q3|`` and of the tilt term ``8 |q2| (t_max / e)^2``
    (`spatial.analysis.mass_shell.volume_on_one_level`): q2 the edge-midpoint rule of the shell's
    height t, q3 the rule exact for cubics (vertices 1/20, midpoints 2/15, centroid 9/20 of the area),
    e^2 the mean of the squared edge lengths, t_max the largest |t| at the seven points."""
    quad = 0.0
    tilt = 0.0
    for k in range(tri.shape[0]):
        i, j, l = tri[k, 0], tri[k, 1], tri[k, 2]
        area = 3.0 * w[3 * k]
        ma, mb, mc = t_mid[3 * k], t_mid[3 * k + 1], t_mid[3 * k + 2]
        va, vb, vc = t_vert[i], t_vert[j], t_vert[l]
        c = t_cen[k]
        q2 = w[3 * k] * (ma + mb + mc)
        q3 = area * ((va + vb + vc) / 20.0 + (ma + mb + mc) * (2.0 / 15.0) + c * (9.0 / 20.0))
        quad += abs(q2 - q3)
        tmax = max(abs(ma), abs(mb), abs(mc), abs(va), abs(vb), abs(vc), abs(c))
        e2 = 0.0
        for q in range(3):
            dab = pts[i, q] - pts[j, q]
            dbc = pts[j, q] - pts[l, q]
            dca = pts[l, q] - pts[i, q]
            e2 += dab * dab + dbc * dbc + dca * dca
        e2 /= 3.0
        if e2 > 0.0:
            tilt += 8.0 * abs(q2) * tmax * tmax / e2
    return quad, tilt
