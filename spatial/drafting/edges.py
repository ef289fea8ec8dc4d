"""Feature edges and silhouettes of a boundary mesh, snapped to the solid.

A marching-cubes mesh chamfers every sharp edge with a strip of triangles;
the dihedral angles inside that strip are half the true angle each, so
thresholding mesh normals draws every edge twice.  Here every triangle takes
the exact normal of the CSG leaf whose surface it lies on (the leaf with the
smallest ``|field|`` at its centroid, its gradient by central differences):
across a chamfer strip those normals jump once, from one face to the other,
and an edge is drawn where two neighbouring triangles' exact normals differ
by more than `FEATURE_ANGLE`.  The chain of mesh vertices along that jump is
then moved onto the true edge by a small quadric error fit (the tangent
planes of the triangles around each vertex, as dual contouring places its
vertices), so a straight edge comes out straight and a corner sharp.

Faces lying exactly on lattice planes (round sizes at round resolutions)
leave chamfers of zero width that draw an edge twice: mesh for drawings
with `spatial.drafting.part_views.part_mesh`, which shifts the lattice.

Silhouettes depend on the view: on the curved triangles (whose exact
normals vary), the zero set of ``normal . direction`` interpolated between
vertices (marching triangles) is the contour of the surface seen along
`direction`.

References
----------
T. Ju, F. Losasso, S. Schaefer, J. Warren, "Dual Contouring of Hermite Data",
SIGGRAPH 2002 (vertex placement by a truncated pseudo-inverse).

Examples
--------
>>> from implicit import box
>>> from spatial.drafting.part_views import part_mesh
>>> m = part_mesh(box((4, 2, 1)), resolution=24)
>>> lines = surface_edges(m, box((4, 2, 1)))
>>> round(sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in lines.polylines))  # 4 x (4 + 2 + 1)
28
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .csg_features import leaf_gradients, leaves, nearest_leaf

__all__ = ["FEATURE_ANGLE", "SurfaceEdges", "surface_edges", "silhouettes", "strip_segments"]

#: Smallest angle (degrees) between the faces of a drawn edge; tangent edges are not drawn.
FEATURE_ANGLE = 20.0

#: Step of the finite differences for exact normals, in voxels: small, so that a point near
#: the bisector of a box edge takes the normal of one face and not a mixture of both.
GRADIENT_STEP = 1e-5

#: Vertex normals differing by less than this (radians) make a triangle flat: it has no silhouette.
_FLAT = 1e-4

#: Corner normals differing by more than this (degrees) straddle an edge rather than a curved face.
_CURVED_MAX = 35.0


@dataclass
class SurfaceEdges:
    """Sharp edges of a surface and what silhouettes need.

    Attributes
    ----------
    polylines : list of (k, 3) float
        Feature edges in world coordinates, chained.
    points : (n, 3) float
        Mesh vertices.
    triangles : (t, 3) int
    corner_normals : (t, 3, 3) float
        Exact outward normal at each triangle's three vertices.
    curved : (t,) bool
        Triangles on curved faces (the only ones with silhouettes).
    voxel_size : float
    """

    polylines: list
    points: np.ndarray
    triangles: np.ndarray
    corner_normals: np.ndarray
    curved: np.ndarray
    voxel_size: float


def _triangles(mesh) -> np.ndarray:
    faces = np.asarray(mesh.faces)
    if faces.size == 0:
        return np.zeros((0, 3), dtype=np.int64)
    if faces.size % 4 or np.any(faces.reshape(-1, 4)[:, 0] != 3):
        mesh = mesh.triangulate()
        faces = np.asarray(mesh.faces)
    return faces.reshape(-1, 4)[:, 1:].astype(np.int64)


def _edge_pairs(tris: np.ndarray):
    """Unique edges ``(e, 2)`` and the two triangles on each ``(e, 2)`` (-1 on a border)."""
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    owner = np.tile(np.arange(len(tris)), 3)
    e = np.sort(e, axis=1)
    n = int(tris.max()) + 1
    keys, inv = np.unique(e[:, 0] * n + e[:, 1], return_inverse=True)
    uniq = np.column_stack([keys // n, keys % n])
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    counts = np.bincount(inv, minlength=len(uniq))
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    first = owner[order[starts]]
    second = np.where(counts >= 2, owner[order[np.minimum(starts + 1, len(order) - 1)]], -1)
    return uniq, np.column_stack([first, second])


def strip_segments(points: np.ndarray, segments: np.ndarray) -> list[np.ndarray]:
    """Join segments ``(s, 2)`` of vertex indices into polylines (VTK's stripper)."""
    if len(segments) == 0:
        return []
    import pyvista as pv

    lines = np.column_stack([np.full(len(segments), 2), segments]).ravel()
    poly = pv.PolyData(np.asarray(points, dtype=float), lines=lines)
    stripped = poly.strip(join=True, max_length=1_000_000)
    cells = np.asarray(stripped.lines)
    pts = np.asarray(stripped.points)
    out = []
    i = 0
    while i < len(cells):  # one step per polyline, not per point
        n = int(cells[i])
        out.append(pts[cells[i + 1:i + 1 + n]])
        i += n + 1
    return out


def _snap(points, tris, edges, c_points, c_normals, feature):
    """Move the vertices of feature edges onto the intersection of the face planes.

    Each such vertex takes the tangent planes of all triangles around it: two
    faces put it on their edge, three (near a corner) on the corner.
    """
    on_edge = np.zeros(len(points), dtype=bool)
    on_edge[edges[feature].ravel()] = True
    vert = tris.ravel()
    tri = np.repeat(np.arange(len(tris)), 3)
    keep = on_edge[vert]
    vert, tri = vert[keep], tri[keep]
    n = c_normals[tri]
    d = np.einsum("ij,ij->i", n, c_points[tri])
    moved, slot = np.unique(vert, return_inverse=True)
    slot = slot.ravel()
    a = np.zeros((len(moved), 3, 3))
    b = np.zeros((len(moved), 3))
    np.add.at(a, slot, n[:, :, None] * n[:, None, :])
    np.add.at(b, slot, n * d[:, None])
    w, v = np.linalg.eigh(a)
    x0 = points[moved]
    rhs = b - np.einsum("ijk,ik->ij", a, x0)
    # Truncated pseudo-inverse: directions without a plane (along an edge) keep the vertex.
    keep = w > 0.05 * w[:, -1:]
    inv_w = np.where(keep, 1.0 / np.where(keep, w, 1.0), 0.0)
    step = np.einsum("ijk,ik->ij", v, inv_w * np.einsum("ikj,ik->ij", v, rhs))
    out = points.copy()
    out[moved] = x0 + step
    return out


def surface_edges(mesh, solid=None, *, feature_angle: float = FEATURE_ANGLE) -> SurfaceEdges:
    """Sharp edges of `mesh`, exact when `solid` (the meshed CSG tree) is given.

    Parameters
    ----------
    mesh : pyvista.PolyData
        A closed triangle mesh (`spatial.mesh`).
    solid : implicit.Solid, optional
        The solid the mesh came from; without it the mesh normals are used
        (edges then come out as the chamfer's double lines).
    feature_angle : float
        Degrees between face normals for an edge to be drawn.

    Returns
    -------
    SurfaceEdges
    """
    if not 0 < feature_angle < 180:
        raise ValueError(f"feature_angle: expected degrees between 0 and 180, got {feature_angle!r}")
    marched = "voxel_size" in mesh.field_data
    if not marched:
        # A mesh from elsewhere may repeat its vertices face by face: merge them first.
        mesh = mesh.clean()
    points = np.asarray(mesh.points, dtype=float)
    tris = _triangles(mesh)
    h = float(np.asarray(mesh.field_data["voxel_size"]).ravel()[0]) if marched else 0.0
    if h <= 0 and len(tris):
        h = float(np.median(np.linalg.norm(points[tris[:, 1]] - points[tris[:, 0]], axis=1)))
    if len(tris) == 0:
        return SurfaceEdges([], points, tris, np.zeros((0, 3, 3)), np.zeros(0, bool), h)
    corners = points[tris]
    centroids = corners.mean(axis=1)
    if solid is not None:
        leaf_list = leaves(solid)
        label = nearest_leaf(leaf_list, centroids)
        sign = np.where([leaf.negative for leaf in leaf_list], -1.0, 1.0)[label]
        f, g = leaf_gradients(leaf_list, label, centroids, GRADIENT_STEP * h)
        c_normals = g * sign[:, None]
        c_points = centroids - f[:, None] * g
        # Corner normals once per (vertex, leaf) pair: most vertices have one leaf around them.
        pair = tris.ravel() * len(leaf_list) + np.repeat(label, 3)
        keys, inv = np.unique(pair, return_inverse=True)
        fv, gv = leaf_gradients(leaf_list, keys % len(leaf_list), points[keys // len(leaf_list)], GRADIENT_STEP * h)
        gv = gv[inv.ravel()]
        fv = fv[inv.ravel()]
        if "feature_rank" in mesh.point_data:
            # A feature mesh puts vertices on the edges, where a leaf's gradient is that of either
            # face: there each corner takes it a little way into its own triangle.
            sharp = np.flatnonzero(np.asarray(mesh.point_data["feature_rank"])[tris.ravel()] > 0)
            at = points[tris.ravel()[sharp]]
            at = at + 0.02 * (np.repeat(centroids, 3, axis=0)[sharp] - at)
            fs, gs = leaf_gradients(leaf_list, np.repeat(label, 3)[sharp], at, GRADIENT_STEP * h)
            gv[sharp], fv[sharp] = gs, fs
        corner_normals = gv.reshape(-1, 3, 3) * sign[:, None, None]
        # A triangle whose corners are not all on its leaf's surface straddles two leaves.
        on_leaf = (np.abs(fv) < 0.02 * h).reshape(-1, 3).all(axis=1)
    else:
        nrm = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        c_normals = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
        c_points = centroids
        corner_normals = np.repeat(c_normals[:, None, :], 3, axis=1)
        on_leaf = np.ones(len(tris), dtype=bool)
    edges, pairs = _edge_pairs(tris)
    curves = _sharp_curves(mesh, points, tris, edges, pairs, feature_angle) if solid is not None else None
    inner = pairs[:, 1] >= 0
    cos = np.full(len(edges), -1.0)
    cos[inner] = np.einsum("ij,ij->i", c_normals[pairs[inner, 0]], c_normals[pairs[inner, 1]])
    feature = cos < np.cos(np.radians(feature_angle))
    if curves is not None:
        # The feature curves are the edges between CSG faces; corners inside one face (a
        # tooth's tip on a gear's profile) are still found where the exact normals jump.
        curves, on_curve = curves
        feature &= ~(on_curve[edges[:, 0]] & on_curve[edges[:, 1]])
    snapped = _snap(points, tris, edges, c_points, c_normals, feature) \
        if solid is not None and feature.any() else points
    polylines = strip_segments(snapped, edges[feature])
    if marched:
        # Only marching cubes leaves its voxel-sized links at corners.
        polylines = join_corners(polylines, h)
    if curves is not None:
        polylines = [p for p in polylines if _length(p) > 2.5 * h] + curves
    spread = np.einsum("ij,ij->i", corner_normals[:, 0], corner_normals[:, 1])
    spread = np.minimum(spread, np.einsum("ij,ij->i", corner_normals[:, 0], corner_normals[:, 2]))
    # Chamfer triangles across a sharp edge have corners on two faces: not a curved face.
    curved = (spread < np.cos(_FLAT)) & (spread > np.cos(np.radians(_CURVED_MAX))) & on_leaf
    return SurfaceEdges(polylines, points, tris, corner_normals, curved, h)


def _sharp_curves(mesh, points, tris, edges, pairs, feature_angle):
    """The meshing room's sharp feature curves (`spatial.meshing.feature_edges`) of a mesh made
    with ``features=True``, less the tangent ones (faces meeting within `feature_angle`), and
    which mesh vertices they run through; None when the mesh has none (a mesh or field with
    no CSG faces)."""
    if "feature_rank" not in mesh.point_data:
        return None
    from ..meshing import feature_edges

    curves = feature_edges(mesh)
    if not curves.polylines:
        return None
    on_curve = np.zeros(len(points), dtype=bool)
    on_curve[np.concatenate(curves.vertices)] = True
    # The mesh's own dihedral angle along each curve: a feature mesh has its triangles on the faces.
    corners = points[tris]
    nrm = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    n = len(points)
    keys = edges[:, 0] * n + edges[:, 1]
    inner = pairs[:, 1] >= 0
    cos = np.ones(len(edges))
    cos[inner] = np.einsum("ij,ij->i", nrm[pairs[inner, 0]], nrm[pairs[inner, 1]])
    segments = []
    for verts in curves.vertices:  # one step per curve
        a, b = np.minimum(verts[:-1], verts[1:]), np.maximum(verts[:-1], verts[1:])
        at = np.clip(np.searchsorted(keys, a * n + b), 0, len(keys) - 1)
        found = keys[at] == a * n + b
        if found.any() and np.median(cos[at[found]]) > np.cos(np.radians(feature_angle)):
            continue
        segments.append(np.column_stack([a, b]))
    if not segments:
        return [], on_curve
    # Chained where they share vertices, then drawn on to where they meet: the curves come
    # in pieces, and stop short of corners by up to a few voxels.
    lines = strip_segments(points, np.unique(np.concatenate(segments), axis=0))
    h = float(np.asarray(mesh.field_data["voxel_size"]).ravel()[0])
    lines = lines + _bridges(lines, h, reach=16.0)
    return _chain(join_corners(lines, h, reach=6.0, extend=True)), on_curve


def _chain(lines: list) -> list:
    """Polylines that share end points joined into one (VTK's stripper on the merged points)."""
    if not lines:
        return lines
    pts = np.concatenate(lines)
    uniq, inv = np.unique(pts, axis=0, return_inverse=True)
    inv = inv.ravel()
    sizes = np.array([len(p) for p in lines])
    last = np.cumsum(sizes) - 1
    keep = np.ones(len(pts) - 1, dtype=bool)
    keep[last[:-1]] = False   # no segment from one line's end to the next line's start
    seg = np.column_stack([inv[:-1], inv[1:]])[keep]
    seg = seg[seg[:, 0] != seg[:, 1]]
    return strip_segments(uniq, np.unique(np.sort(seg, axis=1), axis=0))


def _bridges(lines: list, h: float, *, reach: float) -> list:
    """Straight pieces across the breaks of curves: two ends within `reach` voxels, each
    heading for the other (the chord of a break that short is within a voxel of the curve)."""
    from scipy.spatial import cKDTree

    ends, dirs = [], []
    for p in lines:  # one step per polyline
        if len(p) < 2 or np.allclose(p[0], p[-1]):
            continue
        for tip, back in ((p[0], p[min(3, len(p) - 1)]), (p[-1], p[max(-4, -len(p))])):
            d = tip - back
            ends.append(tip)
            dirs.append(d / max(np.linalg.norm(d), 1e-300))
    if len(ends) < 2:
        return []
    ends, dirs = np.array(ends), np.array(dirs)
    pairs = cKDTree(ends).query_pairs(reach * h, output_type="ndarray")
    if len(pairs) == 0:
        return []
    gap = ends[pairs[:, 1]] - ends[pairs[:, 0]]
    length = np.linalg.norm(gap, axis=1)
    unit = gap / np.maximum(length, 1e-300)[:, None]
    # Closer than half a voxel, any two ends meet (the pieces of a rim step across each other).
    heading = ((np.einsum("ij,ij->i", dirs[pairs[:, 0]], unit) > 0.95) &
               (np.einsum("ij,ij->i", dirs[pairs[:, 1]], -unit) > 0.95)) | (length < 0.5 * h)
    heading &= length > 1e-9 * h
    pairs, length = pairs[heading], length[heading]
    # Each end bridged once, to its nearest partner.
    order = np.argsort(length)
    used = np.zeros(len(ends), dtype=bool)
    out = []
    for a, b in pairs[order]:  # one step per candidate break
        if not (used[a] or used[b]):
            used[a] = used[b] = True
            out.append(np.array([ends[a], ends[b]]))
    return out


def _length(p):
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def join_corners(polylines: list, h: float, *, reach: float = 2.5, extend: bool = False) -> list:
    """Close the gaps the mesh leaves at corners: drop links shorter than a
    few voxels and move the ends that meet there (within `reach` voxels) onto
    the point nearest all their tangent lines (a least-squares intersection);
    with `extend` the ends stay and the lines are drawn on to that point."""
    if not polylines or h <= 0:
        return polylines
    lines = [p for p in polylines if _length(p) > 2.5 * h or np.allclose(p[0], p[-1])] if not extend \
        else [p for p in polylines if len(p) >= 2]
    open_ = [i for i, p in enumerate(lines) if len(p) >= 2 and not np.allclose(p[0], p[-1])]
    if len(open_) < 1:
        return lines
    ends, dirs, where = [], [], []
    for i in open_:  # one step per polyline
        p = lines[i]
        for k, (tip, back) in enumerate(((p[0], p[min(3, len(p) - 1)]), (p[-1], p[max(-4, -len(p))]))):
            d = tip - back
            ends.append(tip)
            dirs.append(d / max(np.linalg.norm(d), 1e-300))
            where.append((i, k))
    ends, dirs = np.array(ends), np.array(dirs)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(ends).query_pairs(reach * h, output_type="ndarray")
    if len(pairs) == 0:
        return lines
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(ends), len(ends)))
    _, comp = connected_components(graph, directed=False)
    proj = np.eye(3)[None] - dirs[:, :, None] * dirs[:, None, :]
    a = np.zeros((comp.max() + 1, 3, 3))
    b = np.zeros((comp.max() + 1, 3))
    np.add.at(a, comp, proj)
    np.add.at(b, comp, np.einsum("ijk,ik->ij", proj, ends))
    count = np.bincount(comp)
    mean = np.zeros((len(count), 3))
    np.add.at(mean, comp, ends)
    mean /= count[:, None]
    w, v = np.linalg.eigh(a)
    rhs = b - np.einsum("ijk,ik->ij", a, mean)
    keep = w > 0.2 * np.maximum(w[:, -1:], 1e-300)
    inv_w = np.where(keep, 1.0 / np.where(keep, w, 1.0), 0.0)
    corner = mean + np.einsum("ijk,ik->ij", v, inv_w * np.einsum("ikj,ik->ij", v, rhs))
    lines = [p.copy() for p in lines]
    for j, (i, k) in enumerate(where):  # one step per polyline end
        c = corner[comp[j]]
        if count[comp[j]] < 2 or np.linalg.norm(c - ends[j]) > (reach + 0.5) * h:
            continue
        if not extend:
            lines[i][0 if k == 0 else -1] = c
        elif np.linalg.norm(c - ends[j]) > 1e-9 * h:
            lines[i] = np.vstack([c, lines[i]]) if k == 0 else np.vstack([lines[i], c])
    return lines


def silhouettes(edges: SurfaceEdges, direction) -> list[np.ndarray]:
    """Contour lines of the curved faces seen along `direction` (world polylines).

    Marching triangles on ``s = normal . direction`` at the triangle corners:
    each curved triangle whose corners change sign holds one segment.
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    rows = np.flatnonzero(edges.curved)
    if rows.size == 0:
        return []
    s = edges.corner_normals[rows] @ d
    s = np.where(s == 0.0, 1e-12, s)
    pos = s > 0
    mixed = pos.any(axis=1) & ~pos.all(axis=1)
    rows, s = rows[mixed], s[mixed]
    if rows.size == 0:
        return []
    tri = edges.triangles[rows]
    # The corner alone on its side of zero, and the two others.
    odd = np.where((s > 0).sum(axis=1) == 1, np.argmax(s > 0, axis=1), np.argmax(s < 0, axis=1))
    a = tri[np.arange(len(tri)), odd]
    b = tri[np.arange(len(tri)), (odd + 1) % 3]
    c = tri[np.arange(len(tri)), (odd + 2) % 3]
    sa = s[np.arange(len(s)), odd]
    sb = s[np.arange(len(s)), (odd + 1) % 3]
    sc = s[np.arange(len(s)), (odd + 2) % 3]
    p = edges.points
    t1 = (sa / (sa - sb))[:, None]
    t2 = (sa / (sa - sc))[:, None]
    q1 = p[a] + t1 * (p[b] - p[a])
    q2 = p[a] + t2 * (p[c] - p[a])
    # Crossings on a shared mesh edge coincide: merge them so the segments chain.
    keys = np.concatenate([np.sort(np.column_stack([a, b]), axis=1), np.sort(np.column_stack([a, c]), axis=1)])
    pts = np.concatenate([q1, q2])
    uniq, first, inv = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inv = inv.ravel()
    segs = np.column_stack([inv[: len(rows)], inv[len(rows):]])
    segs = segs[segs[:, 0] != segs[:, 1]]
    return strip_segments(pts[first], segs)
