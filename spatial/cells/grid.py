"""Spatial-occupancy grids: a regular lattice of voxels with sampled distances.

An `OccupancyGrid` holds the signed distance of a solid sampled at the CENTRES
of the voxels of a regular lattice: voxel ``(i, j, k)`` covers
``origin + [i, i+1] x [j, j+1] x [k, k+1] * voxel_size`` and its sample sits at
``origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size``.  ``occupancy`` is
``distance <= 0``.

Grids are dense (memory grows with the volume); before allocating one the
memory is estimated and a grid that does not fit is refused with the estimate
and the octree alternative (`spatial.Octree`, `spatial.mesh`), whose cost
follows the surface.
"""

from __future__ import annotations

import numpy as np

from ..files.progress import progress_bar
from .lattice import (BOUNDARY, EMPTY, FULL, available_memory, check_dense_memory,  # noqa: F401
                      make_lattice, provide, provided)
from .octree import Octree

__all__ = ["OccupancyGrid", "check_dense_memory", "available_memory"]

# Half the diagonal of a unit cube: a voxel whose |distance| exceeds this (in voxels) holds no boundary.
_HALF_DIAG = 0.5 * np.sqrt(3.0)


class OccupancyGrid:
    """Signed distances sampled at voxel centres, and the occupancy they imply.

    Parameters
    ----------
    distance : (nx, ny, nz) array_like
        Signed distances at the voxel centres (stored as float32).
    origin : (3,) array_like
        Lower corner of voxel (0, 0, 0).
    voxel_size : float
        Voxel edge ``h``.
    bounds : (lo, hi), optional
        Region of interest the grid was made for (default: the grid's box).

    Attributes
    ----------
    distance : (nx, ny, nz) float32
    occupancy : (nx, ny, nz) bool
        ``distance <= 0``.
    origin : (3,) float64
    voxel_size : float
    shape : tuple of 3 int

    Examples
    --------
    >>> from implicit import sphere
    >>> grid = OccupancyGrid.from_solid(sphere(1.0), resolution=40)
    >>> abs(grid.volume(method="fraction") - 4.18879) < 0.01
    True
    """

    def __init__(self, distance, *, origin=(0.0, 0.0, 0.0), voxel_size=1.0, bounds=None):
        d = np.asarray(distance)
        if d.ndim != 3:
            raise ValueError(f"distance: expected a 3-d array, got shape {d.shape}")
        if not np.issubdtype(d.dtype, np.number):
            raise TypeError(f"distance: expected numbers, got dtype {d.dtype}")
        self.distance = np.ascontiguousarray(d, dtype=np.float32)
        self.origin = np.asarray(origin, dtype=np.float64).reshape(3)
        self.voxel_size = float(voxel_size)
        if not self.voxel_size > 0:
            raise ValueError(f"voxel_size: expected a positive number, got {voxel_size!r}")
        self.shape = tuple(int(v) for v in self.distance.shape)
        top = self.origin + np.array(self.shape) * self.voxel_size
        self.bounds = bounds if bounds is not None else (self.origin.copy(), top)

    # -- construction ---------------------------------------------------------
    @classmethod
    def from_solid(cls, solid, *, voxel_size=None, resolution=None, bounds=None, progress=None,
                   max_bytes=None) -> "OccupancyGrid":
        """Sample `solid` at the voxel centres of a lattice covering its bounds.

        The lattice is the one `Octree.from_solid` uses for the same arguments
        (padded by one voxel on each side), so grids and octrees of one solid
        line up.

        Parameters
        ----------
        solid : Solid
        voxel_size, resolution : float / int
            Exactly one: voxel edge, or voxels across the longest side.
        bounds : (lo, hi), optional
            Region (default: the solid's bounds); the solid is clipped to it.
        progress : bool or None
            Progress bar (None: only on a terminal).
        max_bytes : int, optional
            Memory limit (default: a fraction of the available memory).

        Raises
        ------
        MemoryError
            When the dense grid would not fit (before any sampling).
        """
        lattice = make_lattice(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds)
        if lattice.empty:
            raise ValueError("solid: it is empty (its bounds enclose nothing); pass bounds= to sample a region")
        n = tuple(int(v) for v in lattice.shape)
        # float32 distances, plus a bool occupancy when the caller asks for it
        check_dense_memory(n, bytes_per_voxel=5, what="OccupancyGrid.from_solid", max_bytes=max_bytes)
        h = lattice.voxel_size
        dist = np.empty(n, dtype=np.float32)
        jk = np.stack(np.meshgrid(np.arange(n[1]), np.arange(n[2]), indexing="ij"), axis=-1).reshape(-1, 2)
        yz = lattice.origin[1:] + (jk + 0.5) * h
        slab = max(1, int(2_000_000 // max(yz.shape[0], 1)))
        pts = np.empty((slab, yz.shape[0], 3))
        pts[:, :, 1:] = yz
        with progress_bar(n[0], "sample", progress, unit="slab") as bar:
            for i0 in range(0, n[0], slab):
                i1 = min(i0 + slab, n[0])
                p = pts[: i1 - i0]
                p[:, :, 0] = (lattice.origin[0] + (np.arange(i0, i1) + 0.5) * h)[:, None]
                dist[i0:i1] = lattice.solid(p).reshape(i1 - i0, n[1], n[2])
                bar.update(i1 - i0)
        return cls(dist, origin=lattice.origin, voxel_size=h, bounds=lattice.bounds)

    # -- views ------------------------------------------------------------------
    @property
    def occupancy(self) -> np.ndarray:
        """Boolean occupancy ``distance <= 0``, shape `shape`."""
        return self.distance <= 0

    @property
    def centres(self) -> np.ndarray:
        """Sample positions, shape ``(nx, ny, nz, 3)`` (allocates)."""
        idx = np.indices(self.shape, dtype=np.float64).transpose(1, 2, 3, 0)
        return self.origin + (idx + 0.5) * self.voxel_size

    @property
    def nbytes(self) -> int:
        return int(self.distance.nbytes)

    def __repr__(self) -> str:
        return (f"OccupancyGrid(shape={self.shape}, voxel_size={self.voxel_size:g}, "
                f"origin={np.round(self.origin, 6).tolist()}, occupied={int(self.occupancy.sum())})")

    # -- boolean algebra on one lattice --------------------------------------------
    def _same_lattice(self, other, op):
        if not isinstance(other, OccupancyGrid):
            raise TypeError(f"grid {op} other: expected an OccupancyGrid, got {type(other).__name__}")
        if (self.shape != other.shape or self.voxel_size != other.voxel_size
                or not np.allclose(self.origin, other.origin, rtol=0, atol=1e-9 * self.voxel_size)):
            raise ValueError(
                f"grid {op} other: the grids must share one lattice (shape, origin, voxel_size); got "
                f"{self.shape}, {self.origin.tolist()}, {self.voxel_size:g} and "
                f"{other.shape}, {other.origin.tolist()}, {other.voxel_size:g}; sample both solids with the "
                "same bounds= and voxel_size="
            )

    def _new(self, distance):
        return OccupancyGrid(distance, origin=self.origin, voxel_size=self.voxel_size, bounds=self.bounds)

    def __or__(self, other):
        self._same_lattice(other, "|")
        return self._new(np.minimum(self.distance, other.distance))

    def __and__(self, other):
        self._same_lattice(other, "&")
        return self._new(np.maximum(self.distance, other.distance))

    def __sub__(self, other):
        self._same_lattice(other, "-")
        return self._new(np.maximum(self.distance, -other.distance))

    def __invert__(self):
        return self._new(-self.distance)

    def __bool__(self):
        raise TypeError("the truth value of an OccupancyGrid is ambiguous; use grid.occupancy.any()")

    # -- measures -----------------------------------------------------------------
    def volume(self, method: str = "count") -> float:
        """Volume of the occupied region.

        Parameters
        ----------
        method : {"count", "fraction"}
            ``count``: occupied voxels times ``h**3`` (error of order h).
            ``fraction``: each voxel counts ``clamp(0.5 - d/h, 0, 1)`` of its
            volume (error about h**2 for exact distances).
        """
        h3 = self.voxel_size ** 3
        if method == "count":
            return float(np.count_nonzero(self.distance <= 0)) * h3
        if method == "fraction":
            frac = np.clip(0.5 - self.distance.astype(np.float64) / self.voxel_size, 0.0, 1.0)
            return float(frac.sum()) * h3
        raise ValueError(f"method: expected 'count' or 'fraction', got {method!r}")

    # -- conversions ----------------------------------------------------------------
    def to_solid(self):
        """A `implicit.fields.GridSolid` interpolating these samples trilinearly."""
        from implicit.fields import GridSolid

        return GridSolid(self.distance, origin=self.origin + 0.5 * self.voxel_size, voxel_size=self.voxel_size)

    def to_mesh(self):
        """Closed, outward-oriented marching-cubes mesh of the samples (dense).

        The grid is padded by one outside sample, so occupancy touching the
        grid's border still closes; samples at exactly 0 are nudged outwards
        (`spatial.meshing.grid_mesh`).

        Returns
        -------
        pyvista.PolyData
        """
        return provided("grid_mesh")(self)

    def cell_states(self) -> np.ndarray:
        """Per-voxel state: BOUNDARY where ``|d| <= sqrt(3)/2 h`` (the voxel may hold
        boundary for a 1-Lipschitz field), else FULL / EMPTY by sign; uint8."""
        band = _HALF_DIAG * self.voxel_size
        st = np.where(self.distance < 0, FULL, EMPTY).astype(np.uint8)
        st[np.abs(self.distance) <= band] = BOUNDARY
        return st

    def to_octree(self) -> Octree:
        """Octree of the voxels' states, merging uniform 2x2x2 blocks bottom-up.

        Voxel states come from `cell_states`; the grid is padded to ``2**depth``
        voxels per side with EMPTY voxels.  Leaves carry conservative value
        ranges ``d -/+ sqrt(3)/2 h`` (min / max over merged blocks).
        """
        h = self.voxel_size
        n = max(self.shape)
        depth = int(np.ceil(np.log2(max(n, 1))))
        side = 1 << depth
        pad = [(0, side - s) for s in self.shape]
        band = _HALF_DIAG * h
        st = np.pad(self.cell_states(), pad, constant_values=EMPTY)
        lo_v = np.pad(self.distance - np.float32(band), pad, constant_values=np.inf)
        hi_v = np.pad(self.distance + np.float32(band), pad, constant_values=np.inf)
        mixed = np.uint8(3)
        levels = [(st, lo_v, hi_v)]
        for _ in range(depth):
            s, a, b = levels[-1]
            m = s.shape[0] // 2
            blk = s.reshape(m, 2, m, 2, m, 2)
            mn = blk.min(axis=(1, 3, 5))
            mx = blk.max(axis=(1, 3, 5))
            parent = np.where((mn == mx) & (mn != BOUNDARY) & (mn != mixed), mn, mixed).astype(np.uint8)
            levels.append((parent, a.reshape(m, 2, m, 2, m, 2).min(axis=(1, 3, 5)),
                           b.reshape(m, 2, m, 2, m, 2).max(axis=(1, 3, 5))))
        levels.reverse()  # levels[l] has 2**l cells per side
        index, state, level, vmin, vmax = [], [], [], [], []
        for lev, (s, a, b) in enumerate(levels):
            if lev == 0:
                leaf = s != mixed
            else:
                parent_mixed = levels[lev - 1][0] == mixed
                up = parent_mixed.repeat(2, 0).repeat(2, 1).repeat(2, 2)
                leaf = up & (s != mixed) if lev < depth else up
            ijk = np.argwhere(leaf)
            index.append(ijk << (depth - lev))
            state.append(s[leaf])
            level.append(np.full(ijk.shape[0], lev, np.uint8))
            vmin.append(a[leaf].astype(np.float64))
            vmax.append(b[leaf].astype(np.float64))
        return Octree(index=np.concatenate(index), state=np.concatenate(state), level=np.concatenate(level),
                      vmin=np.concatenate(vmin), vmax=np.concatenate(vmax), origin=self.origin, voxel_size=h,
                      depth=depth, shape=np.array(self.shape), bounds=self.bounds, solid=None)


provide("OccupancyGrid", OccupancyGrid)
