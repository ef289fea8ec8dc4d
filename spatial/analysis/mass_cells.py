"""Mass properties of cell decompositions: occupancy grids and octrees.

FULL cells integrate exactly as boxes (each cell's own inertia included);
BOUNDARY cells count with the fractional occupancy ``clamp(0.5 - d/h, 0, 1)``
of the distance ``d`` sampled at their centre, a second-order rule.  The
error bounds are rigorous: the true solid lies between the certain cells and
the certain plus uncertain ones.  `spatial.analysis.mass.mass_properties` is the entry
point.
"""

from __future__ import annotations

import numpy as np

from .mass_core import _Raw

__all__ = ["box_moments"]


def box_moments(centers, sizes, weights, *, center) -> tuple[float, np.ndarray, np.ndarray]:
    """Raw moments of many weighted axis-aligned boxes, vectorized.

    A box of centre ``p`` (relative to `center`) and edge lengths ``s`` has
    ``V = s_x s_y s_z``, ``m1 = V p`` and ``M2 = V (p p^T + diag(s^2) / 12)``
    (its own inertia included); each box counts with its weight in [0, 1].

    Parameters
    ----------
    centers : (m, 3) float
    sizes : (m,) or (m, 3) float
    weights : (m,) float
    center : (3,) float
        Reference point of the moments.
    """
    p = np.asarray(centers, dtype=np.float64) - np.asarray(center, dtype=np.float64)
    s = np.asarray(sizes, dtype=np.float64)
    if s.ndim == 1:
        s = np.repeat(s[:, None], 3, axis=1)
    vol = np.prod(s, axis=1) * np.asarray(weights, dtype=np.float64)
    V = float(vol.sum())
    m1 = vol @ p
    m2 = np.einsum("k,ki,kj->ij", vol, p, p) + np.diag(vol @ (s * s)) / 12.0
    return V, m1, m2


def _uncertain_bounds(centers, sizes, weights, center):
    """Error bounds of the moments of boxes whose true occupancy lies anywhere
    in [0, 1] while the estimate used `weights`."""
    p = np.abs(np.asarray(centers, dtype=np.float64) - center)
    s = np.asarray(sizes, dtype=np.float64)
    if s.ndim == 1:
        s = np.repeat(s[:, None], 3, axis=1)
    w = np.asarray(weights, dtype=np.float64)
    slack = np.prod(s, axis=1) * np.maximum(w, 1.0 - w)
    reach = p + 0.5 * s
    e_v = float(slack.sum())
    e_m1 = slack @ reach
    e_m2 = np.einsum("k,ki,kj->ij", slack, reach, reach)
    return e_v, e_m1, e_m2


def _grid_raw(grid) -> tuple[_Raw, float]:
    """Raw moments of an occupancy grid by fractional occupancy."""
    h = float(grid.voxel_size)
    d = np.asarray(grid.distance, dtype=np.float64)
    origin = np.asarray(grid.origin, dtype=np.float64)
    shape = np.asarray(d.shape)
    c0 = origin + 0.5 * h * shape
    # Cells farther than half a cell diagonal from the boundary are certain.
    half_diag = 0.5 * np.sqrt(3.0) * h
    full = d <= -half_diag
    uncertain = np.abs(d) < half_diag
    idx_full = np.argwhere(full)
    idx_unc = np.argwhere(uncertain)
    frac = np.clip(0.5 - d[uncertain] / h, 0.0, 1.0)
    cf = origin + (idx_full + 0.5) * h
    cu = origin + (idx_unc + 0.5) * h
    V1, m1a, m2a = box_moments(cf, np.full(len(cf), h), np.ones(len(cf)), center=c0)
    V2, m1b, m2b = box_moments(cu, np.full(len(cu), h), frac, center=c0)
    eV, e1, e2 = _uncertain_bounds(cu, np.full(len(cu), h), frac, c0)
    area = _grid_area(d, h)
    raw = _Raw(c0, V1 + V2, m1a + m1b, m2a + m2b, area, eV, e1, e2, area)
    return raw, h


def _grid_area(d: np.ndarray, h: float) -> float:
    """Boundary area of a sampled distance field: the co-area estimate
    ``sum |grad d| delta(d) h^3`` with a hat kernel of width one cell."""
    g = np.gradient(d, h)
    grad = np.sqrt(sum(gi * gi for gi in g))
    kernel = np.clip(1.0 - np.abs(d) / h, 0.0, None) / h
    return float((grad * kernel).sum() * h ** 3)


def _octree_raw(tree, solid) -> tuple[_Raw, float]:
    """Raw moments of an octree: FULL leaves exactly, BOUNDARY leaves by the
    fractional occupancy of the distance at their centre."""
    lo = np.asarray(tree.lo, dtype=np.float64)
    size = np.asarray(tree.size, dtype=np.float64)
    state = np.asarray(tree.state)
    full = state == 1
    bnd = state == 2
    if not (full.any() or bnd.any()):
        raise ValueError("octree: it holds no FULL or BOUNDARY cells (empty solid)")
    every = full | bnd
    c0 = 0.5 * (lo[every].min(axis=0) + (lo[every] + size[every, None]).max(axis=0))
    centers = lo + 0.5 * size[:, None]
    V1, m1a, m2a = box_moments(centers[full], size[full], np.ones(int(full.sum())), center=c0)
    cb, sb = centers[bnd], size[bnd]
    if solid is None:
        raise ValueError("octree: it has no solid to weigh its BOUNDARY cells; pass solid=")
    dist = solid(cb)
    frac = np.clip(0.5 - dist / sb, 0.0, 1.0)
    # co-area estimate with a hat kernel (|grad f| = 1); first order only
    area = float((sb * sb * np.clip(1.0 - np.abs(dist) / sb, 0.0, None)).sum())
    V2, m1b, m2b = box_moments(cb, sb, frac, center=c0)
    eV, e1, e2 = _uncertain_bounds(cb, sb, frac, c0)
    h = float(sb.min()) if len(sb) else float(size.min())
    raw = _Raw(c0, V1 + V2, m1a + m1b, m2a + m2b, area, eV, e1, e2, area)
    return raw, h


# ---------------------------------------------------------------------------
