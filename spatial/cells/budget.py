"""Memory budgets of surface meshes and tetrahedral meshes, estimated before any work.

A boundary mesh costs memory in proportion to the surface it meshes, not to
the lattice's volume; before sampling anything the only surface known is the
bounding box's, and the box's area over ``h^2`` is what a boxy part's
triangles follow (the benchmark part: 2.36 triangles per box-area cell at
N = 256 to 2048).  The memory the mesh adds to the process, its peak resident
size less what the interpreter, the modules and the compiled kernels hold, was
measured (``ru_maxrss``) on the benchmark part at N = 256, 512, 1024 and 2048,
the plain mesh and the one with sharp features, and fitted within 1.3 % by
``a + b t + c sqrt(t)`` bytes for ``t`` triangles (`PLAIN_FIT`,
`FEATURES_FIT`; the square-root term: what grows with the slabs, not their
area); `estimate_mesh_bytes` takes the fit with `MARGIN`, so that its
estimate of that part lies between 1 and 1.3 times what it uses at N = 1024
and 2048, 1.5 at N = 256 and 512 where runs vary more
(tests/cells/test_budget.py measures them).
`check_mesh_memory` refuses a request whose estimate exceeds
`lattice.MEMORY_FRACTION` of the available memory, at once, instead of
growing for minutes until the allocator gives up.  `check_tet_memory` does
the same for tetrahedra of a target edge length.
"""

from __future__ import annotations

import math

import numpy as np

from .lattice import MEMORY_FRACTION, available_memory

__all__ = ["estimate_mesh_bytes", "check_mesh_memory", "estimate_tet_bytes", "check_tet_memory"]

#: Triangles per ``h^2`` of bounding-box area (measured 2.36 on the benchmark part).
TRIANGLES_PER_CELL = 2.5
#: Bytes the plain mesh (``features=False``) adds for ``t`` triangles: ``a + b t + c sqrt(t)``
#: (benchmark part, N = 256 to 2048: 87 MB to 2.15 GB).
PLAIN_FIT = (1.7e6, 26.4, 60.0e3)
#: The same with sharp features rebuilt (the default; 86 MB to 3.79 GB: the feature pass holds
#: about 31 bytes more per triangle).  Never below the plain mesh's estimate: the larger of the
#: two is taken.
FEATURES_FIT = (3.7e6, 57.4, 21.6e3)
#: The estimate over the fit: above the spread of one run to the next (up to 12 % either way at
#: N = 256 and 512, where the slab pipeline's timing decides which arrays meet at the peak), so
#: that the benchmark part's meshes use between 1 / 1.3 and all of the estimate at N = 1024 and 2048
#: (1 / 1.5 at N = 256 and 512 on a loaded machine).
MARGIN = 1.18
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


def estimate_mesh_bytes(bounds, voxel_size, *, features=True) -> float:
    """Bytes a boundary mesh of a part in `bounds` at cell size `voxel_size` adds to the process at
    its peak (`features`: with sharp features rebuilt, as `spatial.mesh` does by default).

    Examples
    --------
    >>> round(estimate_mesh_bytes(([0, 0, 0], [1, 1, 1]), 0.01, features=False) / 1e6, 1)
    34.1
    """
    d = _box(bounds)
    h = float(voxel_size)
    area = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    # never more triangles than cells in the box (the lattice's volume bound)
    cells = min(area / (h * h), float(np.prod(np.ceil(d / h) + 2.0)))
    t = TRIANGLES_PER_CELL * cells

    def fit(p):
        return p[0] + p[1] * t + p[2] * math.sqrt(t)

    need = fit(PLAIN_FIT)
    if features:
        need = max(need, fit(FEATURES_FIT))
    return MARGIN * need


def _refuse(need, what, detail, advice, max_bytes):
    avail = available_memory()
    limit = MEMORY_FRACTION * avail if max_bytes is None else float(max_bytes)
    if need > limit:
        raise MemoryError(f"{what}: {detail} needs about {need / 1e9:.3g} GB, more than the {limit / 1e9:.3g} GB "
                          f"allowed ({avail / 1e9:.3g} GB available); {advice}")
    return need


def check_mesh_memory(bounds, voxel_size, *, what="mesh", max_bytes=None, features=True) -> float:
    """Refuse a boundary mesh that would not fit in memory; return the estimate (bytes,
    `estimate_mesh_bytes`).

    Raises
    ------
    MemoryError
        Naming the estimate, the memory available and the voxel size that fits.
    """
    need = estimate_mesh_bytes(bounds, voxel_size, features=features)
    limit = MEMORY_FRACTION * available_memory() if max_bytes is None else float(max_bytes)
    # as if the need went as 1 / h^2: it grows slower, so this voxel fits
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
