"""Marching cubes over a dense occupancy grid (`OccupancyGrid.to_mesh`)."""

from __future__ import annotations

import warnings

import numpy as np

from .arrays import ZERO_NUDGE, empty_mesh

__all__ = ["grid_mesh"]


def grid_mesh(grid):
    """Closed, outward-oriented marching-cubes mesh of a grid's samples.

    The grid is padded by one outside sample, so occupancy touching the
    grid's border still closes; samples at exactly 0 are nudged outwards.

    Parameters
    ----------
    grid : spatial.OccupancyGrid

    Returns
    -------
    pyvista.PolyData

    Examples
    --------
    >>> from implicit import sphere
    >>> from spatial import OccupancyGrid
    >>> grid_mesh(OccupancyGrid.from_solid(sphere(1), resolution=16)).n_cells > 0
    True
    """
    import pyvista as pv
    from skimage.measure import marching_cubes

    h = grid.voxel_size
    eps = np.float32(ZERO_NUDGE * h)
    vol = np.pad(grid.distance, 1, constant_values=np.float32(h))
    small = np.abs(vol) < eps
    vol[small] = np.where(vol[small] < 0, -eps, eps)
    if not (vol.min() < 0 < vol.max()):
        warnings.warn("OccupancyGrid.to_mesh: no boundary in the grid; returning an empty mesh",
                      RuntimeWarning, stacklevel=3)
        return empty_mesh(h)
    verts, faces, _, _ = marching_cubes(vol, 0.0, allow_degenerate=False)
    points = grid.origin + (verts.astype(np.float64) - 0.5) * h
    out = pv.PolyData(points, np.hstack([np.full((faces.shape[0], 1), 3, np.int64), faces]).ravel())
    out.field_data["voxel_size"] = np.array([h])
    out.field_data["evaluations"] = np.array([0], dtype=np.int64)
    return out
