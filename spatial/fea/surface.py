"""Surface meshes fit for volume meshing, and the CSG face regions they carry.

Raw marching-cubes surfaces hold triangles with angles far below one degree;
a tetrahedral mesher that keeps the surface turns them into slivers.  This
module remeshes the solid's feature mesh (`spatial.fea.surface_start`) to a
uniform target edge length by clustering (pyacvd, `spatial.fea.surface_clusters`), projects the new vertices
back onto the solid's zero set with Newton steps along the gradient, and snaps
vertices onto the sharp feature curves and onto the corners where faces of the
CSG tree meet (the faces come from `spatial.fea.facets.FacetField`; the
corners from the feature mesh, `spatial.fea.surface_corners`).

References
----------
S. Valette, J.-M. Chassery, R. Prost, "Generic remeshing of 3D triangular
meshes with metric-dependent discrete Voronoi diagrams", IEEE TVCG 14(2), 2008,
doi:10.1109/TVCG.2007.70430 (the clustering behind pyacvd).
L. Kobbelt, M. Botsch, U. Schwanecke, H.-P. Seidel, "Feature sensitive surface
extraction from volume data", SIGGRAPH 2001, doi:10.1145/383259.383265.
"""

from __future__ import annotations

import numpy as np

from implicit.solid import Solid, as_positive
from .facets import (FacetField, facet_field, independent_facets, project_to_surface, solve_on_facets,
                     value_and_gradient)
from .surface_clusters import _outward, cluster_mesh
from .surface_corners import exact_corners, snap_exact_corners
from .surface_faces import face_clusters
from .surface_quality import (SurfaceQuality, _deviation, _edges, _is_closed_manifold, _normals, _polydata,  # noqa: F401
                              _triangle_angles, enclosed, folded_triangles, mesh_faces, self_intersections, surface_quality)

__all__ = [
    "FacetField",
    "facet_field",
    "project_to_surface",
    "surface_for_fea",
    "SurfaceQuality",
    "surface_quality",
    "self_intersections",
    "mesh_faces",
]

#: Angle (degrees) under which a snapped triangle is rejected and its vertices unsnapped.
SNAP_MIN_ANGLE = 12.0
FLIP_COSINE = 0.1  #: least cosine of a flipped triangle's normal and the sum of the old two unit normals
#: Rounds of feature snapping and tangential relaxation.
SNAP_ROUNDS = 4
#: Relative difference of the enclosed volume from the feature mesh's over which the surface of free
#: clusters is made again with clusters confined to the faces (`spatial.fea.surface_faces`).
FACE_VOLUME_MISS = 0.005


# ---------------------------------------------------------------------------
# feature snapping
# ---------------------------------------------------------------------------

def _snap_features(ff: FacetField, points, faces, size, fixed, far=False):
    """Move vertices onto the curves where two facets meet (and corners of three).

    For every mesh edge whose end points are decided by different facets,
    the end point nearer the other facet is moved onto the two facets'
    intersection; a vertex claimed for three facets goes to their corner.
    Triangles that would collapse or flip keep their vertices unmoved.
    Returns the new points and the number of vertices snapped.
    """
    pts = points.copy()
    n = pts.shape[0]
    value, dec, fvals = ff(pts)
    edges = _edges(faces)
    a, b = edges[:, 0], edges[:, 1]
    cross = (dec[a] != dec[b]) & ~fixed[a] & ~fixed[b]
    a, b = a[cross], b[cross]
    if a.size == 0:
        return pts, 0
    # Distance estimate from each end to the other end's facet (closed-form gradients of those two facets only).
    grads = ff.gradients_of(np.concatenate([pts[a], pts[b]]), np.concatenate([dec[b], dec[a]]))
    nrm = np.linalg.norm(grads, axis=1)
    da = np.abs(fvals[dec[b], a]) / np.maximum(nrm[:a.size], 1e-12)
    db = np.abs(fvals[dec[a], b]) / np.maximum(nrm[a.size:], 1e-12)
    # The nearer end moves (the farther one in `far` rounds, for edges whose nearer end
    # could not move without spoiling a triangle).
    pick_a = (da <= db) != far
    vert = np.where(pick_a, a, b)
    other = np.where(pick_a, dec[b], dec[a])
    # Each vertex: its own facet plus up to two others (most frequent first).
    pairs = np.unique(np.stack([vert, other], axis=1), axis=0)
    order = np.argsort(pairs[:, 0], kind="stable")
    pairs = pairs[order]
    first = np.searchsorted(pairs[:, 0], pairs[:, 0], side="left")
    rank = np.arange(len(pairs)) - first
    pairs, rank = pairs[rank < 2], rank[rank < 2]
    sets = np.full((n, 3), -1, dtype=np.int64)
    sets[:, 0] = dec
    sets[pairs[:, 0], 1 + rank] = pairs[:, 1]
    moving = np.unique(pairs[:, 0])
    sets[moving] = _crossing_sets(ff, pts[moving], sets[moving], fvals[:, moving])
    new = solve_on_facets(ff, pts[moving], sets[moving])
    # Reject moves that are too far or leave the surface (the facets meet elsewhere).
    move = np.linalg.norm(new - pts[moving], axis=1)
    off = np.abs(ff.solid(new))
    ok = (move < 0.8 * size) & (off < 1e-6 * max(size, 1e-12) + 1e-9) & np.isfinite(new).all(axis=1)
    moving, new = moving[ok], new[ok]
    return _apply_snaps(pts, faces, moving, new)


def _on_edges(ff: FacetField, pts, fv, tol):
    """Whether each point lies on two crossing facets, ``(n,)`` bool.

    Coplanar faces of solids that touch (the bottoms of two boxes side by side)
    are both 0 all over their common plane: a point on them is on an edge only
    when a third, crossing facet passes there too (`independent_facets`).
    """
    near = np.abs(fv) < tol
    on = near.sum(axis=0) >= 2
    idx = np.flatnonzero(on)
    if idx.size:
        on[idx] = independent_facets(ff, pts[idx], near[:, idx], count=2)[:, 1] >= 0
    return on


def _crossing_sets(ff: FacetField, pts, sets, fv, parallel=0.99):
    """`sets` ``(n, 3)`` without the facets parallel to a point's own one (slot 0) that it lies on already.

    A point on the coplanar faces of two touching solids would otherwise be solved onto two parallel
    planes (no edge there) instead of onto the crossing facet beside it.  The facets kept move up.
    """
    out = sets.copy()
    rows = np.arange(len(pts))
    g0 = ff.gradients_of(pts, sets[:, 0])
    g0 /= np.maximum(np.linalg.norm(g0, axis=1), 1e-300)[:, None]
    scale = max(float(np.abs(pts).max(initial=0.0)), 1.0)
    for j in (1, 2):
        used = out[:, j] >= 0
        if not used.any():
            continue
        gj = ff.gradients_of(pts[used], out[used, j])
        cos = np.abs(np.einsum("ij,ij->i", gj, g0[used])) / np.maximum(np.linalg.norm(gj, axis=1), 1e-300)
        on = np.abs(fv[out[used, j], rows[used]]) < 1e-9 * scale
        drop = np.flatnonzero(used)[(cos > parallel) & on]
        out[drop, j] = -1
    # keep the used slots first
    order = np.argsort(out[:, 1:] < 0, axis=1, kind="stable")
    out[:, 1:] = np.take_along_axis(out[:, 1:], order, axis=1)
    return out


def _apply_snaps(pts, faces, moving, new):
    """Move vertices `moving` to `new`, then undo moves that fold or sharpen a triangle."""
    n = pts.shape[0]
    before_n = _normals(pts, faces)
    cand = pts.copy()
    cand[moving] = new
    snapped = np.zeros(n, dtype=bool)
    snapped[moving] = True
    for _ in range(10):
        ang = _triangle_angles(cand, faces)
        after_n = _normals(cand, faces)
        flipped = np.einsum("ij,ij->i", before_n, after_n) <= 0
        bad = (ang.min(axis=1) < SNAP_MIN_ANGLE) | flipped
        bad &= snapped[faces].any(axis=1)
        if not bad.any():
            break
        # Unsnap, in each bad triangle, the snapped vertex that moved the most.
        fb = faces[bad]
        dist = np.linalg.norm(cand[fb] - pts[fb], axis=2) * snapped[fb]
        worst = fb[np.arange(len(fb)), dist.argmax(axis=1)]
        cand[worst] = pts[worst]
        snapped[worst] = False
    return cand, int(snapped.sum())


def _snap_corners(ff: FacetField, points, faces, size, tol):
    """Put one vertex on each corner where three facets meet.

    A mesh edge whose two ends lie on three or more facets between them
    (e.g. one end on an edge of the part, the other on another edge) has a
    corner nearby: the three facets' common point.  Of all the vertices next
    to a corner, the nearest moves onto it (unless one is there already).
    Returns the new points and the number of vertices moved.
    """
    pts = points
    _, _, fv = ff(pts)
    near = np.abs(fv) < tol  # (k, n)
    edges = _edges(faces)
    a, b = edges[:, 0], edges[:, 1]
    union = near[:, a] | near[:, b]
    cand = (union.sum(axis=0) >= 3) & near[:, a].any(axis=0) & near[:, b].any(axis=0)
    if not cand.any():
        return pts, 0
    a, b, union = a[cand], b[cand], union[:, cand]
    # Three crossing facets of the union (not two coplanar ones), solved from the edge's midpoint.
    sets = independent_facets(ff, 0.5 * (pts[a] + pts[b]), union, count=3)
    full = (sets >= 0).all(axis=1)
    if not full.any():
        return pts, 0
    a, b, union, sets = a[full], b[full], union[:, full], sets[full]
    corner = solve_on_facets(ff, 0.5 * (pts[a] + pts[b]), sets, iters=12)
    _, _, fc = ff(corner)
    rows = np.arange(len(a))
    ok = np.isfinite(corner).all(axis=1) & (np.abs(ff.solid(corner)) < tol)
    ok &= np.all(np.abs(fc[sets, rows[:, None]]) < tol, axis=1)
    da = np.linalg.norm(pts[a] - corner, axis=1)
    db = np.linalg.norm(pts[b] - corner, axis=1)
    vert = np.where(da <= db, a, b)
    dist = np.minimum(da, db)
    ok &= dist < 0.8 * size
    vert, corner, dist = vert[ok], corner[ok], dist[ok]
    if vert.size == 0:
        return pts, 0
    # One vertex per corner (the nearest), none where a vertex is already on it.
    key = np.round(corner / (1e-3 * size)).astype(np.int64)
    _, group = np.unique(key, axis=0, return_inverse=True)
    group = group.reshape(-1)
    order = np.lexsort((dist, group))
    first = np.ones(order.size, dtype=bool)
    first[1:] = group[order][1:] != group[order][:-1]
    pick = order[first]
    pick = pick[dist[pick] > tol]
    # A vertex near two corners goes to the nearer.
    order = np.lexsort((dist[pick], vert[pick]))
    pick = pick[order]
    keep = np.ones(pick.size, dtype=bool)
    keep[1:] = vert[pick][1:] != vert[pick][:-1]
    pick = pick[keep]
    if pick.size == 0:
        return pts, 0
    return _apply_snaps(pts, faces, vert[pick], corner[pick])


def _flip_across_features(ff: FacetField, points, faces, fixed, evaluated=None, chords=False):
    """Flip edges that cross a feature curve between two vertices lying on it.

    An edge ``(a, b)`` whose ends are decided by different facets and do not
    lie together on one feature, and whose two opposite vertices ``c``, ``d``
    lie together on one feature curve (two common facets), is replaced by
    ``(c, d)``, which then runs along the feature.  Flips that would fold a
    triangle are skipped.  `evaluated` is ``ff(points)`` when the caller has it.  With `chords`, a
    flip is made only when the midpoint of ``(c, d)`` lies on their common facets within a tenth of
    its length.
    Returns new faces.
    """
    _, dec, fv = ff(points) if evaluated is None else evaluated
    near = np.abs(fv) < 1e-7 * max(float(np.ptp(points, axis=0).max()), 1.0)
    m = len(faces)
    he_a = faces.reshape(-1)
    he_b = faces[:, [1, 2, 0]].reshape(-1)
    he_c = faces[:, [2, 0, 1]].reshape(-1)
    he_f = np.repeat(np.arange(m), 3)
    key = np.minimum(he_a, he_b) * (points.shape[0] + 1) + np.maximum(he_a, he_b)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    pair = np.nonzero(ks[1:] == ks[:-1])[0]
    h1, h2 = order[pair], order[pair + 1]
    a, b, c, d = he_a[h1], he_b[h1], he_c[h1], he_c[h2]
    f1, f2 = he_f[h1], he_f[h2]
    along_ab = (near[:, a] & near[:, b]).sum(axis=0) >= 2
    along_cd = (near[:, c] & near[:, d]).sum(axis=0) >= 2
    cand = (dec[a] != dec[b]) & ~along_ab & along_cd & fixed[c] & fixed[d] & (c != d)
    a, b, c, d, f1, f2 = (x[cand] for x in (a, b, c, d, f1, f2))
    # One flip per face.
    used = np.concatenate([f1, f2])
    uniq, counts = np.unique(used, return_counts=True)
    once = np.zeros(m, dtype=bool)
    once[uniq[counts == 1]] = True
    keep = once[f1] & once[f2]
    a, b, c, d, f1, f2 = (x[keep] for x in (a, b, c, d, f1, f2))
    if a.size == 0:
        return faces
    if chords:
        # The chord (c, d) must follow the feature: on a face bent at the vertices of a polygon (a gear's
        # flanks) two nodes of one rim may share the face's two facets across a bend.
        mid = 0.5 * (points[c] + points[d])
        common = near[:, c] & near[:, d]
        off = np.max(np.abs(ff.facet_values(mid)) * common, axis=0)
        follows = off <= 0.1 * np.linalg.norm(points[c] - points[d], axis=1)
        a, b, c, d, f1, f2 = (x[follows] for x in (a, b, c, d, f1, f2))
        if a.size == 0:
            return faces
    # Half-edge a->b lies in f1 as (a, b, c); f2 holds (b, a, d).  New: (c, a, d), (d, b, c).
    n_old = _normals(points, faces)
    t1 = np.stack([c, a, d], axis=1)
    t2 = np.stack([d, b, c], axis=1)
    ref = n_old[f1] + n_old[f2]
    ok = (np.einsum("ij,ij->i", _normals(points, t1), ref) > 0) & (np.einsum("ij,ij->i", _normals(points, t2), ref) > 0)
    ok &= (_triangle_angles(points, t1).min(axis=1) > SNAP_MIN_ANGLE) & (_triangle_angles(points, t2).min(axis=1) > SNAP_MIN_ANGLE)
    # Three nodes of a feature curve round its bend (a gear's tooth tip) make a triangle square to both old ones: turned over.
    u1, u2, v1, v2 = (x / np.maximum(np.linalg.norm(x, axis=1), 1e-300)[:, None] for x in (n_old[f1], n_old[f2], _normals(points, t1), _normals(points, t2)))
    ok &= (np.einsum("ij,ij->i", v1, u1 + u2) > FLIP_COSINE) & (np.einsum("ij,ij->i", v2, u1 + u2) > FLIP_COSINE)
    out = faces.copy()
    out[f1[ok]] = t1[ok]
    out[f2[ok]] = t2[ok]
    return out


# ---------------------------------------------------------------------------
# the surface pipeline
# ---------------------------------------------------------------------------

def _neighbour_mean_matrix(faces, n):
    """Sparse ``(n, n)`` matrix taking vertex positions to the mean of each vertex's neighbours.

    Every edge is counted once per triangle side it is (twice on a closed
    surface), which weighs all neighbours alike.
    """
    from scipy.sparse import csr_matrix

    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    rows = np.concatenate([e[:, 0], e[:, 1]])
    cols = np.concatenate([e[:, 1], e[:, 0]])
    deg = np.bincount(rows, minlength=n).astype(np.float64)
    weight = 1.0 / np.maximum(deg, 1.0)[rows]
    return csr_matrix((weight, (rows, cols)), shape=(n, n))


def _tangential_relax(solid, points, faces, fixed, iterations=3, steps=3):
    """Move free vertices toward their neighbours' mean in the tangent plane, then reproject.

    The neighbour means come from one sparse matrix built once; each Newton
    step of the reprojection evaluates the field and its gradient in one call,
    and the gradient of the last step gives the next iteration's tangent plane.
    """
    p = points.copy()
    free = np.nonzero(~np.asarray(fixed, dtype=bool))[0]
    if free.size == 0:
        return p
    mean_of = _neighbour_mean_matrix(faces, p.shape[0])
    h = _gradient_step(solid)
    gq = solid.gradient(p[free], step=h)
    for it in range(iterations):
        gf = gq / np.maximum(np.linalg.norm(gq, axis=1), 1e-300)[:, None]
        d = (mean_of @ p)[free] - p[free]
        d -= np.einsum("ij,ij->i", d, gf)[:, None] * gf
        q = p[free] + 0.5 * d
        # A tangential step leaves the point off a curved surface by about curvature * step^2: one
        # Newton step takes that to its square, enough for the next iteration; the last one converges.
        for _ in range(steps if it == iterations - 1 else 1):
            f, gq = value_and_gradient(solid, q, h)
            g2 = np.einsum("ij,ij->i", gq, gq)
            ok = g2 > 1e-12
            q[ok] -= (f[ok] / g2[ok])[:, None] * gq[ok]
        p[free] = q
    return p


def _gradient_step(solid):
    """The finite-difference step `project_to_surface` uses for `solid`."""
    lo, hi = solid.bounds
    ext = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
    return 1e-7 * max(float(np.max(ext)), 1.0)


def _crossings(surface, solid):
    """Triangles of `surface` that pierce another, plus (given the solid) those turned over onto their face."""
    crossing = self_intersections(surface)
    if solid is not None:
        crossing += folded_triangles(solid, np.asarray(surface.points), mesh_faces(surface))
    return crossing


def _remesh(mesh, corner_mesh, solid, size, size_field, split_sides, chords):
    """Cluster `mesh` to edges of about `size`, then put the nodes on `solid`'s faces, edges and corners
    (`chords`: flips only onto chords that follow a feature, for the feature mesh's start).

    Returns the points, the triangles (outward) and the number of nodes snapped onto an edge or corner.
    """
    pts, faces = cluster_mesh(mesh, size, size_field, move_centres=solid is None)
    snapped = 0
    if solid is not None:
        pts = project_to_surface(solid, pts, max_move=size)
        ff = FacetField(solid, split_sides=split_sides)
        fixed = np.zeros(pts.shape[0], dtype=bool)
        for rnd in range(SNAP_ROUNDS):
            pts, count = _snap_features(ff, pts, faces, size, fixed, far=rnd % 2 == 1)
            snapped += count
            # Keep vertices that sit on two facets; relax the others.
            evaluated = ff(pts)
            fixed = _on_edges(ff, pts, evaluated[2], 1e-7 * max(size, 1.0))
            faces = _flip_across_features(ff, pts, faces, fixed, evaluated, chords)
            pts = _tangential_relax(solid, pts, faces, fixed)
        tol = 1e-7 * max(size, 1.0)
        pts, count = _snap_corners(ff, pts, faces, size, tol)
        snapped += count
        if count:
            evaluated = ff(pts)
            fixed = _on_edges(ff, pts, evaluated[2], tol)
            faces = _flip_across_features(ff, pts, faces, fixed, evaluated, chords)
            pts = _tangential_relax(solid, pts, faces, fixed)
        pts, count, _ = snap_exact_corners(pts, faces, exact_corners(ff, corner_mesh), size, tol, _apply_snaps,
                                           lambda p, f, held: _tangential_relax(solid, p, f, held), fixed)
        snapped += count
    return pts, faces, snapped


def _confined_surface(mesh, solid, size, split_sides, result, crossing):
    """The surface of clusters confined to the faces of `solid` (`spatial.fea.surface_faces`) in place
    of `result` (free clusters of feature mesh `mesh`, `crossing` triangles piercing others) when
    that misses the feature mesh's volume by more than `FACE_VOLUME_MISS` or pierces itself, and the
    confined one pierces nothing, comes closer to that volume and has no angle under
    `SNAP_MIN_ANGLE`: ``(points, faces, nodes on corners and curves, surface)``, or None.  A wall as
    thick as `size` has free clusters spanning its whole section."""
    want = abs(enclosed(mesh))
    miss = abs(abs(enclosed(result)) - want) / max(want, 1e-300)
    if not crossing and miss <= FACE_VOLUME_MISS:
        return None
    p, f, fixed = face_clusters(mesh, FacetField(solid, split_sides=split_sides), size)
    if p is None:
        return None
    f = _outward(p, f)
    p = _tangential_relax(solid, p, f, fixed)
    surface = _polydata(p, f)
    limit = max(miss, FACE_VOLUME_MISS) if crossing else miss
    if abs(abs(enclosed(surface)) - want) / max(want, 1e-300) >= limit or _crossings(surface, solid) \
            or _triangle_angles(p, f).min() < SNAP_MIN_ANGLE:
        return None
    return p, f, int(fixed.sum()), surface


def surface_for_fea(solid_or_mesh, *, size, solid=None, max_deviation=None, voxel_size=None,
                    check_intersections=True, size_field=None, split_sides=False, start=None, feature_mesh=None):
    """A closed, outward, uniform triangle surface of target edge length `size`.

    The pipeline: mesh a `Solid` with its sharp features (`spatial.mesh`,
    ``features=True``); merge duplicate points and drop degenerate triangles;
    remesh by clustering (pyacvd) to about ``1.15 area / size^2`` vertices;
    repair with MeshFix when the result is not closed and manifold; then,
    when a `Solid` is known, project every vertex onto its zero set (Newton
    steps along the gradient), relax vertices tangentially and snap vertices
    onto the sharp edges where two facets of the CSG tree meet
    (`FacetField`).  The result is outward-oriented.

    Parameters
    ----------
    solid_or_mesh : Solid or pyvista.PolyData
        The solid (meshed first with `spatial.mesh`) or a closed surface mesh
        of it, e.g. from marching cubes.
    size : float
        Target edge length.
    solid : Solid, optional
        The solid a mesh came from; enables projection and feature snapping.
    max_deviation : float, optional
        Largest allowed ``|f|`` at vertices and face centres; a `ValueError`
        is raised when the result deviates more.  Needs a solid.
    voxel_size : float, optional
        Cell size used to mesh a `Solid` first (default ``size / 4``).
    check_intersections : bool
        Test the result for self-intersecting triangles (pymeshfix) and raise
        when there are any.
    size_field : spatial.fea.graded.SizeField, optional
        A target edge length that varies over the surface (at most `size`):
        the clusters are weighted by it (`spatial.fea.graded`).
    split_sides : bool
        Snap onto the sharp corners of extruded polygons too (`FacetField`).
    start : {"features", "plain"}, optional
        The marching-cubes mesh a `Solid` is clustered from: its feature mesh
        (`spatial.mesh(..., features=True)`, the default for a uniform size),
        or the plain mesh of the solid grown by a twentieth of a voxel (the
        default with a graded `size_field`; `tet_mesh` starts those from the
        feature mesh, `spatial.fea.graded_surface`).  Either way the
        feature mesh's corners become nodes.  A surface from the feature mesh
        that intersects itself is made again from the plain mesh
        (``field_data["start"]`` says which one was used).  A surface from the feature mesh that
        misses its volume by more than `FACE_VOLUME_MISS` or intersects itself is made first with
        clusters confined to the faces, `spatial.fea.surface_faces` (``field_data["clusters"]``:
        ``"faces"``, else ``"free"``).
    feature_mesh : pyvista.PolyData, optional
        The solid's feature mesh at the voxel size (`voxel_size`, default ``size / 4``) when made
        already: ``spatial.mesh(solid, voxel_size=..., features=True, progress=False)``
        (`tet_mesh` measures the solid's volume on it too).

    Returns
    -------
    pyvista.PolyData
        Triangles; ``field_data`` holds ``max_deviation`` (when a solid is
        known), ``snapped_vertices``, ``start``, ``clusters`` and ``size`` (the size it was made at).

    Raises
    ------
    TypeError
        When `solid_or_mesh` is neither a Solid nor a PolyData.
    ValueError
        When `size` is not positive, the deviation exceeds `max_deviation`,
        or the result intersects itself.

    Examples
    --------
    >>> import pyvista as pv
    >>> from implicit import sphere
    >>> s = surface_for_fea(pv.Sphere(radius=1.0, theta_resolution=60, phi_resolution=60),
    ...                     size=0.3, solid=sphere(1.0))
    >>> q = surface_quality(s, sphere(1.0))
    >>> q.closed, bool(q.min_angle > 20), bool(q.max_deviation < 0.03)
    (True, True, True)
    """
    import pyvista as pv

    size = as_positive(size, "size")
    if isinstance(solid_or_mesh, Solid):
        if solid is not None and solid is not solid_or_mesh:
            raise ValueError("solid: give the solid once (as the first argument or as solid=)")
        solid = solid_or_mesh
        mesh = None
    elif isinstance(solid_or_mesh, pv.PolyData):
        mesh = corner_mesh = solid_or_mesh
        kind = "given"
    else:
        raise TypeError(f"solid_or_mesh: expected a Solid or a pyvista.PolyData, got {type(solid_or_mesh).__name__}")
    if solid is not None and not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if max_deviation is not None:
        max_deviation = as_positive(max_deviation, "max_deviation")
        if solid is None:
            raise ValueError("max_deviation: needs the solid (solid=) to measure the deviation")
    if voxel_size is not None:
        voxel_size = as_positive(voxel_size, "voxel_size")
    if feature_mesh is not None:
        if not isinstance(feature_mesh, pv.PolyData):
            raise TypeError(f"feature_mesh: expected a pyvista.PolyData, got {type(feature_mesh).__name__}")
        if mesh is not None:
            raise ValueError("feature_mesh: only applies to a Solid (a mesh given is clustered as it is)")
    if start is None:
        start = "plain" if size_field is not None and not size_field.uniform else "features"
    if start not in ("features", "plain"):
        raise ValueError(f"start: expected 'features' or 'plain', got {start!r}")
    if mesh is None:
        if not solid.is_bounded or solid.is_empty_bounds:
            raise ValueError("solid_or_mesh: expected a bounded, non-empty solid")
        from .surface_start import start_mesh

        h = voxel_size or (size if size_field is None else size_field.smallest) / 4.0
        # One marching-cubes mesh: the feature mesh starts the clustering and its corners become nodes.
        mesh, corner_mesh, kind = start_mesh(solid, h, start, feature_mesh)
    if mesh.n_cells == 0:
        raise ValueError("solid_or_mesh: the mesh has no cells")

    pts, faces, snapped = _remesh(mesh, corner_mesh, solid, size, size_field, split_sides, kind == "features")
    result = _polydata(pts, faces)
    crossing = _crossings(result, solid) if check_intersections or kind == "features" else 0
    clusters = "free"
    if kind == "features" and (size_field is None or size_field.uniform):
        confined = _confined_surface(mesh, solid, size, split_sides, result, crossing)
        if confined is not None:
            pts, faces, snapped, result = confined
            crossing, clusters = 0, "faces"
    if crossing and kind == "features":
        # Clustered from the feature mesh, the surface pierces itself: the plain start at the same size.
        mesh, corner_mesh, kind = start_mesh(solid, h, "plain", corner_mesh)
        pts, faces, snapped = _remesh(mesh, corner_mesh, solid, size, size_field, split_sides, kind == "features")
        result = _polydata(pts, faces)
        crossing = _crossings(result, solid) if check_intersections else 0
    result.field_data["snapped_vertices"] = np.array([snapped])
    result.field_data["start"] = np.array([kind])
    result.field_data["clusters"] = np.array([clusters])
    result.field_data["size"] = np.array([size])
    if solid is not None:
        dev = _deviation(solid, pts, faces)
        result.field_data["max_deviation"] = np.array([dev])
        if max_deviation is not None and dev > max_deviation:
            raise ValueError(f"max_deviation: the remeshed surface deviates {dev:.3g} from the solid, "
                             f"more than {max_deviation:.3g}; use a smaller size")
    if crossing and check_intersections:
        raise ValueError(f"size: the remeshed surface has {crossing} self-intersecting (or folded) triangles at size "
                         f"{size:g}; use a smaller size")
    return result

