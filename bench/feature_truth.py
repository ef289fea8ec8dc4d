"""Points on the exact sharp edges and corners of a CSG solid, and their distances to a mesh.

Seeds (vertices of a fine plain mesh) near two CSG faces are moved by
Gauss-Newton onto the common curve of those faces; a point is kept when it
lies on the solid's boundary and the boundary really bends there: on a small
circle around the curve, in the plane across it, the two sign changes of the
field are not opposite (a face continued flat by another face is no edge).
Corners are the points of three faces with real edges of two of their pairs
nearby.  Distances to a mesh are exact point-to-triangle distances (VTK's
cell locator through pyvista's ``find_closest_cell``).
"""

from __future__ import annotations

import numpy as np

from implicit.facets import FacetField

#: Radius of the test circle, in voxels of the seed mesh.
CIRCLE = 0.05
#: Sign changes closer than this to opposite (degrees) are a smooth surface.
BEND_DEG = 8.0


def _solve(ff, p, sets, iters=8, step=1e-7):
    p = p.copy()
    r = np.arange(p.shape[0])
    k = sets.shape[1]
    for _ in range(iters):
        _, _, f = ff(p)
        g = ff.facet_gradients(p, step=step)
        val = np.stack([f[sets[:, j], r] for j in range(k)], axis=1)
        jac = np.stack([g[sets[:, j], r] for j in range(k)], axis=1)
        jj = jac @ np.swapaxes(jac, 1, 2) + 1e-14 * np.eye(k)
        y = np.linalg.solve(jj, val[:, :, None])[:, :, 0]
        p -= np.einsum("nji,nj->ni", jac, y)
    _, _, f = ff(p)
    g = ff.facet_gradients(p, step=step)
    return p, np.stack([f[sets[:, j], r] for j in range(k)], axis=1), np.stack([g[sets[:, j], r] for j in range(k)], 1)


def exact_features(solid, resolution=128, seeds=None):
    """Points on the sharp edges and the corners of `solid`.

    Returns
    -------
    edges : (m, 3) float
    pairs : (m, 2) int, the facets of each edge point
    corners : (c, 3) float
    names : list of str
    h : float, the seed mesh's voxel size
    """
    from spatial.meshing import mesh

    ff = FacetField(solid)
    seed_mesh = mesh(solid, resolution=resolution, features=False)
    h = float(seed_mesh.field_data["voxel_size"][0])
    p = np.asarray(seed_mesh.points if seeds is None else seeds, dtype=np.float64)
    names = ff.names
    leaf = np.unique([nm.split(".")[0] for nm in names], return_inverse=True)[1]
    _, _, fv = ff(p)
    leafmax = np.full((leaf.max() + 1, p.shape[0]), -np.inf)
    np.maximum.at(leafmax, leaf, fv)
    relevant = fv >= leafmax[leaf] - 1.5 * h
    score = np.where(relevant, np.abs(fv), np.inf)
    order = np.argsort(score, axis=0)
    best = np.take_along_axis(score, order, axis=0)
    tol = 1e-7 * max(1.0, float(np.abs(p).max()))

    def on_boundary(q, val):
        return (np.abs(solid(q)) < tol) & np.all(np.abs(val) < tol, axis=1)

    near2 = best[1] < 1.5 * h
    sets = np.sort(order[:2, near2].T, axis=1)
    q, val, grad = _solve(ff, p[near2], sets)
    ok = on_boundary(q, val) & (np.linalg.norm(q - p[near2], axis=1) < 3 * h)
    n1, n2 = grad[:, 0], grad[:, 1]
    t = np.cross(n1, n2)
    tn = np.linalg.norm(t, axis=1)
    ok &= tn > 0.2 * np.linalg.norm(n1, axis=1) * np.linalg.norm(n2, axis=1)
    q, sets, t, n1 = q[ok], sets[ok], t[ok] / tn[ok, None], n1[ok]
    u = n1 / np.linalg.norm(n1, axis=1)[:, None]
    v = np.cross(t, u)
    ang = np.radians(np.arange(0, 360, 2.0))
    ring = q[:, None, :] + CIRCLE * h * (np.cos(ang)[None, :, None] * u[:, None, :] + np.sin(ang)[None, :, None] * v[:, None, :])
    s = solid(ring.reshape(-1, 3)).reshape(q.shape[0], -1) < 0
    change = s != np.roll(s, -1, axis=1)
    two = change.sum(axis=1) == 2
    idx = np.argsort(~change, axis=1, kind="stable")[:, :2]
    gap = np.degrees(np.abs(ang[idx[:, 1]] - ang[idx[:, 0]]))
    bent = two & (np.abs(gap - 180.0) > BEND_DEG)
    edges, pairs = q[bent], sets[bent]

    near3 = best[2] < 1.5 * h
    sets3 = np.sort(order[:3, near3].T, axis=1)
    c, val3, _ = _solve(ff, p[near3], sets3)
    okc = on_boundary(c, val3) & (np.linalg.norm(c - p[near3], axis=1) < 3 * h)
    c, sets3 = c[okc], sets3[okc]
    corners = np.zeros((0, 3))
    if c.shape[0] and edges.shape[0]:
        from scipy.spatial import cKDTree

        tree = cKDTree(edges)
        hits = np.zeros(c.shape[0], int)
        for a, b in ((0, 1), (0, 2), (1, 2)):
            lists = tree.query_ball_point(c, 2 * h)
            want = sets3[:, [a, b]]
            hits += np.array([np.any(np.all(pairs[li] == w, axis=1)) if li else False
                              for li, w in zip(lists, want)])
        c = c[hits >= 2]
        if c.shape[0]:
            corners = np.unique(np.round(c / (1e-6 * h)) * (1e-6 * h), axis=0)
            # merge the copies found from different seeds
            keep = np.ones(corners.shape[0], bool)
            tc = cKDTree(corners)
            for i, j in sorted(tc.query_pairs(0.01 * h)):
                if keep[i]:
                    keep[j] = False
            corners = corners[keep]
    return edges, pairs, corners, names, h


def distances(mesh, points):
    """Exact distance from each point to the mesh's triangles."""
    if points.shape[0] == 0:
        return np.zeros(0)
    _, closest = mesh.find_closest_cell(points, return_closest_point=True)
    return np.linalg.norm(closest - points, axis=1)
