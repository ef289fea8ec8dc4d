"""The corners of the feature mesh, carried onto the FEA surface as nodes.

`surface_for_fea` remeshes by clustering, which knows nothing of the part's
corners; its own snapping finds a corner only where a mesh edge already
spans three faces, which a coarse surface misses.  The feature mesh
(`spatial.mesh(..., features=True)`) lists every corner with its three CSG
faces (`spatial.feature_edges`): each is solved exactly on those faces and
the nearest node of the remeshed surface is moved onto it.

Two checks keep the remeshed surface true to the feature mesh it starts
from: an edge flipped to run along a feature must follow it
(`chords_follow_features`: a chord between two nodes of one feature curve may
cut across the curve's bends, a tooth flank's polygon for one, and pierce
the surface next to it), and the surface must enclose the feature mesh's
volume (`volume_drift`: a size too coarse for a thin part lets the
clustering cut its edges off, without any self-intersection to tell).
"""

from __future__ import annotations

import numpy as np

from .facets import FacetField, solve_on_facets

__all__ = ["exact_corners", "snap_exact_corners", "chords_follow_features", "volume_drift", "check_volume_kept",
           "CHORD_GAP", "VOLUME_DRIFT"]

#: Largest distance, as a fraction of its length, from a chord's midpoint to each of the two faces
#: whose feature curve it is to follow (a circular rim of radius R gives L / (8 R): R >= 1.25 L passes).
CHORD_GAP = 0.1
#: Largest relative difference between the volume the remeshed surface encloses and the feature
#: mesh's (itself within about 1e-4 of the part at a quarter of the size): half of `tet_mesh`'s
#: default volume tolerance, the other half left to the tetrahedra and the volume estimate.
VOLUME_DRIFT = 2.5e-3


def exact_corners(ff: FacetField, mesh) -> np.ndarray:
    """Corners of a feature mesh, put exactly on their three faces of `ff`'s solid, ``(c, 3)``.

    `mesh` is a mesh of the same solid made with ``features=True`` (its
    ``feature_facets`` number the faces as `ff` does).  Corners whose faces
    have no common point nearby are left out.

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing import mesh
    >>> c = exact_corners(FacetField(box(1.0)), mesh(box(1.0), resolution=8, features=True))
    >>> c.shape, float(abs(c).max())
    ((8, 3), 0.5)
    """
    from ..meshing import feature_edges

    if "feature_rank" not in mesh.point_data or "facet_names" not in mesh.field_data:
        return np.zeros((0, 3))
    # the mesh's faces are numbered as the tree numbers them, as are ff's (which may rename them)
    if len(mesh.field_data["facet_names"]) != len(ff.names):
        return np.zeros((0, 3))
    curves = feature_edges(mesh)
    sets = np.asarray(mesh.point_data["feature_facets"], dtype=np.int64)[curves.corner_vertices]
    rows = np.flatnonzero((sets >= 0).all(axis=1))
    if rows.shape[0] == 0:
        return np.zeros((0, 3))
    sets = sets[rows]
    start = np.asarray(curves.corners, dtype=np.float64)[rows]
    c = solve_on_facets(ff, start, sets, iters=12)
    _, _, fv = ff(c)
    scale = max(float(np.abs(start).max()), 1.0)
    ok = np.isfinite(c).all(axis=1)
    ok &= np.all(np.abs(fv[sets, np.arange(len(rows))[:, None]]) < 1e-9 * scale, axis=1)
    ok &= np.abs(ff.solid(c)) < 1e-9 * scale
    ok &= np.linalg.norm(c - start, axis=1) < 0.1 * scale
    return c[ok]


def snap_exact_corners(points, faces, corners, size, tol, apply_snaps, relax=None, fixed=None, min_angle=6.0):
    """Move the node nearest each corner onto it (where no node is on it yet).

    A node claimed by two corners goes to the nearer; `apply_snaps(points,
    faces, moving, new)` makes the moves and undoes those that fold or
    sharpen a triangle.  The corners whose move was undone are tried once
    more with `relax(points, faces, held)` smoothing the nodes around them
    (corner nodes and `fixed` held); that try is kept when no triangle
    turns over and none has an angle under `min_angle` degrees that was not
    there before.  Returns the new points, the number of nodes moved onto a
    corner and the indices of the nodes on a corner.
    """
    from scipy.spatial import cKDTree

    if corners.shape[0] == 0:
        return points, 0, np.zeros(0, np.int64)

    def claims(pts):
        dist, vert = cKDTree(pts).query(corners)
        far = (dist > tol) & (dist < size)
        order = np.lexsort((dist[far], vert[far]))
        v, c = vert[far][order], corners[far][order]
        first = np.ones(v.shape[0], bool)
        first[1:] = v[1:] != v[:-1]
        return v[first], c[first], vert[dist <= tol]

    _, _, before = claims(points)
    v, c, _ = claims(points)
    if v.shape[0]:
        points, _ = apply_snaps(points, faces, v, c)
    v, c, on = claims(points)
    if v.shape[0] and relax is not None:
        trial = points.copy()
        trial[v] = c
        hold = np.zeros(points.shape[0], bool) if fixed is None else fixed.copy()
        hold[np.r_[on, v]] = True
        trial = relax(trial, faces, hold)
        trial[v] = c
        a0, n0 = _angles_normals(points, faces)
        a1, n1 = _angles_normals(trial, faces)
        turned = np.einsum("ij,ij->i", n0, n1) <= 0
        sharp = (a1 < min_angle) & (a0 >= min_angle)
        if not (turned | sharp).any():
            points = trial
    _, _, on = claims(points)
    return points, int(np.setdiff1d(on, before).shape[0]), on


def _angles_normals(p, faces):
    """Smallest interior angle (degrees) and unit normal of each triangle."""
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]

    def ang(u, w):
        cos = np.einsum("ij,ij->i", u, w) / np.maximum(np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1), 1e-300)
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))

    smallest = np.minimum(np.minimum(ang(b - a, c - a), ang(a - b, c - b)), ang(a - c, b - c))
    return smallest, n


def chords_follow_features(ff: FacetField, points, c, d, near, max_gap=CHORD_GAP):
    """Whether each chord ``c[i] -> d[i]`` follows the feature curve its two ends lie on, ``(k,) bool``.

    `near` ``(facets, n) bool`` tells which faces each point lies on; a chord
    follows the curve of its ends' common faces when its midpoint lies within
    ``max_gap * length`` of each of them.  Chords with fewer than two common
    faces do not follow any.

    Examples
    --------
    >>> from implicit import box
    >>> ff = FacetField(box(2.0))
    >>> p = np.array([[1.0, 1.0, -0.5], [1.0, 1.0, 0.5], [1.0, 0.0, 1.0]])
    >>> near = np.abs(ff(p)[2]) < 1e-9
    >>> chords_follow_features(ff, p, np.array([0, 0]), np.array([1, 2]), near).tolist()
    [True, False]
    """
    c, d = np.asarray(c, dtype=np.int64), np.asarray(d, dtype=np.int64)
    if c.shape[0] == 0:
        return np.zeros(0, bool)
    common = near[:, c] & near[:, d]                                   # (facets, k)
    mid = 0.5 * (points[c] + points[d])
    _, _, fm = ff(mid)
    g = np.linalg.norm(ff.facet_gradients(mid), axis=2)                # (facets, k)
    gap = np.abs(fm) / np.maximum(g, 1e-300)
    length = np.linalg.norm(points[c] - points[d], axis=1)
    off = (common & (gap > max_gap * length)).any(axis=0)
    return (common.sum(axis=0) >= 2) & ~off


def volume_drift(start, points, faces) -> float:
    """Relative difference between the volume a closed surface encloses and the `start` mesh's.

    Examples
    --------
    >>> import pyvista as pv
    >>> cube = pv.Box().triangulate()
    >>> f = np.asarray(cube.faces).reshape(-1, 4)[:, 1:]
    >>> round(volume_drift(cube, np.asarray(cube.points) * 1.01, f), 4)
    0.0303
    """
    a, b, c = (np.asarray(points, dtype=np.float64)[np.asarray(faces)[:, i]] for i in range(3))
    vol = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    ref = float(start.volume)
    return abs(vol - ref) / max(abs(ref), 1e-300)


def check_volume_kept(start, points, faces, size, limit=VOLUME_DRIFT) -> float:
    """`volume_drift` of a remeshed surface from its start mesh; a `ValueError` above `limit`.

    The message says "edges cut off" (what a too coarse `size` does), which
    `tet_mesh` reads as a cue to try a finer size.
    """
    drift = volume_drift(start, points, faces)
    if drift > limit:
        raise ValueError(f"size: the remeshed surface's volume differs by {100 * drift:.2g} percent from the "
                         f"part's mesh at size {size:g} (edges cut off); use a smaller size")
    return drift
