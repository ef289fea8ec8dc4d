"""The lattice shared by octrees, grids and meshes, and its classification.

Cell decomposition: an octree of FULL, EMPTY and BOUNDARY cells.

The region of interest (a solid's bounds, or bounds given by the caller) is
covered by a lattice of finest cells of edge `voxel_size`, padded by one cell
on every side.  The octree's root is a cube of ``2**depth`` finest cells per
side anchored at the lattice `origin`.  Level by level, every cell of the
level is classified in ONE vectorized call to ``solid.value_bounds(lo, hi)``:

* ``vmin > 0``  -> EMPTY (no point of the closed cell is inside),
* ``vmax < 0``  -> FULL (every point of the closed cell is inside),
* otherwise     -> BOUNDARY, split into 8 children down to the voxel size.

The classification is conservative: a FULL or EMPTY cell never holds
boundary.  Cells lying wholly outside the padded region are EMPTY without
being evaluated.

Leaves are stored as flat arrays (one row per leaf): `index` (integer lower
corner in finest cells), `lo`, `size`, `state`, `level`, `vmin`, `vmax`.

References
----------
M. Keeter, "Massively Parallel Rendering of Complex Closed-Form Implicit
Surfaces", ACM Trans. Graph. 39(4), 2020, doi:10.1145/3386569.3392429.
D. Meagher, "Geometric modeling using octree encoding", Computer Graphics and
Image Processing 19(2), 1982, doi:10.1016/0146-664X(82)90104-6.
"""

from __future__ import annotations

import math
import numbers
import os

import numpy as np

from implicit.solid import Solid

from ..files.progress import progress_bar

__all__ = ["EMPTY", "FULL", "BOUNDARY", "STATE_NAMES", "CHILD_OFFSETS", "MAX_DEPTH", "Lattice", "make_lattice",
           "descend", "check_dense_memory", "available_memory", "provide", "provided"]

#: Cell states.
EMPTY = 0
FULL = 1
BOUNDARY = 2
STATE_NAMES = ("empty", "full", "boundary")

# Offsets of the 8 children of a cell, in units of the child size (x slowest).
CHILD_OFFSETS = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)], dtype=np.int32)

#: Largest octree depth accepted (2**depth finest cells per side).
MAX_DEPTH = 20


# ---------------------------------------------------------------------------
# the lattice shared by octrees, grids and meshes
# ---------------------------------------------------------------------------

class Lattice:
    """A regular lattice of cubic cells: ``origin + index * voxel_size``.

    Attributes
    ----------
    solid : Solid
        The solid to decompose (clipped to `bounds` when the caller gave
        bounds that do not hold the solid).
    origin : (3,) float64
        Lower corner of cell (0, 0, 0).
    voxel_size : float
        Cell edge ``h``.
    shape : (3,) int64
        Number of cells per axis covering the bounds plus one cell of padding
        on each side.
    bounds : (lo, hi)
        The region of interest (finite).
    depth : int
        Smallest ``L`` with ``2**L >= max(shape)``.
    """

    __slots__ = ("solid", "origin", "voxel_size", "shape", "bounds", "depth", "empty")

    def __init__(self, solid, origin, voxel_size, shape, bounds, empty=False):
        self.solid = solid
        self.origin = np.asarray(origin, dtype=np.float64)
        self.voxel_size = float(voxel_size)
        self.shape = np.asarray(shape, dtype=np.int64)
        self.bounds = bounds
        self.depth = int(max(0, math.ceil(math.log2(max(int(self.shape.max()), 1)))))
        self.empty = bool(empty)


def _check_solid(solid, name="solid"):
    if not isinstance(solid, Solid):
        raise TypeError(f"{name}: expected an implicit.Solid, got {type(solid).__name__}")


def _check_bounds(bounds):
    try:
        arr = np.asarray(bounds, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"bounds: expected (lo, hi) with 3 numbers each, got {bounds!r}") from exc
    if arr.size != 6:
        raise ValueError(f"bounds: expected (lo, hi) with 3 numbers each, got shape {arr.shape}")
    arr = arr.reshape(2, 3)
    if not np.isfinite(arr).all():
        raise ValueError(f"bounds: expected finite numbers, got {arr.tolist()}")
    if np.any(arr[0] >= arr[1]):
        raise ValueError(f"bounds: expected lo < hi on every axis, got lo={arr[0].tolist()} hi={arr[1].tolist()}")
    return arr[0].copy(), arr[1].copy()


def _solid_bounds(solid):
    """Finite bounds of `solid` or a clear error (uses `Solid.require_bounds` when present)."""
    require = getattr(solid, "require_bounds", None)
    if callable(require):
        lo, hi = require()
        return np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    lo, hi = solid.bounds
    if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
        raise ValueError(
            f"solid: its bounds are unbounded (lo={lo.tolist()}, hi={hi.tolist()}); "
            "pass bounds=(lo, hi) to decompose a finite region of it"
        )
    return np.array(lo), np.array(hi)


def make_lattice(solid, *, voxel_size=None, resolution=None, bounds=None, max_depth=MAX_DEPTH) -> Lattice:
    """Choose the lattice of finest cells for `solid`.

    Exactly one of `voxel_size` (cell edge) or `resolution` (cells across the
    longest side of the bounds) is given.  When `bounds` are given and the
    solid's own bounds stick out of them, the solid is clipped to the box so
    that meshes stay closed.

    Returns
    -------
    Lattice
        With ``empty=True`` when the solid is empty and no bounds were given.
    """
    _check_solid(solid)
    if (voxel_size is None) == (resolution is None):
        raise ValueError("give exactly one of voxel_size= (cell edge) or resolution= (cells across the longest side)")
    if voxel_size is not None:
        if isinstance(voxel_size, bool) or not isinstance(voxel_size, numbers.Real):
            raise TypeError(f"voxel_size: expected a positive number, got {voxel_size!r}")
        if not (math.isfinite(voxel_size) and voxel_size > 0):
            raise ValueError(f"voxel_size: expected a positive number, got {voxel_size!r}")
    else:
        if isinstance(resolution, bool) or not isinstance(resolution, numbers.Integral):
            raise TypeError(f"resolution: expected a positive integer, got {resolution!r}")
        if resolution < 1:
            raise ValueError(f"resolution: expected a positive integer, got {resolution!r}")
    clip = False
    if bounds is not None:
        lo, hi = _check_bounds(bounds)
        slo, shi = solid.bounds
        if not solid.is_empty_bounds and (np.any(slo < lo) or np.any(shi > hi)):
            clip = True
    else:
        if solid.is_empty_bounds:
            return Lattice(solid, np.zeros(3), voxel_size or 1.0, np.ones(3, dtype=np.int64),
                           (np.zeros(3), np.zeros(3)), empty=True)
        lo, hi = _solid_bounds(solid)
        hi = np.maximum(hi, lo)
    extent = hi - lo
    if voxel_size is not None:
        h = float(voxel_size)
    else:
        longest = float(extent.max())
        if longest <= 0:
            raise ValueError(f"resolution: the bounds have zero extent ({lo.tolist()} to {hi.tolist()}); pass voxel_size=")
        h = longest / int(resolution)
    cells = np.ceil(extent / h * (1 - 1e-12)).astype(np.int64)
    cells = np.maximum(cells, 1) + 2  # one cell of padding on each side
    if cells.max() > 2 ** max_depth:
        raise ValueError(
            f"voxel_size: {h:g} gives {int(cells.max())} cells across the bounds, more than the "
            f"{2 ** max_depth} an octree of depth {max_depth} holds; use a larger voxel size"
        )
    centre = 0.5 * (lo + hi)
    origin = centre - 0.5 * cells * h
    if clip:
        from implicit import box as _box  # a box node clipping the solid to the bounds

        solid = solid & _box(size=hi - lo, center=centre)
    return Lattice(solid, origin, h, cells, (lo, hi))


# ---------------------------------------------------------------------------
# classification, level by level
# ---------------------------------------------------------------------------

def descend(lattice: Lattice, *, keep_leaves=True, stop_level=None, progress=None, chunk=None, margin=0.0,
            start=None):
    """Classify the lattice's octree top-down.

    Parameters
    ----------
    lattice : Lattice
    keep_leaves : bool
        Keep the FULL / EMPTY leaves of every level (the mesh only needs the
        boundary cells of the last level).
    stop_level : int, optional
        Last level classified (default `lattice.depth`, the finest).
    progress : bool or None
        Progress bar (None: only on a terminal).
    chunk : int, optional
        Bound at most this many boxes per `value_bounds` call (default: one
        call per level).
    margin : float
        A cell is EMPTY only when ``vmin > margin`` and FULL only when ``vmax
        < -margin``: a mesher that pushes samples within `margin` of the level
        off it needs uniform cells whose samples keep one sign under the
        rounding of a point evaluation (a face lying on a lattice plane gives
        ``vmin`` of 1e-17 and samples of -1e-17).
    start : (int, (k, 3) int), optional
        ``(level, cells)``: classify from that level on, starting with these
        cells of it (default: the root, level 0) -- a part of the octree,
        classified exactly as the whole tree classifies it.

    Returns
    -------
    dict
        ``leaves``: list per level of ``(index, state, vmin, vmax)`` (index in
        units of that level's cells); ``boundary``: (m, 3) int32 indices of the
        BOUNDARY cells of the last level; ``evaluations``: number of boxes
        bounded; ``classified``: cells classified per level.
    """
    depth = lattice.depth
    stop = depth if stop_level is None else int(stop_level)
    solid, origin, h = lattice.solid, lattice.origin, lattice.voxel_size
    shape = lattice.shape
    first, cells = (0, np.zeros((1, 3), dtype=np.int32)) if start is None else \
        (int(start[0]), np.asarray(start[1], dtype=np.int32).reshape(-1, 3))
    boundary = cells[:0]
    leaves = []
    classified = []
    evaluations = 0
    bar = progress_bar(max(stop + 1 - first, 0), "classify", progress, unit="level")
    try:
        for level in range(first, stop + 1):
            s = 1 << (depth - level)
            # cells wholly outside the padded region are EMPTY without evaluation
            limit = (-(-shape // s)).astype(np.int32)
            inside = (cells < limit).all(axis=1)
            if not inside.all():
                out_cells = cells[~inside]
                cells = cells[inside]
            else:
                out_cells = cells[:0]
            m = cells.shape[0]
            vmin = np.empty(m)
            vmax = np.empty(m)
            step = m if not chunk else int(chunk)
            for a in range(0, m, max(step, 1)):
                lo = origin + cells[a:a + step] * (s * h)
                vmin[a:a + step], vmax[a:a + step] = solid.value_bounds(lo, lo + s * h)
            evaluations += m
            classified.append(m + out_cells.shape[0])
            state = np.full(m, BOUNDARY, dtype=np.uint8)
            state[vmin > margin] = EMPTY
            state[vmax < -margin] = FULL
            is_b = state == BOUNDARY
            if keep_leaves:
                done = ~is_b if level < stop else np.ones_like(is_b)
                idx = np.concatenate([cells[done], out_cells])
                st = np.concatenate([state[done], np.full(out_cells.shape[0], EMPTY, np.uint8)])
                vlo = np.concatenate([vmin[done], np.full(out_cells.shape[0], np.inf)])
                vhi = np.concatenate([vmax[done], np.full(out_cells.shape[0], np.inf)])
                leaves.append((idx, st, vlo, vhi))
            del vmin, vmax, state
            boundary = cells[is_b]
            if level < stop:
                cells = (2 * boundary[:, None, :] + CHILD_OFFSETS).reshape(-1, 3)
            bar.update()
    finally:
        bar.close()
    return {"leaves": leaves, "boundary": boundary, "evaluations": evaluations, "classified": classified}


#: A dense allocation may use at most this fraction of the available memory.
MEMORY_FRACTION = 0.7


def available_memory() -> int:
    """Bytes of physical memory currently available (``os.sysconf``)."""
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return 8 << 30


def check_dense_memory(shape, *, bytes_per_voxel, what, max_bytes=None):
    """Refuse a dense allocation that would not fit.

    Parameters
    ----------
    shape : tuple of int
        Voxels per axis.
    bytes_per_voxel : float
        Peak bytes per voxel of the operation.
    what : str
        Name of the operation, for the message.
    max_bytes : int, optional
        Limit (default: `MEMORY_FRACTION` of the available memory).

    Raises
    ------
    MemoryError
        Naming the estimate (GB), the available memory and the octree route.
    """
    need = float(np.prod(np.asarray(shape, dtype=np.float64))) * bytes_per_voxel
    avail = available_memory()
    limit = MEMORY_FRACTION * avail if max_bytes is None else float(max_bytes)
    if need > limit:
        raise MemoryError(
            f"{what}: a dense grid of {tuple(int(v) for v in shape)} voxels needs about {need / 1e9:.2f} GB, "
            f"more than the {limit / 1e9:.2f} GB allowed ({avail / 1e9:.2f} GB available); use "
            "spatial.Octree.from_solid or spatial.mesh, whose cost follows the surface, or a larger voxel size"
        )
    return need


# ---------------------------------------------------------------------------
# seams: what other modules provide to the cells' methods
# ---------------------------------------------------------------------------

#: Filled in at import by the providers: the occupancy grid class (for
#: `Octree.to_grid`; the grid module imports the octree's, not the other way)
#: and the meshers of the meshing room above (`Octree.to_mesh`,
#: `OccupancyGrid.to_mesh`), so that no module of this room imports upward.
_PROVIDED: dict = {}

#: Where each name is registered.  `import spatial` loads its rooms lazily, so a
#: user may hold an octree before anything imported its provider: the provider
#: is then loaded by name when a method first needs it.  The dependency stays
#: one-way in the code (this room names no module above it in an import).
_PROVIDERS = {"OccupancyGrid": "spatial.cells.grid", "mesh_cells": "spatial.meshing", "grid_mesh": "spatial.meshing"}


def provide(name: str, obj):
    """Register `obj` under `name` for the cells' methods; returns `obj`."""
    _PROVIDED[name] = obj
    return obj


def provided(name: str):
    """The object registered under `name`, its provider loaded on first need."""
    if name not in _PROVIDED and name in _PROVIDERS:
        import importlib

        importlib.import_module(_PROVIDERS[name])
    try:
        return _PROVIDED[name]
    except KeyError:
        raise ImportError(f"{name!r} is provided by a room above spatial.cells, and none registered it") from None
