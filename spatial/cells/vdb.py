"""OpenVDB level sets: sparse narrow-band grids, `.vdb` files, meshes to solids.

OpenVDB comes from Debian's ``python3-openvdb`` (module ``pyopenvdb``), imported
only by the functions that need it.  Note that ``copyToArray`` /
``copyFromArray`` index a voxel ``(i, j, k)`` as ``array[i, j, k]``, and voxel
``(i, j, k)`` of a linear transform sits at ``translation + (i, j, k) * h``.
"""

from __future__ import annotations

import os

import numpy as np

from ..files.atomic import atomic_write
from ..files.meshes import load_mesh
from .sparse_grid import TILE, SparseGridSolid

__all__ = ["mesh_to_solid", "save_vdb", "load_vdb", "vdb_metadata", "import_openvdb", "VDB_HALF_WIDTH"]

#: Narrow-band half width of VDB level sets, in voxels.
VDB_HALF_WIDTH = 3.0


# OpenVDB
# ---------------------------------------------------------------------------

def import_openvdb():
    """Import Debian's pyopenvdb, or raise ImportError naming the package."""
    try:
        import pyopenvdb
    except ImportError as exc:
        raise ImportError(
            "OpenVDB support needs the 'pyopenvdb' module: install Debian's python3-openvdb "
            "(apt-get install python3-openvdb) and expose it to this environment"
        ) from exc
    return pyopenvdb


def _check_vdb_path(path):
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name, got {type(path).__name__}")
    if os.path.splitext(os.fspath(path))[1].lower() != ".vdb":
        raise ValueError(f"{os.fspath(path)}: expected a .vdb file name")


#: Active boxes up to this many voxels are read into one dense `GridSolid` (at most 32 MB of float64);
#: larger ones into a `SparseGridSolid` of the band's tiles.
DENSE_VOXELS = 1 << 22


def _grid_to_solid(grid, pad=2, dense=None):
    """A solid of a FloatGrid level set: a dense `GridSolid` over its active box (plus `pad` voxels) when
    that box is small (`DENSE_VOXELS`) or `dense` is True, otherwise a `SparseGridSolid` of the tiles the
    band occupies -- memory proportional to the active voxels, never to the box."""
    lo, hi = grid.evalActiveVoxelBoundingBox()
    lo = np.array(lo, dtype=np.int64)
    hi = np.array(hi, dtype=np.int64)
    if np.any(lo > hi):
        raise ValueError("VDB grid: no active voxels")
    xform = grid.transform
    origin = np.array(xform.indexToWorld((0, 0, 0)), dtype=np.float64)
    step = np.array(xform.indexToWorld((1, 1, 1)), dtype=np.float64) - origin
    h = float(step[0])
    if not np.allclose(step, h, rtol=1e-9):
        raise ValueError(f"VDB grid: expected a uniform voxel size, got {step.tolist()}")
    box = np.prod((hi - lo + 1 + 2 * pad).astype(np.float64))
    if dense or (dense is None and box <= DENSE_VOXELS):
        from implicit.fields import GridSolid

        lo, hi = lo - pad, hi + pad
        arr = np.empty(tuple(int(v) for v in hi - lo + 1), dtype=np.float32)
        grid.copyToArray(arr, ijk=tuple(int(v) for v in lo))  # inactive voxels and tiles: +-background
        return GridSolid(arr, origin=origin + lo * h, voxel_size=h)
    return _sparse_solid(grid, origin, h)


def _band_tiles(grid, origin, h):
    """Indices (k, 3) of the tiles of `TILE**3` voxels that may hold active voxels, found sparsely.

    The zero level (`FloatGrid.convertToQuads`, a mesh of the surface) marks
    the tiles it crosses; every active voxel of a narrow band lies within
    the band's half width (background / h voxels) of it, hence within that
    many tiles, by which the marked ones are dilated.  A grid with no zero
    level has no surface to keep.
    """
    points, _ = grid.convertToQuads(0.0)
    points = np.asarray(points, dtype=np.float64)
    if points.shape[0] == 0:
        raise ValueError("VDB grid: no zero level (no surface) in the grid")
    keys = np.unique(np.floor((points - origin) / (h * TILE)).astype(np.int64), axis=0)
    del points
    reach = max(int(np.ceil(abs(float(grid.background)) / h / TILE)), 1)
    span = np.arange(-reach, reach + 1)
    offsets = np.stack(np.meshgrid(span, span, span, indexing="ij"), -1).reshape(-1, 3)
    return np.unique((keys[:, None, :] + offsets[None]).reshape(-1, 3), axis=0)


def _sparse_solid(grid, origin, h):
    """A `SparseGridSolid` of the grid's band: each candidate tile read with one `copyToArray` (a call per
    tile, never per voxel), tiles holding nothing but the background dropped."""
    keys = _band_tiles(grid, origin, h)
    n = TILE + 1
    bg = abs(float(grid.background))
    kept, samples = [], []
    tile = np.empty((n, n, n), dtype=np.float32)
    for row, key in enumerate(keys):
        grid.copyToArray(tile, ijk=tuple(int(v) * TILE for v in key))
        if np.any(np.abs(tile) < bg):  # background only: the bound outside the tiles says as much
            kept.append(row)
            samples.append(tile.copy())
    if not kept:
        raise ValueError("VDB grid: no values inside its band")
    return SparseGridSolid(keys[kept], np.stack(samples), origin=origin, voxel_size=h)


def _open_edges(faces: np.ndarray) -> int:
    """Half-edges without an opposite one (0 for a closed, consistently
    oriented, manifold surface); an edge used twice the same way counts too."""
    a = faces.ravel().astype(np.int64)
    b = np.roll(faces, -1, axis=1).ravel().astype(np.int64)
    n = int(max(a.max(), b.max())) + 1
    fwd = np.unique(a * n + b, return_counts=True)
    rev = np.sort(b * n + a)
    repeated = int((fwd[1] > 1).sum())
    found = np.isin(fwd[0], rev, assume_unique=False)
    return int((~found).sum()) + repeated


#: Faces probed for overlap by `_intersecting`.
PROBES = 256


def _winding(q, points, faces):
    """Generalized winding numbers of points `q` (k, 3) about the mesh (`implicit`'s, in blocks of
    about 16 MB of corners)."""
    from implicit.surface_projection import winding_number

    return winding_number(q, points[faces], chunk=2_000_000 // 9)


def _intersecting(points, faces) -> int:
    """Probed faces whose inner side is not simply inside (winding number 1).

    Just inside a face of a closed, outward, non-intersecting surface the
    winding number is 1; where shells overlap or a part of the surface
    folds through another it is 2 or 0.  `PROBES` faces spread over the
    mesh are probed: overlapping bodies and folds are found, a crossing
    smaller than the probes' spacing may not be.
    """
    m = len(faces)
    pick = np.unique(np.linspace(0, m - 1, min(PROBES, m)).astype(np.int64))
    tri = points[faces[pick]]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    norm = np.linalg.norm(cross, axis=1)
    keep = norm > 0
    n = cross[keep] / norm[keep, None]
    edge = np.sqrt(norm[keep])
    q = tri[keep].mean(axis=1) - 1e-3 * edge[:, None] * n
    w = _winding(q, points, faces)
    return int(np.sum(np.abs(w - 1.0) > 0.5))


def _repaired(points, faces):
    import pymeshfix

    fix = pymeshfix.MeshFix(np.asarray(points, dtype=np.float64), np.asarray(faces, dtype=np.int32))
    fix.repair()
    return np.asarray(fix.points, dtype=np.float64), np.asarray(fix.faces, dtype=np.int32).reshape(-1, 3)


def _mesh_problems(points, faces) -> str:
    """'' for a closed, oriented, non-self-intersecting mesh, else what is wrong."""
    open_edges = _open_edges(faces)
    if open_edges:
        return f"open or not consistently oriented ({open_edges} edges without an opposite)"
    crossing = _intersecting(points, faces)
    if crossing:
        return f"self-intersecting (inside {crossing} of the probed faces the surface is crossed again)"
    return ""


def mesh_to_solid(mesh_or_path, voxel_size, *, half_width=VDB_HALF_WIDTH, repair=False):
    """A closed triangle mesh as a solid (an OpenVDB narrow-band level set).

    An open or self-intersecting mesh has no inside: its level set would call
    points outside the part inside.  Such a mesh is refused, or, with
    ``repair=True``, first closed and untangled by pymeshfix (holes filled,
    intersecting triangles removed and re-stitched), which changes the
    surface where it was broken.

    Parameters
    ----------
    mesh_or_path : pyvista.PolyData or path
        A closed surface (scanned or exported parts).
    voxel_size : float
        Voxel edge of the level set.
    half_width : float
        Narrow-band half width in voxels; distances are clamped to it (the
        field stays a conservative bound).
    repair : bool
        Repair an open or self-intersecting mesh instead of refusing it.

    Returns
    -------
    implicit.fields.GridSolid

    Raises
    ------
    ValueError
        The mesh is open, not consistently oriented, or intersects itself
        (and `repair` is False), or a repair leaves it so.
    """
    from implicit.solid import as_positive

    h = as_positive(voxel_size, "voxel_size")
    import pyvista as pv

    mesh = load_mesh(mesh_or_path) if isinstance(mesh_or_path, (str, os.PathLike)) else mesh_or_path
    if not isinstance(mesh, pv.PolyData):
        raise TypeError(f"mesh_or_path: expected a pyvista.PolyData or a file name, got {type(mesh).__name__}")
    if mesh.n_cells == 0:
        raise ValueError("mesh_or_path: the mesh has no faces")
    vdb = import_openvdb()
    tri = mesh.triangulate() if not mesh.is_all_triangles else mesh
    faces = tri.faces.reshape(-1, 4)[:, 1:].astype(np.int32)
    points = np.asarray(tri.points, dtype=np.float64)
    if not np.all(np.isfinite(points)):
        raise ValueError("mesh_or_path: the mesh has non-finite vertices")
    # STL repeats every vertex per triangle: weld equal positions first
    points, inverse = np.unique(points, axis=0, return_inverse=True)
    faces = inverse.reshape(-1)[faces].astype(np.int32)
    problems = _mesh_problems(points, faces)
    if problems and repair:
        points, faces = _repaired(points, faces)
        problems = _mesh_problems(points, faces) if len(faces) else "no faces left"
        if problems:
            raise ValueError(f"mesh_or_path: the repaired mesh is still {problems}")
    elif problems:
        raise ValueError(f"mesh_or_path: the mesh is {problems}, so it has no inside; repair it "
                         "(mesh_to_solid(..., repair=True) uses pymeshfix) or give a closed surface")
    # OpenVDB level sets wind inward: flip the outward triangles.
    faces = faces[:, ::-1].copy()
    grid = vdb.FloatGrid.createLevelSetFromPolygons(
        np.asarray(points, dtype=np.float32), triangles=faces,
        transform=vdb.createLinearTransform(voxelSize=h), halfWidth=float(half_width))
    return _grid_to_solid(grid)


def save_vdb(solid_or_grid, path, *, voxel_size=None, units="mm", name="surface"):
    """Write a level set (.vdb) with its voxel size and units as metadata.

    Parameters
    ----------
    solid_or_grid : Solid, GridSolid or OccupancyGrid
        A solid is sampled on a grid of `voxel_size` first.
    path : str or os.PathLike
        A ``.vdb`` file name; written atomically.
    voxel_size : float, optional
        Needed for a general solid.
    units : str
        Length unit recorded in the metadata.
    """
    _check_vdb_path(path)
    if not isinstance(units, str):
        raise TypeError(f"units: expected a string, got {units!r}")
    from implicit.fields import GridSolid
    from implicit.solid import Solid, as_positive

    from .grid import OccupancyGrid

    if isinstance(solid_or_grid, OccupancyGrid):
        data, origin, h = solid_or_grid.distance, solid_or_grid.origin + 0.5 * solid_or_grid.voxel_size, \
            solid_or_grid.voxel_size
    elif isinstance(solid_or_grid, GridSolid) and voxel_size is None:
        data, origin, h = solid_or_grid.distance, solid_or_grid.origin, solid_or_grid.voxel_size
    elif isinstance(solid_or_grid, Solid):
        if voxel_size is None:
            raise ValueError("voxel_size: needed to sample a solid into a level set")
        grid = OccupancyGrid.from_solid(solid_or_grid, voxel_size=as_positive(voxel_size, "voxel_size"))
        data, origin, h = grid.distance, grid.origin + 0.5 * grid.voxel_size, grid.voxel_size
    else:
        raise TypeError(f"solid_or_grid: expected a Solid or an OccupancyGrid, got {type(solid_or_grid).__name__}")
    vdb = import_openvdb()
    band = float(VDB_HALF_WIDTH * h)
    grid = vdb.FloatGrid(background=band)
    matrix = np.eye(4) * h
    matrix[3] = [origin[0], origin[1], origin[2], 1.0]
    grid.transform = vdb.createLinearTransform(matrix.tolist())
    grid.copyFromArray(np.clip(np.asarray(data, dtype=np.float32), -band, band), ijk=(0, 0, 0), tolerance=0.0)
    grid.gridClass = vdb.GridClass.LEVEL_SET
    grid.name = name
    grid["voxel_size"] = float(h)
    grid["units"] = units
    return atomic_write(path, lambda tmp: vdb.write(tmp, grids=[grid]), ".vdb")


def load_vdb(path, *, dense=None):
    """Read the first float grid of a .vdb file as a solid.

    Sparse in, sparse out: a grid whose active box is small (at most
    `DENSE_VOXELS`, or with ``dense=True``) is read into one dense
    `GridSolid`; a larger one into a `SparseGridSolid` holding only the
    tiles of its narrow band (found from its zero level, read tile by tile),
    so that memory follows the active voxels, not the box: two small balls a
    thousand voxels apart take kilobytes, not the box's 4 GB.

    Parameters
    ----------
    path : str or os.PathLike
        A .vdb file.
    dense : bool, optional
        Force the dense (True) or the sparse (False) form.

    Returns
    -------
    GridSolid or SparseGridSolid

    Examples
    --------
    >>> solid = load_vdb("part.vdb")  # doctest: +SKIP
    >>> solid([[0.0, 0.0, 0.0]])  # doctest: +SKIP
    array([-0.5])
    """
    _check_vdb_path(path)
    if dense is not None and not isinstance(dense, (bool, np.bool_)):
        raise TypeError(f"dense: expected True, False or None, got {dense!r}")
    if not os.path.exists(os.fspath(path)):
        raise FileNotFoundError(2, "No such file", os.fspath(path))
    vdb = import_openvdb()
    grids, _ = vdb.readAll(os.fspath(path))
    floats = [g for g in grids if isinstance(g, vdb.FloatGrid)]
    if not floats:
        raise ValueError(f"{os.fspath(path)}: no float grid in the file")
    return _grid_to_solid(floats[0], dense=dense)


def vdb_metadata(path) -> dict:
    """Metadata (voxel size, units, ...) of the first grid of a .vdb file."""
    _check_vdb_path(path)
    vdb = import_openvdb()
    grids, _ = vdb.readAll(os.fspath(path))
    return dict(grids[0].metadata) if grids else {}
