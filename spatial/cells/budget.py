"""Memory budgets of surface meshes and tetrahedral meshes, estimated before any work.

A boundary mesh costs memory in proportion to the surface it meshes, not to
the lattice's volume; before sampling anything the only surface known is the
bounding box's, and the box's area over ``h^2`` is what a boxy part's
triangles follow (the benchmark part at N = 1024: 14.9 M triangles for
6.3 M box-area cells, 2.4 per cell, peak about 56 bytes per triangle beyond
the imports).  `estimate_mesh_bytes` takes that with a margin of two;
`check_mesh_memory` refuses a request whose estimate exceeds
`lattice.MEMORY_FRACTION` of the available memory, at once, instead of
growing for minutes until the allocator gives up.  `check_tet_memory` does
the same for tetrahedra of a target edge length.
"""

from __future__ import annotations

import numpy as np

from .lattice import MEMORY_FRACTION, available_memory

__all__ = ["estimate_mesh_bytes", "check_mesh_memory", "estimate_tet_bytes", "check_tet_memory"]

#: Triangles per ``h^2`` of bounding-box area (measured 2.4 on the benchmark part).
TRIANGLES_PER_CELL = 2.5
#: Peak bytes per triangle of the boundary mesher (measured about 56; margin 2).
BYTES_PER_TRIANGLE = 120.0
#: Tetrahedra per ``size^3`` of volume (a regular tetrahedron holds 0.118 size^3;
#: TetGen's quality meshes of the benchmark part hold about 14).
TETS_PER_CELL = 15.0
#: Peak bytes per tetrahedron of TetGen and the quality passes, with margin.
BYTES_PER_TET = 400.0


def _box(bounds):
    lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
    if lo.shape != (3,) or hi.shape != (3,) or not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise ValueError(f"bounds: expected two finite 3-vectors, got {bounds!r}")
    return np.maximum(hi - lo, 0.0)


def estimate_mesh_bytes(bounds, voxel_size) -> float:
    """Peak bytes of a boundary mesh of a part in `bounds` at cell size `voxel_size`.

    Examples
    --------
    >>> round(estimate_mesh_bytes(([0, 0, 0], [1, 1, 1]), 0.01) / 1e6, 1)
    18.0
    """
    d = _box(bounds)
    h = float(voxel_size)
    area = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    # never more triangles than cells in the box (the lattice's volume bound)
    cells = min(area / (h * h), float(np.prod(np.ceil(d / h) + 2.0)))
    return TRIANGLES_PER_CELL * cells * BYTES_PER_TRIANGLE


def _refuse(need, what, detail, advice, max_bytes):
    avail = available_memory()
    limit = MEMORY_FRACTION * avail if max_bytes is None else float(max_bytes)
    if need > limit:
        raise MemoryError(f"{what}: {detail} needs about {need / 1e9:.3g} GB, more than the {limit / 1e9:.3g} GB "
                          f"allowed ({avail / 1e9:.3g} GB available); {advice}")
    return need


def check_mesh_memory(bounds, voxel_size, *, what="mesh", max_bytes=None) -> float:
    """Refuse a boundary mesh that would not fit in memory; return the estimate (bytes).

    Raises
    ------
    MemoryError
        Naming the estimate, the memory available and the voxel size that fits.
    """
    need = estimate_mesh_bytes(bounds, voxel_size)
    limit = MEMORY_FRACTION * available_memory() if max_bytes is None else float(max_bytes)
    fits = float(voxel_size) * np.sqrt(need / max(limit, 1.0))
    return _refuse(need, what, f"a boundary mesh at voxel size {float(voxel_size):.3g}",
                   f"use a voxel size of at least {fits:.3g} (or fewer cells)", max_bytes)


def estimate_tet_bytes(bounds, size) -> float:
    """Peak bytes of tetrahedra of edge `size` filling the box `bounds`."""
    d = _box(bounds)
    s = float(size)
    return TETS_PER_CELL * float(np.prod(d / s)) * BYTES_PER_TET


def check_tet_memory(bounds, size, *, what="fea", max_bytes=None) -> float:
    """Refuse a tetrahedral mesh that would not fit in memory; return the estimate (bytes).

    The surface it starts from is checked as well (voxels of ``size / 4``).
    """
    check_mesh_memory(bounds, float(size) / 4.0, what=what, max_bytes=max_bytes)
    need = estimate_tet_bytes(bounds, size)
    limit = MEMORY_FRACTION * available_memory() if max_bytes is None else float(max_bytes)
    fits = float(size) * (need / max(limit, 1.0)) ** (1.0 / 3.0)
    return _refuse(need, what, f"tetrahedra of size {float(size):.3g}",
                   f"use a size of at least {fits:.3g}", max_bytes)
