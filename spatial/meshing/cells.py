"""The meshing pipeline over a set of boundary cells: slabs, merge, refinement."""

from __future__ import annotations

import time
import warnings

import numpy as np

from ..files.progress import progress_bar
from ..files.surface import triangle_surface
from .arrays import (DEFAULT_BLOCK, EVAL_CHUNK, REFINE_ACCEPT, REFINE_TOL, ZERO_NUDGE, ZERO_TIE, _chunks_on_threads,
                     _release_free_memory, _settle_ties, _stable_order, empty_mesh, refine_scale)
from .blocks import INTERIOR, check_block as _check_block, merge_blocks
from .features import FACE_ROOM, point_room, sharp_polydata_lent
from .refine import _refine_on_edges
from .cells_kernels import (min_max, min_max_rows, order_by_key, stage_counts, stage_fill, take_entries, take_nudged,
                            take_rows, ties)
from .kernels import place_rows
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
    cells = _index_rows(cells, np.int64)
    if cells.shape[0] == 0:
        warnings.warn("mesh: no boundary in the region (the solid is empty there or fills it); "
                      "returning an empty mesh", RuntimeWarning, stacklevel=_stacklevel)
        return empty_mesh(h, evaluations)
    lowest, highest = min_max_rows(cells)
    if lowest < 0:
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
    least = int((highest + 1) * c) + 2
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
    # the rings' rows checked (they are cut out slab by slab below, after the cells)
    rings = [_ring(pair, name, what, np.int32 if name != "node_values" else np.int64, vtype, c) if usable else None
             for pair, name, what, vtype in ((uniform_cells, "uniform_cells", "signs", np.int8),
                                             (uniform_parents, "uniform_parents", "signs", np.int8),
                                             (node_values, "node_values", "values", np.float64))]
    del uniform_cells, uniform_parents, node_values
    centre_infer = usable and centre_values is not None
    eps = ZERO_NUDGE * h
    # cells grouped in slabs of `block` voxels along x: a counting sort by slab (the stable order)
    first_slab, last_slab = (int(v) // per for v in min_max(cells[:, 0]))
    order, starts = order_by_key(cells[:, 0], per, first_slab, last_slab - first_slab + 1)
    if centre_values is not None:
        # ties settled in the slabs' order, as every sample of a slab is (the values of a copy)
        tie = ties(centre_values, ZERO_TIE * h)
        if tie.size:
            tie = tie[_stable_order(cells[tie, 0] // per)]
            settled = centre_values[tie]
            evaluations += _settle_ties(solid, origin + (c * cells[tie].astype(np.int64) + c // 2) * h, settled, h)
            centre_values = centre_values.copy()
            centre_values[tie] = settled
            del settled
        del tie
    slabs = np.flatnonzero(starts[1:] > starts[:-1])
    spans = [(int(starts[k]), int(starts[k + 1])) for k in slabs]
    slabs = (slabs + first_slab).astype(np.int64)
    n_cells = int(cells.shape[0])

    # -- the rings sorted along x once (the nodes' ties settled in that order) --------------
    sorted_rings = [None, None, None]
    for col, (ring, lo, hi) in enumerate((
            (rings[0], slabs * per - 1, (slabs + 1) * per + 1),
            (rings[1], (slabs * per - 1) // 2, ((slabs + 1) * per) // 2 + 1),
            # nodes strictly inside the slab (those on its planes are shared: not worth merging)
            (rings[2], slabs * block + 1, (slabs + 1) * block)), start=2):
        if ring is None:
            continue
        idx, val, itype = ring
        rings[col - 2] = None
        x_lo, x_hi = min_max(idx[:, 0]) if idx.shape[0] else (0, -1)
        r_order, r_starts = order_by_key(idx[:, 0], 1, x_lo, x_hi - x_lo + 1)
        if col == 4:
            # the nodes' ties settled in order along x (the values of a copy)
            tie = ties(val, ZERO_TIE * h)
            if tie.size:
                tie = tie[_stable_order(idx[tie, 0] - x_lo)]
                settled = val[tie]
                evaluations += _settle_ties(solid, origin + idx[tie].astype(np.int64) * h, settled, h)
                val = val.copy()
                val[tie] = settled
                del settled
            del tie
        # the rows of x in [lo, hi) of each slab
        first = r_starts[np.clip(lo - x_lo, 0, r_starts.shape[0] - 1)]
        last = r_starts[np.clip(hi - x_lo, 0, r_starts.shape[0] - 1)]
        sorted_rings[col - 2] = (idx, val, itype, r_order, first, last)
        del ring, idx, val, r_order, r_starts
    del rings
    # -- each slab's share of the classification, cut out once and dropped as its slab is done --
    # (the whole-lattice arrays would otherwise stay alive under the growing parts: at N=1024 some
    # 150 MB of the peak).  With the slabs on two threads, the first slab's share is cut here and
    # the others on a thread of their own while the first slab is sampled.
    overlap = slab_threads == 2 and len(spans) >= OVERLAP_MIN_SLABS
    shares = _Shares([cells, centre_values, order, sorted_rings], spans, eps, threaded=overlap)
    del cells, centre_values, order, starts, sorted_rings

    parts = []
    n_blocks = 0
    bar = progress_bar(len(spans), "mesh", progress, unit="slab")

    def tasks():
        for k in range(len(spans)):
            sc, given, ring, ring_parents, extra = shares.take(k)  # the slab's job holds what it needs
            job = _SlabJob(solid, origin, h, c, block, int(slabs[k]), stride, lip if usable else None)
            yield job, (sc, given, (ring, ring_parents), centre_infer, extra)
            del sc, given, ring, ring_parents, extra

    try:
        for nb, spent in run_slabs(tasks(), parts, overlap=overlap):
            n_blocks += nb
            evaluations += spent
            bar.update()
    finally:
        bar.close()
        shares.close()
    # (with room behind the triangles for the few the feature pass adds: written in place, no second array)
    data, faces = merge_blocks(parts, threads=slab_threads, spare=FACE_ROOM if features else 0.0)
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
    # one compiled pass: a vertex inside a cube (on no edge) is placed at the mean of its neighbours
    # below; the others' fractions along their edge, and those to refine
    certify = bool(usable)
    floor = np.float32(ZERO_NUDGE * h * (1 + 1e-3))
    least = np.float32(lip * h - REFINE_ACCEPT * h) if certify else np.float32(0.0)
    # beside a tie (an end pushed ZERO_NUDGE h off the level) the stop tolerances shrink with h past
    # REFINE_FULL_N voxels across the solid (`refine_scale`): a fixed fraction of h left those vertices
    # a first-order distance off.  Elsewhere the free last step already leaves an O(h^2) error.
    scale = refine_scale(solid, h) if refine else 1.0
    t, inner, tied, rows, finite = _vertex_stage(f0, f1, axis, (INTERIOR, bool(refine), certify, floor, least,
                                                                scale < 1.0), slab_threads)
    if not finite:  # never for ends of opposite signs; a guard against a field's NaN
        t = np.nan_to_num(t, nan=0.5, posinf=1.0, neginf=0.0)
        np.clip(t, 0.0, 1.0, out=t)
    if refine:
        if scale < 1.0 and (tied.size or rows.size):
            spent = _refine_on_edges(solid, origin, nodes, axis, h, t, f0, f1, tied, tol=REFINE_TOL * scale,
                                     accept=REFINE_ACCEPT * scale, threads=slab_threads)
            evaluations += spent
        del tied
        spent = _refine_on_edges(solid, origin, nodes, axis, h, t, f0, f1, rows, threads=slab_threads)
        evaluations += spent
        del rows
    del f0, f1
    _release_free_memory()
    if edge_ids:
        ids = ((nodes[:, 0].astype(np.int64) * stride + nodes[:, 1]) * stride + nodes[:, 2]) * 3 + axis
    # (with features, room behind the points for the pass's feature vertices: untouched rows cost no memory)
    p0 = np.empty((nodes.shape[0] + point_room(nodes.shape[0]), 3))[:nodes.shape[0]] if features else \
        np.empty((nodes.shape[0], 3))
    _chunks_on_threads(lambda a, b: place_rows(nodes, axis, t, h, origin, p0, a, b), nodes.shape[0], EVAL_CHUNK,
                       threads=slab_threads)
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


class _Shares:
    """Each slab's share of the classification -- its cells (and their centre values, nudged to
    float32) and the rows of the three rings -- cut out of the whole-lattice arrays `whole` (``[cells,
    centre values or None, the cells' order by slab, the sorted rings]``) for the slab `take` asks.

    With `threaded`, the first share is cut at once and the others on a thread of their own (the
    first slab is then being sampled, the meshing thread waiting for it); else all are cut at once.
    Either way the whole-lattice arrays are let go, and the freed heap handed back, once every share
    is cut."""

    def __init__(self, whole, spans, eps, threaded):
        import threading

        self._whole, self._spans, self._eps = whole, spans, eps
        n = len(spans)
        self._pieces = [None] * n
        self._done = [threading.Event() for _ in range(n)]
        self._failed = []
        self._thread = None
        if threaded and n > 1:
            self._cut(0)
            self._thread = threading.Thread(target=self._cut_all, args=(1,), name="implicad-slab-shares",
                                            daemon=True)
            self._thread.start()
        else:
            self._cut_all(0)

    def _cut(self, k):
        cells, centre_values, order, rings = self._whole
        s0, s1 = self._spans[k]
        sc = np.empty((s1 - s0, 3), np.int64)
        take_rows(cells, order, s0, s1, sc)
        given = None
        if centre_values is not None:
            given = np.empty(s1 - s0, np.float32)
            take_nudged(centre_values, order, s0, s1, self._eps, given)
        piece = [sc, given, None, None, None]
        for col, ring in enumerate(rings, start=2):
            if ring is None:
                continue
            idx, val, itype, r_order, first, last = ring
            a, b = int(first[k]), int(last[k])
            rows = np.empty((max(b - a, 0), 3), itype)
            if col == 4:
                vals = np.empty(rows.shape[0], np.float32)
                take_nudged(val, r_order, a, a + rows.shape[0], self._eps, vals)
            else:
                vals = np.empty(rows.shape[0], val.dtype)
                take_entries(val, r_order, a, a + rows.shape[0], vals)
            take_rows(idx, r_order, a, a + rows.shape[0], rows)
            piece[col] = (rows, vals)
        self._pieces[k] = piece
        self._done[k].set()

    def _cut_all(self, first):
        try:
            for k in range(first, len(self._spans)):
                self._cut(k)
        except BaseException as exc:  # raised where the share is taken
            self._failed.append(exc)
        finally:
            self._whole = None
            for done in self._done:
                done.set()
            _release_free_memory()

    def take(self, k):
        """Slab `k`'s share ``[cells, centre values or None, ring, parents' ring, nodes]``, handed over."""
        self._done[k].wait()
        piece, self._pieces[k] = self._pieces[k], None
        if piece is None:
            raise self._failed[0] if self._failed else RuntimeError(f"mesh: slab {k}'s share taken twice")
        return piece

    def close(self):
        """Wait for the thread cutting the shares (when the slabs stopped early, their shares go)."""
        if self._thread is not None:
            self._thread.join()
        self._pieces = [None] * len(self._pieces)


def _vertex_stage(f0, f1, axis, args, threads):
    """The vertex stage (`cells_kernels.stage_counts`) in chunks of vertices on `threads` threads: the
    chunks' counts, then each chunk fills its own slots of the lists (`stage_fill`).

    Returns ``(t (v,) float64, inner (i,) int64, tied (k,) int32, rest (j,) int32, finite)``: `tied`
    is empty unless `split`; `finite` is False when some ``t`` is not finite (a field's NaN)."""
    n = f0.shape[0]
    spans = [(a, min(a + EVAL_CHUNK, n)) for a in range(0, n, EVAL_CHUNK)]
    counts = np.zeros((len(spans) + 1, 3), np.int64)

    def count(a, b):
        for k in range(a, b):
            counts[k + 1] = stage_counts(f0, f1, axis, *args, *spans[k])

    _chunks_on_threads(count, len(spans), 1, threads=threads)
    at = np.cumsum(counts, axis=0)
    t = np.empty(n, np.float64)
    inner = np.empty(int(at[-1, 0]), np.int64)
    tied = np.empty(int(at[-1, 1]), np.int32)
    rest = np.empty(int(at[-1, 2]), np.int32)
    finite = np.ones(len(spans), np.bool_)

    def fill(a, b):
        for k in range(a, b):
            finite[k] = stage_fill(f0, f1, axis, *args, *spans[k], t, inner, tied, rest, *at[k].tolist())

    _chunks_on_threads(fill, len(spans), 1, threads=threads)
    return t, inner, tied, rest, bool(finite.all())


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


def _index_rows(arr, dtype):
    """`arr` as (k, 3) integer rows: int32 and int64 arrays as they are (no whole-array copy), others as `dtype`."""
    arr = np.asarray(arr)
    if arr.dtype not in (np.int32, np.int64):
        arr = arr.astype(dtype)
    return arr.reshape(-1, 3)


def _ring(pair, name, what, index_type, value_type, cell_size):
    """``(indices (k, 3), per-row values, dtype of the slabs' indices)`` checked, or None."""
    if pair is None:
        return None
    if cell_size != 2:
        raise ValueError(f"{name}: only for cells of 2 voxels")
    idx = _index_rows(pair[0], index_type)
    val = np.asarray(pair[1], dtype=value_type).reshape(-1)
    if idx.shape[0] != val.shape[0]:
        raise ValueError(f"{name}: expected as many {what} as rows, got {val.shape[0]} for {idx.shape[0]}")
    return idx, val, index_type
