"""Sharp edges and corners rebuilt inside the marching-cubes cells that hold them.

Marching cubes puts every vertex on a lattice edge, so an edge or a corner of
a CSG part is cut off by a chamfer up to about one voxel wide.  `sharpen`
repairs the boundary mesh after the fact, in the voxels (cells) whose surface
holds two or three distinct faces, in the way of Extended Marching Cubes:

1. candidates: triangles whose normal departs from a vertex normal
   (``cos < COS_CANDIDATE``) mark their cells; only the vertices of those
   cells are evaluated further (a few per cent of the mesh);
2. exact normals: every such vertex is attributed to the CSG face deciding
   the field there (`implicit.facets.FacetField`: the primitive leaf, or one
   face of a box or cylinder); a cell whose vertices all lie on one smooth
   facet (a sphere, a torus, a plane: `implicit.facets.SMOOTH_KINDS`) is none,
   and the vertices of the others take their face's gradient, in closed
   form (`FacetField.gradients_of`);
3. the feature vertex: per cell, the quadric ``sum (n_i . (x - p_i))^2`` over
   the cell's vertices is minimised around their mass point with the
   pseudo-inverse of ``A^T A`` whose eigenvalues below ``EIGEN_CUTOFF`` times
   the largest are dropped; the number kept is the cell's rank (2: an edge,
   3: a corner), whatever the rank a cell on one smooth facet would have
   at a coarse voxel.  When the cell holds exactly that many faces, a few
   Gauss-Newton steps on their fields put the vertex on their exact common
   curve or point (curved faces included).  An edge point that falls
   outside its cell slides along the curve's tangent into it and is put
   back on the curve (clipped to the cell instead, it would leave the
   curve).  The vertex stays inside its cell;
4. the cell's triangles are replaced by a fan from the feature vertex over
   the boundary polygon of the cell's patch (cells whose patch is not one
   disc are left alone), and an edge between two fans whose end vertices
   lie on different faces is flipped so that the two feature vertices are
   joined: the mesh follows the edge;
5. every new triangle must face the way the exact normals of its ordinary
   vertices do; cells whose triangles do not are given back their marching
   cubes triangles and the pass is redone without them;
6. a fan has two triangles more than the marching-cubes polygon it
   replaces: each feature vertex then takes the nearest vertex of its
   polygon (an edge collapse, `feature_collapse`), where that keeps the mesh
   manifold and turns no triangle much, so the feature mesh has about as
   many triangles as the plain one.

The stages run as a few compiled functions (`feature_cells`: the node
tests, the candidate cells found by runs of one cell's triangles and grouped
by one hash probe per run and a counting sort; `feature_kernels`: the cells'
faces, the QEF solved by Jacobi rotations per cell with the patch borders, the
fans with their flips and facing tests; `feature_collapse.finish`), between the
calls into the solid's facets (`implicit.facets`: numpy walks of the tree, with
compiled loops for its boxes, cylinders, spheres and runs of capsules).  Only the walks of stage 1 and of the collapse's output read every
triangle; the rest grows with the candidate cells, and the exact normals and the
QEF only with the cells not on one smooth facet (near the feature curves).  Their arrays over every vertex or triangle are made by the
caller, as small as they can be (int8 axes, int32 indices and triangles, the
exact normals only where they are needed), and the mesher lends the pass its
points (`sharp_polydata_lent`), freed as soon as the fans' points are made.

Each vertex carries ``feature_rank`` (0, 2 or 3) and ``feature_facets`` (up
to three face indices into the field data ``facet_names``; -1 unused), from
which `feature_edges` builds the labelled feature curves.

What was taken from where
-------------------------
* Kobbelt et al. (Extended Marching Cubes): the detection by the spread of
  the exact normals in a cell, one feature vertex per feature cell at the
  intersection of the tangent planes, the fan over the cell's polygon and
  the flip of the edges between neighbouring feature vertices.  Unlike EMC
  the fan is built from the finished marching-cubes mesh, so the merge,
  refinement and sign inference of the mesher stay as they are.
* Ju et al. (dual contouring) and libfive's ``dc_tree.cpp``: the QEF kept as
  ``A^T A``, ``A^T b`` and solved relative to the mass point with a truncated
  eigen-decomposition, which gives the point of an edge nearest the mass
  point when the rank is 2; libfive's count of normals differing by more
  than ``dot < 0.9`` (our `COS_SHARP`) as a face test, and its check that
  the vertex lies in its cell.
* OpenVDB's ``VolumeToMesh.h`` (``findFeaturePoint``): the same pseudo-inverse
  with eigenvalues under a fraction of the largest clamped (1 % there,
  `EIGEN_CUTOFF` here).  Its mesher itself does not rebuild features.
* Beyond all three: the normals are not finite differences of the whole
  field but gradients of the one CSG face deciding the value, and the QEF
  vertex is moved onto the exact intersection of those faces.

References
----------
L. Kobbelt, M. Botsch, U. Schwanecke, H.-P. Seidel, "Feature sensitive surface
extraction from volume data", SIGGRAPH 2001, doi:10.1145/383259.383265.
T. Ju, F. Losasso, S. Schaefer, J. Warren, "Dual contouring of Hermite data",
SIGGRAPH 2002, doi:10.1145/566654.566586.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from .feature_collapse import _room, finish
from .feature_threads import on_threads, spans
from .feature_cells import cells as _cells, nodes as _nodes
from .feature_kernels import _cell_faces, _facing_kernel, _fan_rows, _flip_fans, _newton_step, _solve_cells

__all__ = ["sharpen", "sharp_polydata", "sharp_polydata_lent", "COS_CANDIDATE", "COS_SHARP", "EIGEN_CUTOFF",
           "FACE_ROOM"]

#: A triangle whose normal makes ``cos < COS_CANDIDATE`` with one of its vertex normals marks its cell.
COS_CANDIDATE = 0.97
#: A vertex this close (in voxels, every coordinate) to a lattice node lies at a node: its sample was a tie.
AT_NODE = 0.01
#: Bisection steps that put a vertex of a lattice edge lying in a face at the face's border (2**-30 voxels).
BISECTIONS = 30
#: Two exact normals with ``cos < COS_SHARP`` belong to different faces (libfive's 0.9).
COS_SHARP = 0.9
#: QEF eigenvalues under this fraction of the largest are dropped (the rank is what is left).
EIGEN_CUTOFF = 0.03
#: Gauss-Newton steps onto the common curve or point of the cell's faces (from the QEF point, one is enough).
NEWTON_STEPS = 1
#: Feature vertices are kept this far (in voxels) inside their cell's faces.
CELL_MARGIN = 1e-3
#: A new triangle must face one ordinary vertex's exact normal with ``cos > MIN_FACING`` and oppose none.
MIN_FACING = 0.3
#: Rounds of rejecting bad cells before the pass gives up (and returns the plain mesh).
ROUNDS = 6
#: The fans' vertices go in the rows after the points where they are at most one per ROOM points.
ROOM = 16
#: The mesher leaves this fraction of rows free behind its triangles: the pass's few extra ones are then
#: written in place (the fans' two extra triangles each are mostly collapsed away: 0.09 % more at N=512).
FACE_ROOM = 1 / 64


def _unit(v):
    n = np.sqrt(np.einsum("...i,...i->...", v, v))[..., None]
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


def _cross(u, v):
    """Row-wise cross product (``np.cross`` is several times slower on long arrays)."""
    out = np.empty_like(u)
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out


#: Rows from which the facets' numpy walks (`implicit.facets`: row by row) run in two halves on two threads.
ROWS_ON_THREADS = 8192


def point_room(n):
    """Rows the pass wants behind `n` points for the fans' vertices (at most one per `ROOM` points)."""
    return n // ROOM + 256


def _by_rows(walk, n):
    """``walk(0, n)``, an array computed row by row, made as two halves on two threads (`feature_threads`)
    when there are rows enough: numpy and the compiled leaves release the interpreter's lock for the most
    part, and each row's result is the one of the whole walk."""
    if n < ROWS_ON_THREADS:
        return walk(0, n)
    return np.concatenate(on_threads([partial(walk, a, b) for a, b in spans(n)]))


def _runs(sorted_keys):
    """Start index of every run of equal values in a sorted array."""
    return np.flatnonzero(np.r_[True, sorted_keys[1:] != sorted_keys[:-1]])


def sharpen(solid, points, faces, origin, h):
    """Rebuild the sharp edges and corners of a marching-cubes mesh of `solid`.

    Parameters
    ----------
    solid : Solid
    points : (n, 3) float
        Vertices, each on a lattice edge (as `mesh_cells` makes them).
    faces : (m, 3) int
        Triangles, outward; each lies in one voxel.
    origin : (3,) float
        Position of lattice node (0, 0, 0).
    h : float
        Voxel edge.

    Returns
    -------
    dict
        ``points`` (n', 3), ``faces`` (m', 3), ``feature_rank`` (n',) int8,
        ``feature_facets`` (n', 3) int32, ``facet_names`` (list of str) and
        ``feature_cells`` (int).

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing import mesh
    >>> m = mesh(box(1.0), resolution=8, features=True)
    >>> int((m.point_data["feature_rank"] == 3).sum())
    8
    """
    return _sharpen(solid, [points, faces], origin, h)


def _sharpen(solid, lent, origin, h, overwrite=False):
    """`sharpen` of ``lent = [points, faces]``, a list it empties: when the caller keeps no other
    reference to the points, they are freed once the fans' points are made, before the last stage
    (at N=1024, some 180 MB of the pass's peak).  With `overwrite` the triangles are the caller's to
    overwrite: the result's are written into their rows where they fit."""
    from implicit.facets import FacetField

    points, faces = lent
    lent.clear()
    pts = np.asarray(points, dtype=np.float64)
    f = np.ascontiguousarray(faces)
    del points, faces
    if f.dtype not in (np.int32, np.int64):  # the mesher's int32 triangles are read as they are
        f = f.astype(np.int64)
    n = pts.shape[0]
    ff = FacetField(solid)

    def plain(pts=pts):
        return dict(points=pts, faces=f, feature_rank=np.zeros(n, np.int8),
                    feature_facets=np.full((n, 3), -1, np.int32), facet_names=list(ff.names), feature_cells=0)

    if f.shape[0] == 0:
        return plain()
    origin = np.asarray(origin, dtype=np.float64)
    m = f.shape[0]

    # -- 0. vertices on lattice edges lying in a face ------------------------------------------
    # (the pass's arrays over every vertex or triangle are made here, by numpy, and handed to the kernels:
    # their sizes and types are chosen in one place)
    at_node, axis = np.empty(n, np.bool_), np.empty(n, np.int8)
    border = _nodes(pts, f, origin, float(h), AT_NODE, at_node, axis)
    pts, moved = _off_flat_edges(solid, pts, border, axis, origin, float(h))
    del border, axis
    u = (pts[moved] - origin) / h
    at_node[moved] = np.abs(u - np.floor(u + 0.5)).max(axis=1, initial=0.0) < AT_NODE

    # -- 1. candidate cells, from the mesh alone ---------------------------------------------
    # (`index`: each vertex's row among the candidate cells' vertices, -1 for the others)
    # (the vertex normals' rows, once read, take the points of the fans: `room` has rows for the fans'
    # vertices beyond them, which are never touched unless used)
    # (`index` and the runs' starts, once read, are the collapses' work arrays: pages already touched)
    # (lent points with room behind them, `point_room`, are the fans' points already: no copy)
    # (then the vertex normals have an array of their own; else they take the rows of `room` until the points
    # are copied there)
    room = _room(pts, n + point_room(n)) if overwrite else None
    in_room = room is not None
    if in_room:
        vn = np.empty((n, 3))
    else:
        room = np.empty((n + point_room(n), 3))
        vn = room[:n]
    spare = np.empty(n + point_room(n), np.int32)
    index = spare[:n]
    ix = np.int32 if m < 2 ** 31 else np.int64
    work = np.empty(m + 1, ix), np.empty(m, np.int64), np.empty(m, np.bool_)
    cand, lo, s, tri, tcell, pvert, starts, verts, pinv = _cells(pts, f, origin, float(h), COS_CANDIDATE,
                                                                 at_node, vn, *work, index)
    runs = work[0]
    del work, at_node
    if cand.shape[0] == 0:
        return plain()
    n_cells = cand.shape[0]
    vn = vn[verts]        # (a copy: `room` is free for the fans' points)

    # -- 2. exact normals at the vertices of the candidate cells that may hold an edge --------
    # the deciding facets of every candidate vertex, which rule out the cells on one smooth facet (most of
    # them: a sphere's, a plane's chamfer-free turns); the exact normal of the face deciding the field only
    # at the vertices of the others (closed forms; forward steps of 1e-6 h where none)
    at_verts = pts[verts]
    decider = _by_rows(lambda a, b: np.asarray(ff.decide(at_verts[a:b])[1], dtype=np.int64), verts.shape[0])
    need = np.zeros(verts.shape[0], np.bool_)
    labels, n_faces, open_cells = _cell_faces(pinv, decider, starts, ff.smooth, need)
    rows = np.flatnonzero(need)
    normal = np.zeros((verts.shape[0], 3))
    if rows.shape[0]:
        g = _unit(_by_rows(lambda a, b: ff.gradients_of(at_verts[rows[a:b]], decider[rows[a:b]], 1e-6 * h),
                           rows.shape[0]))
        g *= np.where(np.einsum("ij,ij->i", g, vn[rows]) < 0, -1.0, 1.0)[:, None]
        normal[rows] = g
        del g
    del vn, at_verts, need, rows
    exact = (normal, index)

    # -- 3. QEF per open cell ----------------------------------------------------------------
    # (the border of each cell's patch, for the cells of rank 2 or more; the faces in each cell, most
    # frequent first, are the labels and the surfaces to solve on)
    # (the cells in two chunks on two threads: each cell is solved alone, the border edges put together in
    # the cells' order)
    x, rank = np.empty((n_cells, 3)), np.empty(n_cells, np.int64)
    disc, edge = np.empty(n_cells, np.bool_), np.empty(n_cells, np.bool_)
    solved = on_threads([partial(_solve_cells, pts, f, tri, tcell, pvert, normal, pinv, starts, open_cells,
                                 EIGEN_CUTOFF, c0, c1, x, rank, disc, edge) for c0, c1 in spans(n_cells)])
    b0, b1, bc = (np.concatenate([part[j] for part in solved]) for j in range(3))
    del solved, edge
    cell_lo = origin + (np.stack([cand // (s * s), (cand // s) % s, cand % s], axis=1) + lo) * h
    # (a cell on one smooth face, not open, holds no edge however much the face turns across it at a coarse
    # voxel, where its QEF would read as two planes: it was given rank 0)
    feature = rank >= 2
    x = _onto_faces(ff, x, labels, rank, n_faces, feature, cell_lo, h)
    margin = CELL_MARGIN * h
    x = np.clip(x, cell_lo + margin, cell_lo + h - margin)

    # -- 4./5. fans and flips, with the cells that fail handed back --------------------------
    feature &= disc           # cells whose patch is not one disc are left alone
    # (the rounds only take cells away: the first round's fans are the most there are)
    if feature.any() and room.shape[0] >= n + int(feature.sum()):
        if not in_room:
            room[:n] = pts
    else:
        room = None
    for _ in range(ROUNDS):
        new_faces, owner, fan_cells, newp, bad = _fans_and_flips(pts, exact, (b0, b1, bc), feature, n, n_cells, x,
                                                                 room)
        if not bad.any():
            break
        gone = np.unique(owner[bad].reshape(-1))
        feature[gone[gone >= 0]] = False
    else:
        return plain()
    # (`newp`, unless no fan was made, is this pass's own array: the points used are gathered in it)
    own = newp is not pts
    del plain, pts, room
    drop = np.zeros(f.shape[0], np.bool_)
    drop[tri[feature[tcell]]] = True
    # the fans' two extra triangles each are taken back by collapsing a polygon vertex into the feature
    # vertex; a vertex no triangle uses (that, or marching cubes' inner vertex of an ambiguous cube, no
    # corner of the fan that replaced the cell's triangles) is dropped
    n_all = newp.shape[0]
    del exact, index
    work = (spare[:n_all], runs[:n_all + 1]) if spare.shape[0] >= n_all and runs.shape[0] > n_all else None
    out_faces, used, _, newp = finish(newp, f, drop, new_faces, n, overwrite_points=own, overwrite_faces=overwrite,
                                      dtype=np.int32 if n_all < 2 ** 31 else np.int64, work=work)
    del work, spare, runs
    # the feature vertices come last, in the order of their cells
    kept = used[n:]
    n_plain = newp.shape[0] - int(kept.sum())
    frank = np.zeros(newp.shape[0], np.int8)
    frank[n_plain:] = np.minimum(rank[fan_cells], 3)[kept]
    ffacets = np.full((newp.shape[0], 3), -1, np.int32)
    lab = labels[fan_cells]
    lab[np.arange(3)[None, :] >= np.maximum(rank[fan_cells], n_faces[fan_cells])[:, None]] = -1
    ffacets[n_plain:] = lab[kept]
    return dict(points=newp, faces=out_faces, feature_rank=frank, feature_facets=ffacets,
                facet_names=list(ff.names), feature_cells=int(fan_cells.shape[0]))


def _off_flat_edges(solid, pts, border, axis, origin, h):
    """Vertices at a lattice node whose lattice edge lies in a face, moved to where that face ends.

    On a face lying in a lattice plane the field is 0 along the lattice
    edges of the plane, so the crossing found on such an edge (the sample
    at its far end inside, the tie at the node settled outside, or the
    reverse) sits at the node, up to a voxel from the face's true border.
    Only vertices at a node that join an ordinary vertex (the border of
    the face) and whose value is a tie are looked at; each is bisected
    along its edge, from the far node, to where the field stops having
    the far node's sign: the point of the edge on the face's border.
    """
    from .arrays import ZERO_TIE

    v = np.flatnonzero(border)
    if v.shape[0] == 0:
        return pts, v
    tie = ZERO_TIE * h
    val = solid(pts[v])
    v = v[np.abs(val) <= tie]
    if v.shape[0] == 0:
        return pts, v
    a = axis[v]
    r = np.arange(v.shape[0])
    u = (pts[v, a] - origin[a]) / h
    near = np.floor(u + 0.5)
    far = origin[a] + (near - np.sign(near - u)) * h       # the other end of the vertex's lattice edge
    lo = pts[v].copy()
    lo[r, a] = far
    s_far = np.sign(solid(lo))
    ok = np.abs(solid(lo)) > tie
    v, a, r, lo, s_far = v[ok], a[ok], np.arange(int(ok.sum())), lo[ok], s_far[ok]
    if v.shape[0] == 0:
        return pts, v
    hi = pts[v].copy()
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        fm = solid(mid)
        same = (np.sign(fm) == s_far) & (np.abs(fm) > tie)
        lo[same] = mid[same]
        hi[~same] = mid[~same]
    # a vertex on a true crossing at the node stays (bisection finds the node again)
    moved = np.abs(hi - pts[v]).max(axis=1) > 0.1 * AT_NODE * h
    out = pts.copy()
    out[v[moved]] = hi[moved]
    return out, v[moved]


def _onto_faces(ff, x, labels, rank, n_faces, feature, cell_lo, h):
    """Gauss-Newton onto the common curve (2 faces) or point (3) of a cell's faces.

    Only cells whose rank equals their number of faces; a point that leaves
    its cell (grown by half a voxel) keeps its QEF position.  An edge point
    outside its cell slides along the curve's tangent to the nearest point
    of the tangent line in the cell, and one more step puts it back on the
    curve.
    """
    rows = np.flatnonzero(feature & (n_faces == rank) & (rank <= 3))
    if rows.shape[0] == 0:
        return x
    # (each row alone: in two halves on two threads when there are many)
    q = _by_rows(lambda a, b: _onto_rows(ff, x, labels, rank, cell_lo, h, rows[a:b]), rows.shape[0])
    inside = ~np.isnan(q[:, 0])
    x = x.copy()
    x[rows[inside]] = q[inside]
    return x


def _onto_rows(ff, x, labels, rank, cell_lo, h, rows):
    """`_onto_faces` of the cells `rows`: their points, NaN where a point keeps its QEF position."""
    k = 3
    sets = labels[rows]
    used = np.arange(k)[None, :] < rank[rows][:, None]
    idx = np.where(used, sets, -1)       # (an unused slot asks no facet: values and gradients 0 there)
    q = x[rows].copy()
    q, jac = _newton(ff, q, idx, used, h, NEWTON_STEPS)
    # an edge point outside the cell slides along the curve's tangent into the cell (one more step puts it
    # back on the curve): clipped to the cell instead, it would leave the curve
    # (the clip to the cell's margin comes later: an edge in a lattice plane stays on it)
    eps = 0.01 * h
    lo_c, hi_c = cell_lo[rows], cell_lo[rows] + h
    off = np.any((q < lo_c - eps) | (q > hi_c + eps), axis=1) & (rank[rows] == 2)
    if off.any():
        t = _unit(_cross(jac[off, 0], jac[off, 1]))
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = (lo_c[off] - q[off]) / t, (hi_c[off] - q[off]) / t
        flat = np.abs(t) < 1e-12
        inside_flat = (q[off] >= lo_c[off] - eps) & (q[off] <= hi_c[off] + eps)
        s0 = np.where(flat, np.where(inside_flat, -np.inf, np.inf), np.minimum(a, b)).max(axis=1)
        s1 = np.where(flat, np.where(inside_flat, np.inf, -np.inf), np.maximum(a, b)).min(axis=1)
        hit = s0 <= s1
        slide = np.clip(0.0, s0, s1)
        moved = q[off] + np.where(hit, slide, 0.0)[:, None] * t
        sub = np.flatnonzero(off)[hit]
        if sub.shape[0]:
            q[sub], _ = _newton(ff, moved[hit], idx[sub], used[sub], h, 1)
        # a curve that passes by the cell without entering it (the cell holds it only through a vertex
        # not yet on the surface): the point of the tangent line nearest the cell, which the clip to the
        # cell then takes to the cell's point nearest the curve (the plain clip would go across it)
        miss = np.flatnonzero(off)[~hit]
        if miss.shape[0]:
            q[miss] = _nearest_on_line(q[miss], t[~hit], lo_c[miss], hi_c[miss], h)
    lo = cell_lo[rows] - 0.5 * h
    inside = np.all((q >= lo) & (q <= lo + 2.0 * h), axis=1) & np.all(np.isfinite(q), axis=1)
    q[~inside] = np.nan
    return q


def _nearest_on_line(q, t, lo, hi, h, steps=40):
    """Point ``q + s t`` (``|s| <= 2 h``) nearest the box ``[lo, hi]``, per row (golden-section search:
    the distance to a box along a line is convex), where it is within 0.05 h of the box; else `q`."""
    a = np.full(q.shape[0], -2.0 * h)
    b = np.full(q.shape[0], 2.0 * h)
    g = 0.5 * (np.sqrt(5.0) - 1.0)

    def gap(s):
        p = q + s[:, None] * t
        return np.einsum("ij,ij->i", *(2 * [p - np.clip(p, lo, hi)]))

    for _ in range(steps):
        c, d = b - g * (b - a), a + g * (b - a)
        left = gap(c) <= gap(d)
        b = np.where(left, d, b)
        a = np.where(left, a, c)
    s = 0.5 * (a + b)
    # only a line that passes close by (a curve grazing the cell); others keep their point
    return q + np.where(gap(s) < (0.05 * h) ** 2, s, 0.0)[:, None] * t


def _newton(ff, q, idx, used, h, steps):
    """Gauss-Newton steps onto the common zero set of the facets ``idx`` (``used`` of them per row)."""
    k = idx.shape[1]
    q = q.copy()
    jac = np.zeros((q.shape[0], k, 3))
    for _ in range(steps):
        val = ff.values_of(q, idx) * used      # only the leaves of the row's facets, at its point
        jac = ff.gradients_of(q, idx, 1e-6 * h) * used[:, :, None]
        _newton_step(q, jac, val, used)
    return q, jac


def _fans_and_flips(pts, exact, borders, feature, n, n_cells, x, room=None):
    """Fans of the feature cells (whose patch is one disc: `_cell_borders`), and the flips between them.

    Returns the new triangles, for each the cells it came from (two for a
    flipped pair, the second -1 otherwise) as ``owner`` (k, 2), the cells
    that received a vertex (vertex ``n + i`` is cell ``fan_cells[i]``), the
    points with those vertices appended (in the rows of `room` from ``n``
    on, when given: an array holding the points in its first rows, with
    rows enough) and which new triangles face badly (`_facing_badly`).  A
    flip is made only where both of its triangles face their ordinary
    vertices' normals.  Two compiled calls (`feature_kernels._fan_rows`, `_flip_fans`).
    """
    b0, b1, bc = borders
    n_fan = int(np.count_nonzero(feature))
    if n_fan == 0:
        return (np.empty((0, 3), np.int64), np.empty((0, 2), np.int64), np.empty(0, np.int64), pts,
                np.empty(0, np.bool_))
    if room is not None:
        newp = room[:n + n_fan]
    else:
        newp = np.empty((n + n_fan, 3))
        newp[:n] = pts
    normal, index = exact
    fan, owner, fan_cells, ekey = _fan_rows(b0, b1, bc, feature, n, x, newp)
    # (numpy's stable sort of the nearly sorted keys, its runs those of the cells, is the fastest way here)
    order = np.argsort(ekey, kind="stable")
    bad = _flip_fans(fan, owner, ekey, order, n, n_cells, normal, index, newp, COS_SHARP, MIN_FACING)
    return fan, owner, fan_cells, newp, bad


def _facing_badly(points, faces, exact, n):
    """New triangles that are degenerate, or do not face their ordinary vertices' exact normals
    (`exact`: the normals of the candidate cells' vertices and each vertex's row among them).

    A vertex next to an edge may belong to the other face, so a triangle
    must face the normal of one of its ordinary vertices (``cos >
    MIN_FACING``) and oppose none (``cos > -MIN_FACING``).
    """
    return _facing_kernel(points, np.ascontiguousarray(faces, dtype=np.int64), exact[0], exact[1], n, MIN_FACING)


def sharp_polydata(solid, points, faces, origin, h):
    """`sharpen` the mesh and return it as PolyData carrying the feature fields.

    One place for what the single-process mesher and the cluster's merged mesh
    both attach: ``feature_rank`` and ``feature_facets`` per point, the facet
    names and the count of feature cells.
    """
    return _polydata(solid, [points, faces], origin, h, overwrite=False)


def sharp_polydata_lent(solid, lent, origin, h):
    """`sharp_polydata` of ``lent = [points, faces]``, a list it empties, so that the pass can free
    the points once it no longer needs them and write its triangles over the lent ones (the caller
    keeps no other reference to them)."""
    return _polydata(solid, lent, origin, h, overwrite=True)


def _polydata(solid, lent, origin, h, overwrite):
    from ..files.surface import triangle_surface  # PolyData, or arrays for a job that only writes them

    sharp = _sharpen(solid, lent, origin, h, overwrite=overwrite)
    del lent
    out = triangle_surface(sharp["points"], sharp["faces"])
    out.point_data["feature_rank"] = sharp["feature_rank"]
    out.point_data["feature_facets"] = sharp["feature_facets"]
    out.field_data["facet_names"] = np.array(sharp["facet_names"] or [""])
    out.field_data["feature_cells"] = np.array([sharp["feature_cells"]], dtype=np.int64)
    return out
