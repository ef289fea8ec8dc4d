"""Points inside the cavities of a closed surface, for TetGen's hole list.

TetGen removes the tetrahedra outside a closed surface by flooding from its convex hull; a
void enclosed by an inner shell (a hollow ball, a box with a bubble) is never reached from
there and comes back filled.  Each inner shell (one whose enclosed signed volume is negative
on an outward-oriented surface) gives one point just off its largest triangle, on the side
its normal points to: inside the void.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cavity_points"]

# Step off the triangle, as a fraction of its size: far below any other surface's distance.
STEP = 1e-3


def cavity_points(points, faces):
    """One point inside each void enclosed by an inner shell of an outward-oriented surface.

    Parameters
    ----------
    points : (n, 3) array_like of float
    faces : (m, 3) array_like of int
        A closed, outward-oriented triangle surface, possibly of several shells.

    Returns
    -------
    (k, 3) ndarray of float
        A point in each inner shell's void (k = 0 for a surface without cavities).

    Examples
    --------
    >>> import pyvista as pv
    >>> outer = pv.Sphere(radius=2.0).triangulate().clean()
    >>> inner = pv.Sphere(radius=1.0).triangulate().clean()
    >>> inner = inner.flip_faces() if hasattr(inner, "flip_faces") else inner.flip_normals()
    >>> shell = outer.merge(inner)
    >>> p = cavity_points(shell.points, shell.faces.reshape(-1, 4)[:, 1:])
    >>> p.shape, bool(np.linalg.norm(p[0]) < 1.0)
    ((1, 3), True)
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return np.zeros((0, 3))
    n = len(points)
    # Shells: vertices joined by the triangles' sides.
    rows = faces.ravel()
    cols = np.roll(faces, -1, axis=1).ravel()
    graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    n_shells, label = connected_components(graph, directed=False)
    if n_shells == 1:
        return np.zeros((0, 3))
    shell = label[faces[:, 0]]
    origin = points[faces].reshape(-1, 3).mean(axis=0)
    a, b, c = (points[faces[:, k]] - origin for k in range(3))
    volume = np.bincount(shell, weights=np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0, minlength=n_shells)
    normal = np.cross(b - a, c - a)
    area2 = np.linalg.norm(normal, axis=1)
    holes = []
    for s in np.flatnonzero(volume < 0):
        members = np.flatnonzero(shell == s)
        t = members[np.argmax(area2[members])]
        centre = (a[t] + b[t] + c[t]) / 3.0 + origin
        holes.append(centre + STEP * np.sqrt(0.5 * area2[t]) * normal[t] / area2[t])
    return np.array(holes, dtype=np.float64).reshape(-1, 3)
