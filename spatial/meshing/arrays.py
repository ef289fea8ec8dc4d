"""Constants of the meshing room and the array helpers its stages share."""

from __future__ import annotations

import numpy as np

__all__ = ["ZERO_NUDGE", "DEFAULT_BLOCK", "REFINE_STEPS", "REFINE_TOL", "REFINE_ACCEPT", "REFINE_FULL_N",
           "CLASSIFY_CHUNK", "EVAL_CHUNK", "empty_mesh", "faces_array", "refine_scale"]

#: Samples closer to the level than ``ZERO_NUDGE * h`` are pushed to that distance (sign kept, 0 -> +).
ZERO_NUDGE = 1e-3
#: Samples within ``ZERO_TIE * h`` of 0 are ties (0 up to rounding), settled by the regularized solid
#: (`_settle_ties`); far above the rounding of an evaluation, far below ``ZERO_NUDGE``.
ZERO_TIE = 1e-7
#: Voxels per side of a meshing block.
DEFAULT_BLOCK = 32
#: At most this many regula-falsi steps move vertices onto the surface along their edge.
REFINE_STEPS = 6
#: A vertex stops moving once ``|f| <= REFINE_TOL * h``.
REFINE_TOL = 1e-4
#: A vertex with ``|f| <= REFINE_ACCEPT * h`` takes one more regula-falsi step without a further
#: evaluation: the step shrinks the error by about the curvature times h (a thousandth here).
REFINE_ACCEPT = 2e-3
#: The refinement's stop tolerances `REFINE_TOL` and `REFINE_ACCEPT` hold (in voxels) up to this many voxels
#: across the solid; finer, beside ties, they shrink with the voxel (`refine_scale`), so that the distance a
#: stopped vertex may keep from the surface falls as h^2.  A fixed fraction of h left a first-order volume
#: error on faces lying in lattice planes, -2.6e-3 / N on the benchmark part: beside a node whose sample was a
#: tie, pushed `ZERO_NUDGE` h off the level, the vertex's first value is about that nudge, within
#: `REFINE_ACCEPT` h, and its last free step leaves it about half the nudge inside.  Only those vertices (an end within the nudge)
#: take the scaled tolerances: elsewhere the free last step already leaves an O(h^2) error.
REFINE_FULL_N = 128
#: Boxes bounded per call while descending (caps the memory of the classification).
CLASSIFY_CHUNK = 1 << 18
#: Points evaluated per call (caps the memory of an evaluation).
EVAL_CHUNK = 1 << 18


def refine_scale(solid, h):
    """Factor on `REFINE_TOL` and `REFINE_ACCEPT` at voxel `h`: ``min(1, REFINE_FULL_N h / L)``.

    ``L`` is the longest side of the solid's bounds (1 for an unbounded solid:
    its mesh is a clipped region, and the tolerances stay as they are).  The
    solid's own size, not the region's, so that the bricks of a cluster's mesh
    refine as the single process does.

    Examples
    --------
    >>> from implicit import sphere
    >>> refine_scale(sphere(1.0), 2.0 / 64), refine_scale(sphere(1.0), 2.0 / 512)
    (1.0, 0.25)
    """
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    size = float(np.max(hi - lo))
    if not np.isfinite(size) or size <= 0:
        return 1.0
    return min(1.0, REFINE_FULL_N * float(h) / size)


def empty_mesh(voxel_size=0.0, evaluations=0):
    """An empty `pyvista.PolyData` with the usual field data (arrays inside `spatial.files.surface.arrays_only`)."""
    from ..files.surface import TriangleArrays, arrays_wanted

    if arrays_wanted():
        out = TriangleArrays(np.zeros((0, 3)), np.zeros((0, 3), np.int64))
    else:
        import pyvista as pv

        out = pv.PolyData()
    out.field_data["voxel_size"] = np.array([float(voxel_size)])
    out.field_data["evaluations"] = np.array([int(evaluations)], dtype=np.int64)
    return out


def faces_array(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) and triangles (m, 3) of a PolyData, refusing other cells."""
    import pyvista as pv  # local: heavy import

    if not isinstance(mesh, pv.PolyData):
        raise TypeError(f"mesh: expected a pyvista.PolyData, got {type(mesh).__name__}")
    if mesh.n_cells == 0 or mesh.n_points == 0:
        raise ValueError("mesh: expected a closed triangle mesh, got an empty mesh")
    if mesh.n_lines or mesh.n_verts or mesh.n_strips:
        raise ValueError("mesh: expected triangles only, got lines, vertices or strips (call .triangulate())")
    if not mesh.is_all_triangles:
        raise ValueError("mesh: expected triangles only, got other polygons (call .triangulate())")
    points = np.asarray(mesh.points, dtype=np.float64)
    tri = np.asarray(mesh.faces).reshape(-1, 4)[:, 1:].astype(np.int64)
    return points, tri


def _nudge(values, h):
    """Push samples within ``ZERO_NUDGE * h`` of 0 to that distance, keeping the sign (0 -> +; NaN, a
    field undefined there, -> + too: marching cubes needs a number at every node)."""
    eps = ZERO_NUDGE * h
    out = np.asarray(values, dtype=np.float64)
    small = ~(np.abs(out) >= eps)
    out[small] = np.where(out[small] < 0, -eps, eps)
    return out


_SIX = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)


def _settle_ties(solid, pts, values, h):
    """Decide samples at 0 (up to rounding) by the regularized solid, in place; returns evaluations.

    A CSG fold is exactly 0 where the solid's set is not regular: ``min(a,
    b)`` on the face two solids share, ``max(a, -b)`` on the face a
    difference cuts flush.  Requicha's regularized set is the closure of the
    interior, so such a point belongs to the solid exactly when no point
    close by is strictly outside.  A tie is probed at ``ZERO_NUDGE * h``
    along the six axis directions: outside (pushed to ``+ZERO_NUDGE * h``)
    when one probe is above ``ZERO_TIE * h``, inside (``-ZERO_NUDGE * h``)
    otherwise.  A face of the solid lying on a lattice plane is outside, as
    before; a face two solids share is inside, so a boss standing on its
    plate is one body; a flush cut leaves no skin.  The probes follow the
    lattice's axes, so the same tie gets the same answer in every block.
    Ties on the faces of the solid's bounds are outside without probes.
    """
    # (two compiled passes around the probes' evaluation: the thread preparing the next slab keeps
    # no numpy temporaries and lets the interpreter's lock go)
    from .cells_kernels import settle_probed, tie_probes

    work = values if values.dtype == np.float64 and values.flags.c_contiguous else \
        np.ascontiguousarray(values, dtype=np.float64)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    limit, eps = ZERO_TIE * h, ZERO_NUDGE * h
    tie, probe = tie_probes(work, np.ascontiguousarray(pts, dtype=np.float64), lo + ZERO_TIE * h,
                            hi - ZERO_TIE * h, limit, eps, (ZERO_NUDGE * h) * _SIX)
    if tie.size:
        near = _evaluate(solid, probe).reshape(-1)
        settle_probed(work, tie, np.ascontiguousarray(near, dtype=np.float64), limit, eps)
    if work is not values:
        values[...] = work
    return int(probe.shape[0])


def _evaluate(solid, pts, chunk=EVAL_CHUNK):
    """The solid's values at `pts` (n, 3), evaluated in chunks to cap temporary memory."""
    n = pts.shape[0]
    if n <= chunk:
        return solid(pts)
    out = np.empty(n)
    for a in range(0, n, chunk):
        out[a:a + chunk] = solid(pts[a:a + chunk])
    return out


def _chunks_on_threads(work, n, chunk=EVAL_CHUNK, threads=2):
    """``work(a, b)`` for the chunks ``[a, b)`` of ``range(n)``, on `threads` threads when there are
    several chunks (the compiled evaluation releases the interpreter's lock).  The chunks are the
    ones a single thread would take, so every call -- and every value -- is the same."""
    spans = [(a, min(a + chunk, n)) for a in range(0, n, chunk)]
    if threads < 2 or len(spans) < 2:
        for a, b in spans:
            work(a, b)
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=threads, thread_name_prefix="implicad-eval") as pool:
        for future in [pool.submit(work, a, b) for a, b in spans]:
            future.result()


def _stable_order(keys):
    """``np.argsort(keys, kind="stable")``; keys below 2**16 go through 16 bits, where numpy's
    stable sort is a radix sort (several times faster on the lattice's indices)."""
    if keys.shape[0] and 0 <= keys.min() and keys.max() < 1 << 16:
        keys = keys.astype(np.uint16)
    return np.argsort(keys, kind="stable")


def _release_free_memory():
    """Hand the heap pages freed by the slabs and parts back to the system (glibc only).

    The slabs' temporaries and the merged parts leave the heap fragmented; the
    vertex stage that follows would otherwise add its arrays on top of it.
    """
    global _MALLOC_TRIM
    if _MALLOC_TRIM is None:
        try:
            import ctypes

            _MALLOC_TRIM = ctypes.CDLL("libc.so.6").malloc_trim
        except (OSError, AttributeError):
            _MALLOC_TRIM = False
    if _MALLOC_TRIM:
        _MALLOC_TRIM(0)


_MALLOC_TRIM = None


def _repeat2(arr, axis):
    """``np.repeat(arr, 2, axis)`` for one-byte arrays; along the last axis each byte is doubled
    through a 16-bit view, ten times faster than `np.repeat` there."""
    if axis in (-1, arr.ndim - 1) and arr.dtype.itemsize == 1:
        wide = np.ascontiguousarray(arr).view(np.uint8).astype(np.uint16)
        wide *= 257
        return wide.view(arr.dtype).reshape(arr.shape[:-1] + (2 * arr.shape[-1],))
    return np.repeat(arr, 2, axis=axis)
