"""The corners of the feature mesh, carried onto the FEA surface as nodes.

`surface_for_fea` remeshes by clustering, which knows nothing of the part's
corners; its own snapping finds a corner only where a mesh edge already
spans three faces, which a coarse surface misses.  The feature mesh
(`spatial.mesh(..., features=True)`) lists every corner with its three CSG
faces (`spatial.feature_edges`): each is solved exactly on those faces and
the nearest node of the remeshed surface is moved onto it.

The corners are read from the mesh the clustering starts from
(`spatial.fea.surface_start`: the feature mesh itself, or beside the plain
mesh of the grown solid where that is the start).
"""

from __future__ import annotations

import numpy as np

from .facets import FacetField, solve_on_facets

__all__ = ["exact_corners", "snap_exact_corners"]


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
    if "feature_rank" not in mesh.point_data or "facet_names" not in mesh.field_data:
        return np.zeros((0, 3))
    # the mesh's faces are numbered as the tree numbers them, as are ff's (which may rename them)
    if len(mesh.field_data["facet_names"]) != len(ff.names):
        return np.zeros((0, 3))
    # The corners of `spatial.feature_edges`, read straight from the point data: its polylines are not needed.
    corner = np.flatnonzero(np.asarray(mesh.point_data["feature_rank"]) == 3)
    sets = np.asarray(mesh.point_data["feature_facets"], dtype=np.int64).reshape(-1, 3)[corner]
    rows = np.flatnonzero((sets >= 0).all(axis=1))
    if rows.shape[0] == 0:
        return np.zeros((0, 3))
    sets = sets[rows]
    start = np.asarray(mesh.points, dtype=np.float64)[corner[rows]]
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

