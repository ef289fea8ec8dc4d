"""Octree cell decomposition of a solid: leaves as flat arrays, FULL / EMPTY / BOUNDARY.

See `spatial.cells.lattice` for the lattice and its conservative classification.
"""

from __future__ import annotations

import numpy as np

from .lattice import (BOUNDARY, EMPTY, FULL, STATE_NAMES, Lattice, _check_bounds, _check_solid,  # noqa: F401
                      check_dense_memory, descend, make_lattice, provided)

__all__ = ["Octree"]



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
        return provided("OccupancyGrid")(vals, origin=self.origin, voxel_size=h, bounds=self.bounds)

    def to_mesh(self, *, refine=True, progress=None, block=None, features=True):
        """Watertight boundary mesh of the solid from this octree's BOUNDARY cells.

        See `spatial.meshing.mesh`; needs the solid (octrees from grids use
        `OccupancyGrid.to_mesh`).  As there, sharp edges and corners are
        rebuilt by default (`features=False`: the plain marching-cubes mesh).

        Examples
        --------
        >>> from implicit import box
        >>> m = Octree.from_solid(box(1.0), resolution=8).to_mesh()
        >>> int((m.point_data["feature_rank"] == 3).sum())
        8
        """
        if self.solid is None:
            raise ValueError("Octree.to_mesh: this octree has no solid (built from a grid); use the grid's to_mesh()")
        mesh_cells = provided("mesh_cells")
        kwargs = {} if block is None else {"block": block}
        return mesh_cells(self.solid, self.origin, self.voxel_size, self.boundary_index(), cell_size=1,
                          refine=refine, progress=progress, evaluations=self.evaluations, features=features,
                          **kwargs)
