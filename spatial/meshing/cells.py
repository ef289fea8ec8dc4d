"""The meshing pipeline over a set of boundary cells: slabs, merge, refinement."""

from __future__ import annotations

import time
import warnings

import numpy as np

from ..files.progress import progress_bar
from ..files.surface import triangle_surface
from .arrays import (DEFAULT_BLOCK, REFINE_ACCEPT, REFINE_TOL, ZERO_NUDGE, _nudge, _release_free_memory, _settle_ties,
                     _stable_order, empty_mesh, refine_scale)
from .blocks import INTERIOR, check_block as _check_block, merge_blocks
from .features import sharp_polydata_lent
from .refine import _certified, _refine_on_edges
from .kernels import place_vertices
from .slab import _SlabJob, run_slabs

__all__ = ["mesh_cells"]

#: Slabs from which ``slab_threads=2`` starts the second thread (below, its start costs more than it
#: can save).
OVERLAP_MIN_SLABS = 3


def mesh_cells(solid, origin, voxel_size, cells, *, cell_size=1, refine=True, progress=None, evaluations=0,
               block=DEFAULT_BLOCK, centre_values=None, uniform_cells=None, uniform_parents=None, node_values=None,
               features=None, stride=None, edge_ids=False, slab_threads=1, _stacklevel=2):
    """Mesh the boundary through the given cells of a lattice.

    Parameters
    ----------
    solid : Solid
    origin : (3,) float
        Position of lattice node (0, 0, 0).
    voxel_size : float
        Voxel edge ``h``; node ``(i, j, k)`` is at ``origin + (i, j, k) * h``.
    cells : (m, 3) int
        Lower corners of the cells that may hold boundary, in units of
        ``cell_size`` voxels.  Every other cell must hold samples of one strict
        sign only (FULL or EMPTY).
    cell_size : {1, 2}
        Voxels per side of a cell.
    refine, progress, block
        See `mesh`.
    features : bool or None
        Rebuild sharp edges and corners, as `mesh` does by default.  None
        (the default) is True, except with ``edge_ids=True``: the feature pass
        moves and adds vertices off the lattice edges that the ids name, so a
        mesh whose parts are fused by those ids stays plain.
    evaluations : int
        Evaluations already spent (added to the mesh's count).
    centre_values : (m,) float, optional
        The field at the cells' centres when already sampled (``cell_size``
        2 only): those nodes are not sampled again, and nodes close to a
        centre far enough from the level take its sign without being sampled.
    uniform_cells : ((k, 3) int, (k,) int8), optional
        Cells (same units) known to hold one strict sign, and that sign
        (``cell_size`` 2 only): their nodes take it without being sampled.
    uniform_parents : ((k, 3) int, (k,) int8), optional
        The same for cells twice as large (``2 * cell_size`` voxels).
    node_values : ((j, 3) int, (j,) float), optional
        Lattice nodes already sampled and their values (``cell_size`` 2
        only): reused, and their neighbours far enough from the level take
        their sign.
    stride : int, optional
        Node ids ``(x * stride + y) * stride + z`` (default: from the cells);
        give one stride to the meshes of parts of one lattice so their ids agree.
    edge_ids : bool
        Add point data ``edge_id``: the lattice edge ``3 * id + axis`` of each
        vertex (the key that fuses the meshes of neighbouring parts).
    slab_threads : {1, 2}
        2: a second thread samples the next slab while marching cubes runs
        on this one (`slab.run_slabs`), from `OVERLAP_MIN_SLABS` slabs on, and the
        refinement's chunks run on two threads; the mesh is the same, bit for bit.

    Returns
    -------
    pyvista.PolyData

    Notes
    -----
    A node's sign is all marching cubes needs unless the node ends an edge
    the surface crosses, so sampling runs in two passes: first the nodes
    whose sign is not known (from a centre value ``v`` at distance ``d`` with
    ``|v| > L d``, ``L`` the solid's Lipschitz constant, or from a uniform
    cell holding the node), then the ends of crossing edges still without a
    value.  Both passes are rigorous: an inferred sign is the true one.
    """
    t0 = time.perf_counter()
    h = float(voxel_size)
    c = int(cell_size)
    block = _check_block(block)
    origin = np.asarray(origin, dtype=np.float64)
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 3)
    if cells.shape[0] == 0:
        warnings.warn("mesh: no boundary in the region (the solid is empty there or fills it); "
                      "returning an empty mesh", RuntimeWarning, stacklevel=_stacklevel)
        return empty_mesh(h, evaluations)
    if np.any(cells < 0):
        raise ValueError("cells: expected non-negative lattice indices")
    if isinstance(slab_threads, bool) or slab_threads not in (1, 2):
        raise ValueError(f"slab_threads: expected 1 or 2, got {slab_threads!r}")
    if features is None:
        features = not edge_ids
    if not isinstance(features, (bool, np.bool_)):
        raise TypeError(f"features: expected True, False or None, got {features!r}")
    if edge_ids and features:
        raise ValueError("edge_ids: the feature pass moves and adds vertices off their lattice edges; "
                         "give edge_ids=True or features=True, not both")
    if block % c:
        raise ValueError(f"block: expected a multiple of the cell size {c}, got {block}")
    lip = float(getattr(solid, "lipschitz", np.inf))
    least = int((cells.max() + 1) * c) + 2
    if stride is not None and int(stride) < least:
        raise ValueError(f"stride: expected at least {least} for these cells, got {stride}")
    stride = np.int64(least if stride is None else int(stride))  # global node ids: (x * S + y) * S + z
    per = block // c  # cells per block side

    if centre_values is not None:
        if c != 2:
            raise ValueError("centre_values: only for cells of 2 voxels")
        centre_values = np.asarray(centre_values, dtype=np.float64).reshape(-1)
        if centre_values.shape[0] != cells.shape[0]:
            raise ValueError(f"centre_values: expected {cells.shape[0]} values, got {centre_values.shape[0]}")
    usable = np.isfinite(lip) and lip > 0  # inference needs a finite Lipschitz constant
    uniform = _by_x(uniform_cells, "uniform_cells", "signs", np.int32, np.int8, c) if usable else None
    parents = _by_x(uniform_parents, "uniform_parents", "signs", np.int32, np.int8, c) if usable else None
    known = _by_x(node_values, "node_values", "values", np.int64, np.float64, c) if usable else None
    # their x columns, contiguous for the searches below
    uniform_x, parents_x, known_x = (None if p is None else np.ascontiguousarray(p[0][:, 0])
                                     for p in (uniform, parents, known))
    if known is not None:
        kv = np.array(known[1], dtype=np.float64)
        evaluations += _settle_ties(solid, origin + known[0] * h, kv, h)
        known = (known[0], _nudge(kv, h).astype(np.float32))
        del kv
    del uniform_cells, uniform_parents, node_values
    centre_infer = usable and centre_values is not None
    # cells grouped in slabs of `block` voxels along x
    slab_of = cells[:, 0] // per
    order = _stable_order(slab_of)
    cells, slab_of = cells[order], slab_of[order]
    if centre_values is not None:
        centre_values = centre_values[order]
        evaluations += _settle_ties(solid, origin + (c * cells + c // 2) * h, centre_values, h)
        centre_values = _nudge(centre_values, h).astype(np.float32)
    del order
    slab_starts = np.flatnonzero(np.r_[True, slab_of[1:] != slab_of[:-1]])
    slab_ends = np.r_[slab_starts[1:], cells.shape[0]]

    # -- each slab's share of the classification, cut out once and dropped as its slab is done --
    # (the whole-lattice arrays would otherwise stay alive under the growing parts: at N=1024 some
    # 150 MB of the peak)
    slabs = slab_of[slab_starts].astype(np.int64)
    n_cells = int(cells.shape[0])
    pieces = [[cells[s0:s1].copy(), None if centre_values is None else centre_values[s0:s1].copy(), None, None,
               None] for s0, s1 in zip(slab_starts, slab_ends)]
    del cells, slab_of, centre_values
    for col, (pair, xs, lo, hi) in enumerate((
            (uniform, uniform_x, slabs * per - 1, (slabs + 1) * per + 1),
            (parents, parents_x, (slabs * per - 1) // 2, ((slabs + 1) * per) // 2 + 1),
            # nodes strictly inside the slab (those on its planes are shared: not worth merging)
            (known, known_x, slabs * block + 1, (slabs + 1) * block)), start=2):
        if pair is None:
            continue
        # searched in the column's own dtype: a wider query would cast the whole column
        first = np.searchsorted(xs, lo.astype(xs.dtype))
        last = np.searchsorted(xs, hi.astype(xs.dtype))
        for k in range(len(pieces)):
            pieces[k][col] = (pair[0][first[k]:last[k]].copy(), pair[1][first[k]:last[k]].copy())
        del pair, first, last
    del uniform, parents, known, uniform_x, parents_x, known_x
    _release_free_memory()

    parts = []
    n_blocks = 0
    bar = progress_bar(len(pieces), "mesh", progress, unit="slab")

    def tasks():
        for k in range(len(pieces)):
            sc, given, ring, ring_parents, extra = pieces[k]
            pieces[k] = None  # the slab's job holds what it needs
            job = _SlabJob(solid, origin, h, c, block, int(slabs[k]), stride, lip if usable else None)
            yield job, (sc, given, (ring, ring_parents), centre_infer, extra)
            del sc, given, ring, ring_parents, extra

    try:
        overlap = slab_threads == 2 and len(pieces) >= OVERLAP_MIN_SLABS
        for nb, spent in run_slabs(tasks(), parts, overlap=overlap):
            n_blocks += nb
            evaluations += spent
            bar.update()
    finally:
        bar.close()
    del pieces
    data, faces = merge_blocks(parts)
    del parts
    _release_free_memory()
    if faces.shape[0] == 0:
        warnings.warn("mesh: no surface crosses the sampled nodes (features thinner than the voxel size?); "
                      "returning an empty mesh", RuntimeWarning, stacklevel=_stacklevel)
        return empty_mesh(h, evaluations)

    # -- vertex positions: on their edge, interpolated then refined ------------------------
    # (ordered to keep few vertex-sized arrays alive at once: this is the peak of memory)
    nodes, axis, f0, f1 = data
    del data
    inner = np.flatnonzero(axis == INTERIOR)
    if inner.size:
        # a vertex inside a cube: on no edge, placed at the mean of its neighbours below
        f1[inner] = -f0[inner]
        axis[inner] = 0
    t = f0 / (f0.astype(np.float64) - f1)
    if not np.isfinite(t).all():  # never for ends of opposite signs; a guard against a field's NaN
        t = np.nan_to_num(t, nan=0.5, posinf=1.0, neginf=0.0)
        np.clip(t, 0.0, 1.0, out=t)
    if refine:
        free = ~_certified(f0, f1, h, lip)
        free[inner] = False
        rows = np.flatnonzero(free).astype(np.int32)
        del free
        # beside a tie (an end pushed ZERO_NUDGE h off the level) the stop tolerances shrink with h past
        # REFINE_FULL_N voxels across the solid (`refine_scale`): a fixed fraction of h left those vertices
        # a first-order distance off.  Elsewhere the free last step already leaves an O(h^2) error.
        scale = refine_scale(solid, h)
        if scale < 1.0 and rows.size:
            floor = np.float32(ZERO_NUDGE * h * (1 + 1e-3))
            tied = (np.abs(f0[rows]) <= floor) | (np.abs(f1[rows]) <= floor)
            spent = _refine_on_edges(solid, origin, nodes, axis, h, t, f0, f1, rows[tied], tol=REFINE_TOL * scale,
                                     accept=REFINE_ACCEPT * scale, threads=slab_threads)
            rows = rows[~tied]
            del tied
            evaluations += spent
        spent = _refine_on_edges(solid, origin, nodes, axis, h, t, f0, f1, rows, threads=slab_threads)
        evaluations += spent
        del rows
    del f0, f1
    _release_free_memory()
    if edge_ids:
        ids = ((nodes[:, 0].astype(np.int64) * stride + nodes[:, 1]) * stride + nodes[:, 2]) * 3 + axis
    p0 = place_vertices(nodes, axis, t, h, origin)
    del nodes, t, axis
    if inner.size:
        _centre_inner(p0, faces, inner)
    if features:
        # handed over, not kept: the pass frees the points once its own are made
        lent = [p0, faces]
        del p0, faces
        out = sharp_polydata_lent(solid, lent, origin, h)
    else:
        out = triangle_surface(p0, faces)
    if edge_ids:
        out.point_data["edge_id"] = ids
    out.field_data["voxel_size"] = np.array([h])
    out.field_data["evaluations"] = np.array([int(evaluations)], dtype=np.int64)
    out.field_data["boundary_cells"] = np.array([n_cells], dtype=np.int64)
    out.field_data["blocks"] = np.array([n_blocks], dtype=np.int64)
    out.field_data["seconds"] = np.array([time.perf_counter() - t0])
    return out


def _centre_inner(points, faces, inner):
    """Put the vertices `inner` (inside a cube, on no edge) at the mean of their neighbours, in place.

    Lewiner's extra vertex joins only vertices on the edges of its own cube,
    so the mean lies inside that cube, as marching cubes put it.
    """
    slot = np.full(points.shape[0], -1, dtype=np.int64)
    slot[inner] = np.arange(inner.size)
    where = slot[faces]
    f_row, corner = np.nonzero(where >= 0)
    at = where[f_row, corner]
    total = np.zeros((inner.size, 3))
    for step in (1, 2):
        np.add.at(total, at, points[faces[f_row, (corner + step) % 3]])
    count = np.bincount(at, minlength=inner.size).astype(np.float64) * 2
    points[inner] = total / np.maximum(count, 1)[:, None]


def _by_x(pair, name, what, index_type, value_type, cell_size):
    """``(indices (k, 3), per-row values)`` checked and sorted by x, or None."""
    if pair is None:
        return None
    if cell_size != 2:
        raise ValueError(f"{name}: only for cells of 2 voxels")
    idx = np.asarray(pair[0], dtype=index_type).reshape(-1, 3)
    val = np.asarray(pair[1], dtype=value_type).reshape(-1)
    if idx.shape[0] != val.shape[0]:
        raise ValueError(f"{name}: expected as many {what} as rows, got {val.shape[0]} for {idx.shape[0]}")
    order = _stable_order(idx[:, 0])
    return idx[order], val[order]
