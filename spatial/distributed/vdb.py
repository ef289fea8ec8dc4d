"""Sparse narrow-band level sets of large parts as OpenVDB grids, sampled brick by brick.

A dense grid of a part at N = 4096 holds 69 G voxels; its narrow band holds
about ``6 A / h**2`` of them (A the area).  Each task samples the lattice nodes
of its brick's boundary cells (cells of two voxels the surface may cross: the
nodes within about ``2 sqrt(3) h`` of it) and returns them as a list; the
client writes them into an OpenVDB ``FloatGrid`` block by block (arrays of
``block**3`` voxels, never a dense array of the whole part), fills the
inside with the negative background and writes the .vdb.
"""

from __future__ import annotations

import os

import numpy as np

from ..cells.vdb import VDB_HALF_WIDTH, import_openvdb
from ..files.atomic import atomic_write
from ..meshing import DEFAULT_BLOCK
from .cluster import check_client, connect
from .plan import DEFAULT_BRICK, plan_bricks
from .run import run_bricks
from .warn import user_warnings
from .worker import brick_band

__all__ = ["level_set_vdb", "save_level_set_vdb"]


def _write_nodes(grid, nodes, values, block, band):
    """Add nodes (j, 3) and their values to `grid` through dense arrays of `block**3` voxels, one per block
    holding nodes.  Each array starts from what the grid already holds there: the nodes on a face
    between bricks come from both bricks, in any order, and neither copy may erase the other's."""
    if nodes.shape[0] == 0:
        return
    nodes = nodes.astype(np.int64)
    blk = nodes // block
    span = blk.max(axis=0) - blk.min(axis=0) + 1
    low = blk.min(axis=0)
    key = ((blk[:, 0] - low[0]) * span[1] + blk[:, 1] - low[1]) * span[2] + blk[:, 2] - low[2]
    keys, first, inv = np.unique(key, return_index=True, return_inverse=True)
    keys = blk[first]
    local = nodes - keys[inv] * block
    dense = np.empty((keys.shape[0], block, block, block), dtype=np.float32)
    corners = [tuple(int(v) for v in k * block) for k in keys]
    for k in range(keys.shape[0]):  # one call per block, not per voxel
        grid.copyToArray(dense[k], ijk=corners[k])  # inactive voxels read as the background
    dense[inv, local[:, 0], local[:, 1], local[:, 2]] = np.clip(values, -band, band)
    for k in range(keys.shape[0]):
        grid.copyFromArray(dense[k], ijk=corners[k], tolerance=0.0)


@user_warnings
def level_set_vdb(solid, *, client=None, workers=None, voxel_size=None, resolution=None, bounds=None,
                  half_width=VDB_HALF_WIDTH, brick=DEFAULT_BRICK, block=DEFAULT_BLOCK, name="surface",
                  units="mm", progress=None):
    """A sparse OpenVDB level set of a solid, sampled on a Dask cluster.

    Parameters
    ----------
    solid : Solid
    client, workers, voxel_size, resolution, bounds, brick, block, progress
        See `spatial.distributed.mesh`.
    half_width : float
        Background (the distance outside the band) in voxels; values are
        clamped to ``+-half_width * h``.
    name, units : str
        Grid name and the length unit recorded in its metadata.

    Returns
    -------
    pyopenvdb.FloatGrid
        Active voxels: the lattice nodes of the boundary cells, holding the
        solid's values; voxel ``(i, j, k)`` at lattice node ``(i, j, k)``
        (``origin + (i, j, k) * h``); grid class LEVEL_SET, inside filled
        with ``-background``.
    """
    from implicit.solid import as_positive

    check_client(client, workers)
    hw = as_positive(half_width, "half_width")
    if not isinstance(units, str) or not isinstance(name, str):
        raise TypeError("name, units: expected strings")
    vdb = import_openvdb()
    if voxel_size is None and resolution is None:
        from ..cells.thickness import default_voxel_size

        voxel_size = default_voxel_size(solid, bounds)  # the single-process mesher's voxel
    plan = plan_bricks(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds, block=block,
                       brick=brick)
    h = plan.spec.voxel_size
    band = float(hw * h)
    grid = vdb.FloatGrid(background=band)
    matrix = np.eye(4) * h
    matrix[3] = [*plan.spec.origin, 1.0]
    grid.transform = vdb.createLinearTransform(matrix.tolist())
    grid.gridClass = vdb.GridClass.LEVEL_SET
    grid.name = name
    evaluations = plan.evaluations
    if plan.bricks.shape[0]:
        with connect(client, workers) as c:
            for _, part in run_bricks(c, brick_band, plan.spec, plan.bricks, progress=progress, name="band"):
                evaluations += part["evaluations"]
                _write_nodes(grid, part["nodes"], part["values"], plan.spec.block, band)
    grid.signedFloodFill()
    grid["voxel_size"] = float(h)
    grid["units"] = units
    grid["evaluations"] = int(evaluations)
    return grid


@user_warnings
def save_level_set_vdb(solid, path, **options):
    """Write the sparse level set of `level_set_vdb` to a .vdb file (atomically); returns the path.

    Examples
    --------
    >>> from implicit import sphere
    >>> save_level_set_vdb(sphere(1.0), "ball.vdb", resolution=64, workers=2)  # doctest: +SKIP
    'ball.vdb'
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name, got {type(path).__name__}")
    if os.path.splitext(os.fspath(path))[1].lower() != ".vdb":
        raise ValueError(f"path: expected a .vdb file name, got {os.fspath(path)!r}")
    if not os.path.isdir(os.path.dirname(os.path.abspath(os.fspath(path)))):
        raise ValueError(f"path: the folder of {os.fspath(path)!r} does not exist")
    vdb = import_openvdb()
    grid = level_set_vdb(solid, **options)
    return atomic_write(path, lambda tmp: vdb.write(tmp, grids=[grid]), ".vdb")
