"""Watertight boundary meshes: marching cubes over the octree's BOUNDARY cells.

`mesh` decomposes a solid into an octree (`spatial.octree`) down to cells of
twice the voxel size, keeps their BOUNDARY cells and meshes only them:

1. the lattice nodes (spacing ``h``) of the boundary cells are sampled, slab
   by slab along x, in dense arrays of the slab's active blocks only (the
   work follows the surface); every node is evaluated exactly once (a node on
   a face shared by two blocks is merged by its integer id, one on the plane
   between two slabs is evaluated by the first slab and handed to the next),
   so the blocks on both sides of a face see one value and agree on its sign;
2. the cells are grouped into blocks of ``block**3`` voxels; every block is
   meshed independently by scikit-image's Lewiner marching cubes restricted
   (``mask=``) to the voxels of its boundary cells -- a pure function of the
   block's samples, ready to run elsewhere (`mesh_block`);
3. the blocks' triangles are merged into ONE indexed mesh whose vertices are
   keyed by the lattice edge they lie on (integer id ``3 * node + axis`` of
   the edge's lower node): no floating-point de-duplication (`merge_blocks`);
4. vertices are moved onto the true surface along their edge by a few
   vectorized regula-falsi (Illinois) steps bracketed by the edge's two
   samples, so a vertex never leaves its edge.

Cells classified FULL or EMPTY hold samples of one strict sign only (the
classification is conservative), so no triangle is lost by skipping them, and
the mesh is closed, 2-manifold and outward-oriented (scikit-image's
``gradient_direction='descent'`` with negative-inside distances) whenever the
solid lies inside the padded region.

Samples exactly on the level (0.0, or within ``ZERO_NUDGE * h`` of it) are
pushed off it keeping their sign (zero counts as outside), so a face lying
exactly on a sample plane leaves no hole (scikit-image issue 8116) and no
vertex sits on a lattice node.

References
----------
T. Lewiner, H. Lopes, A. W. Vieira, G. Tavares, "Efficient implementation of
marching cubes' cases with topological guarantees", J. Graphics Tools 8(2),
2003, doi:10.1080/10867651.2003.10487582.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from .octree import CHILD_OFFSETS, descend, make_lattice
from .progress import progress_bar

__all__ = ["mesh", "mesh_cells", "mesh_block", "merge_blocks", "empty_mesh", "ZERO_NUDGE", "DEFAULT_BLOCK",
           "REFINE_STEPS", "REFINE_TOL"]

#: Samples closer to the level than ``ZERO_NUDGE * h`` are pushed to that distance (sign kept, 0 -> +).
ZERO_NUDGE = 1e-3
#: Voxels per side of a meshing block.
DEFAULT_BLOCK = 32
#: At most this many regula-falsi steps move vertices onto the surface along their edge.
REFINE_STEPS = 6
#: A vertex stops moving once ``|f| <= REFINE_TOL * h``.
REFINE_TOL = 1e-4
#: A vertex with ``|f| <= REFINE_ACCEPT * h`` takes one more regula-falsi step without a further
#: evaluation: the step shrinks the error by about the curvature times h (a thousandth here).
REFINE_ACCEPT = 2e-3
#: Boxes bounded per call while descending (caps the memory of the classification).
CLASSIFY_CHUNK = 1 << 18
#: Points evaluated per call (caps the memory of an evaluation).
EVAL_CHUNK = 1 << 18


def empty_mesh(voxel_size=0.0, evaluations=0):
    """An empty `pyvista.PolyData` with the usual field data."""
    import pyvista as pv

    out = pv.PolyData()
    out.field_data["voxel_size"] = np.array([float(voxel_size)])
    out.field_data["evaluations"] = np.array([int(evaluations)], dtype=np.int64)
    return out


def mesh(solid, *, voxel_size=None, resolution=None, bounds=None, refine=True, progress=None,
         block=DEFAULT_BLOCK):
    """Closed, outward-oriented triangle mesh of a solid's boundary.

    Parameters
    ----------
    solid : Solid
        The solid (bounded, or give `bounds`).
    voxel_size : float, optional
        Edge of the voxels (marching-cubes cells).
    resolution : int, optional
        Voxels across the longest side of the bounds (exactly one of
        `voxel_size` / `resolution`).
    bounds : (lo, hi), optional
        Region to mesh; a solid sticking out of it is clipped to it (the mesh
        stays closed).
    refine : bool
        Move vertices onto the true surface (along their lattice edge).
    progress : bool or None
        Progress bar (None: only on a terminal).
    block : int
        Voxels per side of a meshing block (even).

    Returns
    -------
    pyvista.PolyData
        Triangles; ``field_data`` holds ``voxel_size``, ``evaluations``
        (boxes bounded plus points sampled), ``boundary_cells`` (BOUNDARY
        cells of edge ``2h`` meshed), ``blocks`` and ``seconds``.  Empty (with a warning) when no boundary lies in the
        region.

    Examples
    --------
    >>> from implicit import sphere
    >>> surface = mesh(sphere(1.0), resolution=32)
    >>> surface.is_manifold
    True
    """
    block = _check_block(block)
    lattice = make_lattice(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds)
    if lattice.empty:
        warnings.warn("mesh: the solid is empty (its bounds enclose nothing); returning an empty mesh",
                      RuntimeWarning, stacklevel=2)
        return empty_mesh(lattice.voxel_size if voxel_size else 0.0)
    cells, centres, evaluations = _boundary_cells_2h(lattice, progress)
    return mesh_cells(lattice.solid, lattice.origin, lattice.voxel_size, cells, cell_size=2,
                      refine=refine, progress=progress, evaluations=evaluations, block=block,
                      centre_values=centres, _stacklevel=3)


def _boundary_cells_2h(lattice, progress):
    """BOUNDARY cells of edge ``2h`` (level ``depth - 1``) and, when known, the field at their centres.

    Levels down to ``depth - 2`` are classified by `Solid.value_bounds`.  When
    the solid uses the default Lipschitz bound, level ``depth - 1`` is
    classified by the same test on values sampled at the cell centres --
    which are lattice nodes, so the mesh reuses them instead of sampling them
    again.  Returns ``(cells, centre values or None, evaluations)``.
    """
    from implicit.solid import Solid

    solid, depth = lattice.solid, lattice.depth
    if type(solid)._value_bounds is not Solid._value_bounds or depth < 2:
        result = descend(lattice, keep_leaves=False, stop_level=depth - 1, progress=progress,
                         chunk=CLASSIFY_CHUNK)
        return result["boundary"], None, result["evaluations"]
    result = descend(lattice, keep_leaves=False, stop_level=depth - 2, progress=progress, chunk=CLASSIFY_CHUNK)
    children = (2 * result["boundary"][:, None, :] + CHILD_OFFSETS).reshape(-1, 3)
    limit = (-(-lattice.shape // 2)).astype(np.int32)
    children = children[(children < limit).all(axis=1)]
    h = lattice.voxel_size
    values = np.empty(children.shape[0])
    for a in range(0, children.shape[0], EVAL_CHUNK):
        values[a:a + EVAL_CHUNK] = solid(lattice.origin + (2 * children[a:a + EVAL_CHUNK] + 1) * h)
    # the default bound: |f(centre)| <= L * half-diagonal (sqrt(3) h) may hold boundary
    keep = np.abs(values) <= solid.lipschitz * np.sqrt(3.0) * h * (1 + 1e-12)
    return children[keep], values[keep], result["evaluations"] + int(children.shape[0])


def _check_block(block):
    if isinstance(block, bool) or not isinstance(block, (int, np.integer)):
        raise TypeError(f"block: expected an even integer number of voxels, got {block!r}")
    if not 2 <= block <= 256 or block % 2:
        raise ValueError(f"block: expected an even number of voxels from 2 to 256, got {block}")
    return int(block)


# ---------------------------------------------------------------------------
# one block: a pure function of its samples
# ---------------------------------------------------------------------------

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
        Direction of the edge (0, 1, 2).
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
    from skimage.measure import marching_cubes

    try:
        verts, faces, _, _ = marching_cubes(values, 0.0, mask=mask, allow_degenerate=True)
    except (RuntimeError, ValueError):
        # No sign change in the block ('No surface found' / level out of range).
        return (np.empty((0, 3), np.int64), np.empty(0, np.int64), np.empty(0, np.float32),
                np.empty(0, np.float32), np.empty((0, 3), np.int32))
    rounded = np.rint(verts)
    axis = np.argmax(np.abs(verts - rounded), axis=1)
    node = rounded.astype(np.int64)
    rows = np.arange(verts.shape[0])
    node[rows, axis] = np.floor(verts[rows, axis]).astype(np.int64)
    f0 = values[node[:, 0], node[:, 1], node[:, 2]]
    upper = node.copy()
    upper[rows, axis] += 1
    f1 = values[upper[:, 0], upper[:, 1], upper[:, 2]]
    return node, axis.astype(np.int64), f0, f1, faces.astype(np.int32)


def merge_blocks(parts):
    """Merge per-block results into one indexed mesh keyed by global edge id.

    Only vertices on an edge lying in a block-grid plane can belong to two
    blocks; they are merged by their integer edge id (no floating-point
    comparison), the others are taken as they are.

    Parameters
    ----------
    parts : list of (edges, shared, data, faces)
        Per block: global edge ids ``3 * node + axis`` of its vertices that
        may be shared with another block, the boolean mask of those vertices,
        a tuple of per-vertex arrays (merged likewise) and the triangles
        (local vertex indices).

    Returns
    -------
    data : tuple of arrays
        The per-vertex arrays of the merged vertices (non-shared first).
    faces : (f, 3) int32 (int64 beyond 2**31 vertices)
        Triangles indexing the merged vertices.
    """
    parts = [p for p in parts if p[3].shape[0]]
    if not parts:
        return None, np.empty((0, 3), np.int32)
    shared_edges = np.concatenate([p[0] for p in parts])
    uniq, first, inverse = np.unique(shared_edges, return_index=True, return_inverse=True)
    del shared_edges
    n_private = sum(int(p[1].shape[0] - np.count_nonzero(p[1])) for p in parts)
    n_total = n_private + uniq.shape[0]
    itype = np.int32 if n_total < 2 ** 31 else np.int64
    n_data = len(parts[0][2])
    data = []
    for i in range(n_data):
        private = np.concatenate([p[2][i][~p[1]] for p in parts])
        shared = np.concatenate([p[2][i][p[1]] for p in parts])[first]
        data.append(np.concatenate([private, shared]))
        del private, shared
    faces = np.empty((sum(p[3].shape[0] for p in parts), 3), dtype=itype)
    row = private_at = shared_at = 0
    for p in parts:
        sh = p[1]
        k_sh = int(np.count_nonzero(sh))
        k_pr = sh.shape[0] - k_sh
        index = np.empty(sh.shape[0], dtype=itype)
        index[~sh] = np.arange(private_at, private_at + k_pr, dtype=itype)
        index[sh] = n_private + inverse[shared_at:shared_at + k_sh]
        k = p[3].shape[0]
        faces[row:row + k] = index[p[3]]
        row += k
        private_at += k_pr
        shared_at += k_sh
    return tuple(data), faces


# ---------------------------------------------------------------------------
# the pipeline over boundary cells
# ---------------------------------------------------------------------------

def _nudge(values, h):
    """Push samples within ``ZERO_NUDGE * h`` of 0 to that distance, keeping the sign (0 -> +)."""
    eps = ZERO_NUDGE * h
    out = np.asarray(values, dtype=np.float64)
    small = np.abs(out) < eps
    out[small] = np.where(out[small] < 0, -eps, eps)
    return out


def _evaluate(solid, pts, chunk=EVAL_CHUNK):
    """The solid's values at `pts` (n, 3), evaluated in chunks to cap temporary memory."""
    n = pts.shape[0]
    if n <= chunk:
        return solid(pts)
    out = np.empty(n)
    for a in range(0, n, chunk):
        out[a:a + chunk] = solid(pts[a:a + chunk])
    return out


def mesh_cells(solid, origin, voxel_size, cells, *, cell_size=1, refine=True, progress=None, evaluations=0,
               block=DEFAULT_BLOCK, centre_values=None, _stacklevel=2):
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
    evaluations : int
        Evaluations already spent (added to the mesh's count).
    centre_values : (m,) float, optional
        The field at the cells' centres when already sampled (``cell_size``
        2 only): those nodes are not sampled again.

    Returns
    -------
    pyvista.PolyData
    """
    import pyvista as pv

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
    if block % c:
        raise ValueError(f"block: expected a multiple of the cell size {c}, got {block}")
    stride = np.int64(int((cells.max() + 1) * c) + 2)  # global node ids: (x * S + y) * S + z
    per = block // c  # cells per block side

    if centre_values is not None:
        if c != 2:
            raise ValueError("centre_values: only for cells of 2 voxels")
        centre_values = np.asarray(centre_values, dtype=np.float64).reshape(-1)
        if centre_values.shape[0] != cells.shape[0]:
            raise ValueError(f"centre_values: expected {cells.shape[0]} values, got {centre_values.shape[0]}")
    # cells grouped in slabs of `block` voxels along x
    slab_of = cells[:, 0] // per
    order = np.argsort(slab_of, kind="stable")
    cells, slab_of = cells[order], slab_of[order]
    if centre_values is not None:
        centre_values = _nudge(centre_values[order], h).astype(np.float32)
    del order
    slab_starts = np.flatnonzero(np.r_[True, slab_of[1:] != slab_of[:-1]])
    slab_ends = np.r_[slab_starts[1:], cells.shape[0]]

    parts = []
    n_blocks = 0
    handoff = None  # (slab, sorted node ids, values) of the previous slab's upper node plane
    bar = progress_bar(len(slab_starts), "mesh", progress, unit="slab")
    try:
        for s0, s1 in zip(slab_starts, slab_ends):
            slab = int(slab_of[s0])
            sc = cells[s0:s1]
            given = None if centre_values is None else centre_values[s0:s1]
            nb, spent, handoff = _mesh_slab(solid, origin, h, sc, c, block, slab, stride, handoff, parts, given)
            n_blocks += nb
            evaluations += spent
            bar.update()
    finally:
        bar.close()
    data, faces = merge_blocks(parts)
    del parts
    if faces.shape[0] == 0:
        warnings.warn("mesh: no surface crosses the sampled nodes (features thinner than the voxel size?); "
                      "returning an empty mesh", RuntimeWarning, stacklevel=_stacklevel)
        return empty_mesh(h, evaluations)

    # -- vertex positions: on their edge, interpolated then refined ------------------------
    nodes, axis, f0, f1 = data
    del data
    p0 = nodes.astype(np.float64)
    del nodes
    p0 *= h
    p0 += origin
    t = f0 / (f0.astype(np.float64) - f1)
    if refine:
        t, spent = _refine_on_edges(solid, p0, axis, h, t, f0, f1)
        evaluations += spent
    del f0, f1
    p0[np.arange(p0.shape[0]), axis] += t * h
    del t, axis
    out = pv.PolyData.from_regular_faces(p0, faces)
    out.field_data["voxel_size"] = np.array([h])
    out.field_data["evaluations"] = np.array([int(evaluations)], dtype=np.int64)
    out.field_data["boundary_cells"] = np.array([int(cells.shape[0])], dtype=np.int64)
    out.field_data["blocks"] = np.array([n_blocks], dtype=np.int64)
    out.field_data["seconds"] = np.array([time.perf_counter() - t0])
    return out


def _mesh_slab(solid, origin, h, sc, c, block, slab, stride, handoff, parts, given=None):
    """Sample and mesh one slab of cells (x from ``slab * block`` voxels, ``block`` thick).

    The slab's active blocks (those holding cells) are stacked in dense
    ``(nb, block+1, block+1, block+1)`` arrays, so the work follows the
    surface.  Only nodes of the cells are evaluated, each once: nodes on a
    face shared by two blocks are merged by their integer id, and the lower
    node plane reuses the values the previous slab evaluated for its upper
    plane (`handoff`: sorted ids and values).  `given` holds the values at
    the cells' centres when already sampled.  Returns ``(blocks meshed,
    evaluations, handoff)``.
    """
    B = block
    P = B // c
    x0 = slab * B
    # -- active blocks and their cells --------------------------------------------------
    by = sc[:, 1] // P
    bz = sc[:, 2] // P
    nbz = int(bz.max()) + 1
    keys, inv = np.unique(by * nbz + bz, return_inverse=True)
    nb = keys.shape[0]
    bys, bzs = np.divmod(keys, nbz)
    cells = np.zeros((nb, P, P, P), dtype=bool)
    cells[inv, sc[:, 0] - slab * P, sc[:, 1] - by * P, sc[:, 2] - bz * P] = True
    cell_local = (inv, sc[:, 0] - slab * P, sc[:, 1] - by * P, sc[:, 2] - bz * P)
    del by, bz
    # nodes of the cells: a separable dilation (each axis: repeat c times, OR a shift by one)
    need = cells
    for ax in (1, 2, 3):
        rep = np.repeat(need, c, axis=ax) if c > 1 else need
        shape = list(rep.shape)
        shape[ax] += 1
        grown = np.zeros(shape, dtype=bool)
        lo_sl = [slice(None)] * 4
        hi_sl = [slice(None)] * 4
        lo_sl[ax] = slice(0, -1)
        hi_sl[ax] = slice(1, None)
        grown[tuple(lo_sl)] = rep
        grown[tuple(hi_sl)] |= rep
        need = grown
    del rep, grown
    # -- global ids of the needed nodes ----------------------------------------------------
    flat = np.flatnonzero(need)
    n3 = (B + 1) ** 3
    blk, rest = np.divmod(flat, n3)
    li, rest = np.divmod(rest, (B + 1) ** 2)
    lj, lk = np.divmod(rest, B + 1)
    del rest
    gy = bys[blk] * B + lj
    gz = bzs[blk] * B + lk
    gid = ((li + x0) * stride + gy) * stride + gz
    # nodes on a y/z block face or on the lower x plane may be needed twice: merge by id
    maybe = (lj % B == 0) | (lk % B == 0) | (li == 0)
    uniq, ufirst, back = np.unique(gid[maybe], return_index=True, return_inverse=True)
    uval = np.empty(uniq.shape[0])
    todo_u = np.ones(uniq.shape[0], dtype=bool)
    if handoff is not None and handoff[0] == slab - 1 and handoff[1].size:
        pid, pval = handoff[1], handoff[2]
        pos = np.minimum(np.searchsorted(pid, uniq), pid.size - 1)
        hit = pid[pos] == uniq
        uval[hit] = pval[pos[hit]]
        todo_u[hit] = False
    single = ~maybe
    if given is not None:
        # the cells' centres (all-odd local coordinates) are already sampled
        single &= ~((li & 1).astype(bool) & (lj & 1).astype(bool) & (lk & 1).astype(bool))
    # evaluate the single nodes and the merged nodes not handed over, in one call
    pick = np.concatenate([np.flatnonzero(single), np.flatnonzero(maybe)[ufirst[todo_u]]])
    pts = np.empty((pick.shape[0], 3))
    pts[:, 0] = origin[0] + (li[pick] + x0) * h
    pts[:, 1] = origin[1] + gy[pick] * h
    pts[:, 2] = origin[2] + gz[pick] * h
    vals_pick = _nudge(_evaluate(solid, pts), h) if pick.shape[0] else np.empty(0)
    del pts
    spent = int(pick.shape[0])
    n_single = int(np.count_nonzero(single))
    uval[todo_u] = vals_pick[n_single:]
    node_vals = np.zeros(flat.shape[0])
    node_vals[single] = vals_pick[:n_single]
    node_vals[maybe] = uval[back]
    del vals_pick, pick
    # only needed nodes are read (each block sets its other nodes to 1 below)
    values = np.empty((nb, B + 1, B + 1, B + 1), dtype=np.float32)
    values.reshape(-1)[flat] = node_vals
    if given is not None:
        b_, x_, y_, z_ = cell_local
        values[b_, 2 * x_ + 1, 2 * y_ + 1, 2 * z_ + 1] = given
    del cell_local
    # the upper plane goes to the next slab
    top = li == B
    hid, first = np.unique(gid[top], return_index=True)
    handoff = (slab, hid, node_vals[top][first])
    del flat, blk, li, lj, lk, gy, gz, gid, node_vals, maybe, single
    # -- mesh every block -------------------------------------------------------------------
    for b in range(nb):
        cb = cells[b]
        box_lo, box_hi = [], []
        for ax in range(3):
            hit = np.flatnonzero(cb.any(axis=tuple(a for a in range(3) if a != ax)))
            box_lo.append(int(hit[0]))
            box_hi.append(int(hit[-1]) + 1)
        cb = cb[box_lo[0]:box_hi[0], box_lo[1]:box_hi[1], box_lo[2]:box_hi[2]]
        if c > 1:
            cb = np.repeat(np.repeat(np.repeat(cb, c, 0), c, 1), c, 2)
        xs, ys, zs = box_lo[0] * c, box_lo[1] * c, box_lo[2] * c
        box = (b, slice(xs, xs + cb.shape[0] + 1), slice(ys, ys + cb.shape[1] + 1), slice(zs, zs + cb.shape[2] + 1))
        vol = np.ascontiguousarray(values[box])
        vol[~need[box]] = 1.0
        mask = np.zeros(vol.shape, dtype=bool)
        mask[1:, 1:, 1:] = cb
        node, axis, f0, f1, faces = mesh_block(vol, mask)
        if faces.shape[0]:
            node += (xs + x0, ys + int(bys[b]) * B, zs + int(bzs[b]) * B)
            edges = ((node[:, 0] * stride + node[:, 1]) * stride + node[:, 2]) * 3 + axis
            on_plane = (node % B == 0) & (axis[:, None] != np.arange(3))
            shared = on_plane.any(axis=1)
            parts.append((edges[shared], shared, (node.astype(np.int32), axis.astype(np.uint8), f0, f1), faces))
    return nb, spent, handoff


def _refine_on_edges(solid, p0, axis, h, t, f0, f1, steps=REFINE_STEPS, tol=REFINE_TOL, accept=REFINE_ACCEPT,
                     chunk=EVAL_CHUNK):
    """Illinois regula falsi for the root of f along each vertex's edge.

    Vertex ``i`` lies at ``p0[i] + t[i] * h * e[axis[i]]``.  The bracket
    ``[a, b]`` (initially ``[0, 1]``, end values of opposite signs) is kept,
    so every vertex stays on its edge.  Only vertices whose value is still
    above ``tol * h`` are updated; those already within ``accept * h`` take
    that last update without being evaluated again.  Works on chunks of
    vertices to bound the temporaries.  Returns the new parameters and the number of
    evaluations spent.
    """
    out = np.empty_like(t)
    spent = 0
    for s0 in range(0, t.shape[0], chunk):
        sl = slice(s0, s0 + chunk)
        out[sl], used = _refine_chunk(solid, p0[sl], axis[sl], h, t[sl], f0[sl], f1[sl], steps, tol, accept)
        spent += used
    return out, spent


def _refine_chunk(solid, p0, axis, h, t, fa, fb, steps, tol, accept):
    n = t.shape[0]
    t = t.copy()
    a = np.zeros(n)
    b = np.ones(n)
    fa = fa.astype(np.float64)
    fb = fb.astype(np.float64)
    side = np.zeros(n, dtype=np.int8)
    active = np.arange(n)
    spent = 0
    for _ in range(steps):
        if active.size == 0:
            break
        q = p0[active]
        q[np.arange(active.size), axis[active]] += t[active] * h
        ft = solid(q)
        spent += active.size
        busy = np.abs(ft) > tol * h
        active, ft = active[busy], ft[busy]
        ta, aa, ba, fa_, fb_, sd = t[active], a[active], b[active], fa[active], fb[active], side[active]
        left = (ft > 0) == (fa_ > 0)
        # the root lies in [t, b] when f(t) has the sign of f(a)
        aa = np.where(left, ta, aa)
        ba = np.where(left, ba, ta)
        new_fa = np.where(left, ft, fa_)
        new_fb = np.where(left, fb_, ft)
        # Illinois: halve the value of an end kept twice in a row
        new_fb = np.where(left & (sd == 1), 0.5 * new_fb, new_fb)
        new_fa = np.where(~left & (sd == -1), 0.5 * new_fa, new_fa)
        denom = new_fb - new_fa
        ok = denom != 0
        t_new = np.where(ok, (aa * new_fb - ba * new_fa) / np.where(ok, denom, 1.0), 0.5 * (aa + ba))
        t[active] = np.clip(t_new, aa, ba)
        a[active], b[active], fa[active], fb[active] = aa, ba, new_fa, new_fb
        side[active] = np.where(left, 1, -1)
        active = active[np.abs(ft) > accept * h]
    return t, spent
