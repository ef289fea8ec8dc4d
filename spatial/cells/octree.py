"""Cell decomposition: an octree of FULL, EMPTY and BOUNDARY cells.

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

import numpy as np

from implicit.solid import Solid

from .progress import progress_bar

__all__ = ["EMPTY", "FULL", "BOUNDARY", "STATE_NAMES", "Octree", "Lattice", "make_lattice"]

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

def descend(lattice: Lattice, *, keep_leaves=True, stop_level=None, progress=None, chunk=None):
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
    cells = np.zeros((1, 3), dtype=np.int32)
    leaves = []
    classified = []
    evaluations = 0
    bar = progress_bar(stop + 1, "classify", progress, unit="level")
    try:
        for level in range(stop + 1):
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
            state[vmin > 0] = EMPTY
            state[vmax < 0] = FULL
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


# ---------------------------------------------------------------------------
# the octree
# ---------------------------------------------------------------------------

class Octree:
    """Leaves of an octree cell decomposition of a solid.

    Build it with `Octree.from_solid` (or `OccupancyGrid.to_octree`).  All
    per-leaf attributes are flat arrays with one row per leaf; the leaves tile
    the root cube ``origin + [0, 2**depth * voxel_size]^3`` without overlap.

    Attributes
    ----------
    index : (m, 3) int32
        Lower corner of each leaf in finest cells.
    lo : (m, 3) float64
        Lower corner of each leaf (``origin + index * voxel_size``).
    size : (m,) float64
        Edge length of each leaf (``voxel_size * 2**(depth - level)``).
    state : (m,) uint8
        `EMPTY`, `FULL` or `BOUNDARY`.  BOUNDARY leaves are finest cells.
    level : (m,) uint8
        Level of each leaf (0 is the root, `depth` the finest).
    vmin, vmax : (m,) float64
        Conservative range of the field over each leaf (``inf`` for leaves
        outside the padded region, which are EMPTY without evaluation).
    origin : (3,) float64
    voxel_size : float
    depth : int
    shape : (3,) int64
        Finest cells per axis of the padded region of interest.
    bounds : (lo, hi)
        Region of interest.
    solid : Solid or None
        The solid decomposed (None for an octree built from a grid).
    evaluations : int
        Number of boxes bounded while building.

    Examples
    --------
    >>> from implicit import sphere
    >>> tree = Octree.from_solid(sphere(1.0), resolution=16)
    >>> full, full_or_boundary = tree.volume_bounds()
    >>> bool(full < 4.18879 < full_or_boundary)
    True
    """

    def __init__(self, *, index, state, level, vmin, vmax, origin, voxel_size, depth, shape, bounds,
                 solid=None, evaluations=0, classified=None):
        self.index = np.ascontiguousarray(index, dtype=np.int32).reshape(-1, 3)
        self.state = np.ascontiguousarray(state, dtype=np.uint8)
        self.level = np.ascontiguousarray(level, dtype=np.uint8)
        self.vmin = np.asarray(vmin, dtype=np.float64)
        self.vmax = np.asarray(vmax, dtype=np.float64)
        self.origin = np.asarray(origin, dtype=np.float64)
        self.voxel_size = float(voxel_size)
        self.depth = int(depth)
        self.shape = np.asarray(shape, dtype=np.int64)
        self.bounds = bounds
        self.solid = solid
        self.evaluations = int(evaluations)
        self._classified = classified
        self.size = self.voxel_size * (2.0 ** (self.depth - self.level.astype(np.int64)))
        self.lo = self.origin + self.index * self.voxel_size

    # -- construction -------------------------------------------------------
    @classmethod
    def from_solid(cls, solid, *, voxel_size=None, resolution=None, bounds=None, progress=None) -> "Octree":
        """Decompose `solid` into FULL, EMPTY and BOUNDARY cells.

        Parameters
        ----------
        solid : Solid
            A bounded solid, or any solid with `bounds` given.
        voxel_size : float, optional
            Edge of the finest cells.
        resolution : int, optional
            Finest cells across the longest side of the bounds (exactly one of
            `voxel_size` / `resolution`).
        bounds : (lo, hi), optional
            Region to decompose (default: the solid's bounds).  A solid sticking
            out of it is clipped to it.
        progress : bool or None
            Progress bar (None: only on a terminal).

        Returns
        -------
        Octree
        """
        lattice = make_lattice(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds)
        if lattice.empty:
            raise ValueError("solid: it is empty (its bounds enclose nothing); pass bounds= to decompose a region")
        result = descend(lattice, keep_leaves=True, progress=progress)
        depth = lattice.depth
        parts = [[], [], [], [], []]
        for level, (idx, st, vlo, vhi) in enumerate(result["leaves"]):
            parts[0].append(idx.astype(np.int32) << (depth - level))
            parts[1].append(st)
            parts[2].append(np.full(st.shape[0], level, dtype=np.uint8))
            parts[3].append(vlo)
            parts[4].append(vhi)
        return cls(index=np.concatenate(parts[0]), state=np.concatenate(parts[1]), level=np.concatenate(parts[2]),
                   vmin=np.concatenate(parts[3]), vmax=np.concatenate(parts[4]), origin=lattice.origin,
                   voxel_size=lattice.voxel_size, depth=depth, shape=lattice.shape, bounds=lattice.bounds,
                   solid=lattice.solid, evaluations=result["evaluations"], classified=result["classified"])

    # -- summaries ----------------------------------------------------------
    def __len__(self) -> int:
        return int(self.state.shape[0])

    def __repr__(self) -> str:
        counts = np.bincount(self.state, minlength=3)
        return (f"Octree(depth={self.depth}, voxel_size={self.voxel_size:g}, leaves={len(self)}, "
                f"empty={counts[EMPTY]}, full={counts[FULL]}, boundary={counts[BOUNDARY]})")

    @property
    def nbytes(self) -> int:
        """Bytes held by the per-leaf arrays."""
        return int(sum(a.nbytes for a in (self.index, self.state, self.level, self.vmin, self.vmax, self.size, self.lo)))

    def level_stats(self) -> list:
        """Per-level leaf counts and storage.

        Returns
        -------
        list of dict
            One dict per level with keys ``level``, ``cell_size``, ``empty``,
            ``full``, ``boundary`` (leaf counts), ``classified`` (cells bounded
            or skipped at that level) and ``bytes`` (storage of that level's
            leaves).
        """
        per_leaf = self.nbytes / max(len(self), 1)
        counts = np.zeros((self.depth + 1, 3), dtype=np.int64)
        np.add.at(counts, (self.level.astype(np.int64), self.state.astype(np.int64)), 1)
        stats = []
        for level in range(self.depth + 1):
            row = counts[level]
            stats.append({
                "level": level,
                "cell_size": self.voxel_size * 2.0 ** (self.depth - level),
                "empty": int(row[EMPTY]),
                "full": int(row[FULL]),
                "boundary": int(row[BOUNDARY]),
                "classified": int(self._classified[level]) if self._classified else int(row.sum()),
                "bytes": int(round(row.sum() * per_leaf)),
            })
        return stats

    def volume_bounds(self) -> tuple[float, float]:
        """Rigorous bounds on the solid's volume inside the root cube.

        Returns
        -------
        (lower, upper) : float
            Volume of the FULL leaves, and of the FULL plus BOUNDARY leaves.
        """
        vol = self.size ** 3
        full = float(vol[self.state == FULL].sum())
        boundary = float(vol[self.state == BOUNDARY].sum())
        return full, full + boundary

    def boundary_index(self) -> np.ndarray:
        """Integer lower corners (m, 3) of the BOUNDARY (finest) cells."""
        return self.index[self.state == BOUNDARY]

    # -- conversions ----------------------------------------------------------
    def to_grid(self, *, max_bytes=None):
        """Dense `OccupancyGrid` of the finest cells of the padded region.

        Voxels of BOUNDARY leaves hold the solid's distance sampled at their
        centres; voxels of FULL (EMPTY) leaves hold ``min(vmax, -h/2)``
        (``max(vmin, h/2)``): the right sign and a magnitude that never exceeds
        the true distance to the boundary.

        Raises
        ------
        MemoryError
            When the dense grid would not fit in the available memory.
        """
        from .grid import OccupancyGrid, check_dense_memory

        n = tuple(int(v) for v in self.shape)
        check_dense_memory(n, bytes_per_voxel=10, what="Octree.to_grid", max_bytes=max_bytes)
        h = self.voxel_size
        half = np.float32(0.5 * h)
        fill = np.where(self.state == FULL, np.minimum(self.vmax, -half), np.maximum(self.vmin, half))
        fill = fill.astype(np.float32)
        vals = np.zeros((1, 1, 1), dtype=np.float32)
        for level in range(self.depth + 1):
            s = 1 << (self.depth - level)
            m = tuple(-(-v // s) for v in n)
            if level:
                vals = vals.repeat(2, 0)[:m[0]].repeat(2, 1)[:, :m[1]].repeat(2, 2)[:, :, :m[2]]
            sel = np.flatnonzero((self.level == level) & (self.state != BOUNDARY))
            ijk = self.index[sel] >> (self.depth - level)
            ok = np.all(ijk < np.array(m), axis=1)
            vals[ijk[ok, 0], ijk[ok, 1], ijk[ok, 2]] = fill[sel[ok]]
        b = self.boundary_index()
        b = b[np.all(b < self.shape, axis=1)]
        if b.shape[0] and self.solid is not None:
            vals[b[:, 0], b[:, 1], b[:, 2]] = self.solid(self.origin + (b + 0.5) * h).astype(np.float32)
        elif b.shape[0]:
            vals[b[:, 0], b[:, 1], b[:, 2]] = 0.5 * (self.vmin + self.vmax)[self.state == BOUNDARY][
                np.all(self.boundary_index() < self.shape, axis=1)].astype(np.float32)
        return OccupancyGrid(vals, origin=self.origin, voxel_size=h, bounds=self.bounds)

    def to_mesh(self, *, refine=True, progress=None, block=None):
        """Watertight boundary mesh of the solid from this octree's BOUNDARY cells.

        See `spatial.boundary.mesh`; needs the solid (octrees from grids use
        `OccupancyGrid.to_mesh`).
        """
        if self.solid is None:
            raise ValueError("Octree.to_mesh: this octree has no solid (built from a grid); use the grid's to_mesh()")
        from .boundary import mesh_cells

        kwargs = {} if block is None else {"block": block}
        return mesh_cells(self.solid, self.origin, self.voxel_size, self.boundary_index(), cell_size=1,
                          refine=refine, progress=progress, evaluations=self.evaluations, **kwargs)
