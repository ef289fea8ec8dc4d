"""One block of cells: marching cubes as a pure function of its samples, and the merge of blocks."""

from __future__ import annotations

import numpy as np

from .arrays import _chunks_on_threads, _release_free_memory
from .kernels import part_index, remap_faces, scatter_rows
from .slab_kernels import unique_inverse

__all__ = ["mesh_block", "merge_blocks", "check_block", "INTERIOR"]


def check_block(block):
    if isinstance(block, bool) or not isinstance(block, (int, np.integer)):
        raise TypeError(f"block: expected an even integer number of voxels, got {block!r}")
    if not 2 <= block <= 256 or block % 2:
        raise ValueError(f"block: expected an even number of voxels from 2 to 256, got {block}")
    return int(block)


def mesh_block(values, mask):
    """Marching cubes of one block; vertices identified by their lattice edge.

    Parameters
    ----------
    values : (a+1, b+1, c+1) float32
        Samples at the block's lattice nodes, none exactly 0 (see `ZERO_NUDGE`).
    mask : (a+1, b+1, c+1) bool
        ``mask[i+1, j+1, k+1]`` selects the voxel with lower node ``(i, j, k)``
        (scikit-image's convention).

    Returns
    -------
    node : (v, 3) int64
        Local lower node of each vertex's edge.
    axis : (v,) int64
        Direction of the edge (0, 1, 2), or `INTERIOR` (3) for a vertex
        inside a cube (`node` is then the cube's lower node).
    f0, f1 : (v,) float32
        Samples at the edge's two ends (opposite signs).
    faces : (f, 3) int32
        Triangles as indices into the vertices, wound outward (negative
        inside).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(3, dtype=np.float32) - 0.5
    >>> vals = np.broadcast_to(x[:, None, None], (3, 3, 3)).copy()
    >>> mask = np.zeros((3, 3, 3), bool); mask[1, 1, 1] = True
    >>> node, axis, f0, f1, faces = mesh_block(vals, mask)
    >>> faces.shape, sorted(set(axis.tolist()))
    ((2, 3), [0])
    """
    verts, faces = _marching_cubes(values, mask)
    if verts is None:
        return (np.empty((0, 3), np.int64), np.empty(0, np.int64), np.empty(0, np.float32),
                np.empty(0, np.float32), np.empty((0, 3), np.int32))
    node, axis = _edges_of(verts)
    node = node.astype(np.int64)
    f0 = values[node[:, 0], node[:, 1], node[:, 2]]
    upper = node.copy()
    on_edge = np.flatnonzero(axis != INTERIOR)
    upper[on_edge, axis[on_edge]] += 1
    f1 = values[upper[:, 0], upper[:, 1], upper[:, 2]]
    return node, axis.astype(np.int64), f0, f1, faces.astype(np.int32)


def _marching_cubes(values, mask):
    """scikit-image's Lewiner marching cubes at level 0: ``(vertices, faces)``, or ``(None, None)``
    when no surface crosses the block."""
    from skimage.measure import marching_cubes

    from .saddles import break_ties      # edge and point contacts fuse wherever they fall (saddles.py)

    try:
        verts, faces, _, _ = marching_cubes(break_ties(values), 0.0, mask=mask, allow_degenerate=True)
    except (RuntimeError, ValueError):
        # No sign change in the block ('No surface found' / level out of range).
        return None, None
    return verts, faces


#: Axis code of a vertex inside a cube rather than on a lattice edge (see `_edges_of`).
INTERIOR = 3


def _edges_of(verts):
    """Lower node (int32) and axis of the lattice edge each vertex lies on.

    Marching cubes puts nearly every vertex strictly inside an edge (no sample
    is 0): two coordinates are integers, the third is the fractional one.
    Lewiner's topology-preserving cases (7, 10, 12 and 13 of its table) add
    one vertex inside the cube instead, at no lattice edge: it gets axis
    `INTERIOR` and the cube's lower node, belongs to that cube alone (never
    merged with another block's vertex) and is placed later, at the mean of
    its neighbours.  (Rounding it onto an edge gave it the id of a true edge
    vertex: zero-area triangles, and non-manifold edges where blocks meet.)
    """
    rounded = np.rint(verts)
    off = verts != rounded  # integer coordinates are exact in float32
    axis = np.argmax(np.abs(verts - rounded), axis=1)
    node = rounded.astype(np.int32)
    rows = np.arange(verts.shape[0])
    node[rows, axis] = np.floor(verts[rows, axis])
    inner = np.count_nonzero(off, axis=1) > 1
    if inner.any():
        node[inner] = np.floor(verts[inner])
        axis[inner] = INTERIOR
    return node, axis


def _unique_ids(ids):
    """``np.unique(ids, return_inverse=True)``; non-negative int64 ids (the lattice's edge ids) by a
    compiled radix sort (`slab_kernels.unique_inverse`): numpy's comparison sort was most of the merge."""
    if ids.dtype == np.int64 and (ids.size == 0 or ids.min() >= 0):
        return unique_inverse(ids)
    return np.unique(ids, return_inverse=True)


def merge_blocks(parts, threads=1, spare=0.0):
    """Merge per-block results into one indexed mesh keyed by global edge id.

    Only vertices on an edge lying in a block-grid plane can belong to two
    blocks; they are merged by their integer edge id (no floating-point
    comparison), the others are taken as they are.

    Parameters
    ----------
    parts : list of (edges, shared, data, faces)
        Per block: global edge ids ``3 * node + axis`` of its vertices that
        may be shared with another block, the boolean mask of those vertices,
        a tuple of per-vertex arrays (merged likewise; a vertex found in two
        blocks has the same data in both) and the triangles (local vertex
        indices).  The list is emptied as it is merged, so that the memory
        of the parts is released as the merged arrays fill.
    threads : int
        Parts written into the merged arrays on this many threads (compiled,
        GIL-free copies; every part has its own rows, so the result is the
        same).
    spare : float
        The triangles are the first rows of an array with this fraction more
        (and 256) rows behind them, never touched here (so they cost no
        memory until written): room for a pass that adds a few triangles in
        place (`features`).

    Returns
    -------
    data : tuple of arrays
        The per-vertex arrays of the merged vertices (non-shared first).
    faces : (f, 3) int32 (int64 beyond 2**31 vertices)
        Triangles indexing the merged vertices.
    """
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise ValueError(f"threads: expected a positive integer, got {threads!r}")
    parts[:] = [p for p in parts if p[3].shape[0]]
    if not parts:
        return None, np.empty((0, 3), np.int32)
    shared_edges = np.concatenate([p[0] for p in parts])
    uniq, inverse = _unique_ids(shared_edges)
    del shared_edges
    # each part's first face row, first private slot and first shared entry
    k_sh = np.array([int(np.count_nonzero(p[1])) for p in parts], dtype=np.int64)
    k_pr = np.array([p[1].shape[0] for p in parts], dtype=np.int64) - k_sh
    k_f = np.array([p[3].shape[0] for p in parts], dtype=np.int64)
    starts = [np.concatenate([[0], np.cumsum(k)]).tolist() for k in (k_f, k_pr, k_sh)]
    n_private = int(starts[1][-1])
    n_total = n_private + uniq.shape[0]
    del uniq
    itype = np.int32 if n_total < 2 ** 31 else np.int64
    data = [np.empty((n_total,) + arr.shape[1:], dtype=arr.dtype) for arr in parts[0][2]]
    n_f = int(starts[0][-1])
    faces = np.empty((n_f + (int(n_f * spare) + 256 if spare else 0), 3), dtype=itype)[:n_f]

    def work(a, b):
        for i in range(a, b):
            _, sh, pdata, pfaces = parts[i]
            parts[i] = None
            index = np.empty(sh.shape[0], dtype=itype)
            part_index(sh, inverse, starts[2][i], starts[1][i], n_private, index)
            for out, arr in zip(data, pdata):
                scatter_rows(out, index, np.ascontiguousarray(arr))
            remap_faces(index, pfaces, faces, starts[0][i])
            del sh, pdata, pfaces, index
            _release_free_memory()  # the part's pages back to the system as the merged arrays fill

    # one part per task: two threads write disjoint rows (a vertex two parts share gets the same data
    # from both)
    _chunks_on_threads(work, len(parts), 1, threads=threads)
    parts.clear()
    return tuple(data), faces
