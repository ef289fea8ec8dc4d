"""Compiled passes of the sharp-feature rebuild (`spatial.meshing.features`): one loop over all
triangles or vertices each, so the pass adds little to the mesher's own time."""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def _at_node(pts, origin, h, node_tol):
    """Vertices within `node_tol` voxels of a lattice node in every coordinate, and the axis of each
    one's lattice edge (the coordinate farthest from the node; -1 when it sits on the node exactly)."""
    n = pts.shape[0]
    at = np.empty(n, np.bool_)
    axis = np.full(n, -1, np.int64)
    for v in range(n):
        far = 0.0
        for j in range(3):
            u = (pts[v, j] - origin[j]) / h
            d = abs(u - np.floor(u + 0.5))
            if d > far:
                far = d
                axis[v] = j
        at[v] = far < node_tol
    return at, axis


@numba.njit(cache=True, nogil=True)
def _candidate_cells(pts, faces, origin, h, cos_limit, at_node):
    """Lattice cell of every triangle and whether it departs from a vertex normal (one pass each)."""
    m = faces.shape[0]
    n = pts.shape[0]
    vn = np.zeros((n, 3))
    tn = np.empty((m, 3))
    for t in range(m):
        a, b, c = faces[t, 0], faces[t, 1], faces[t, 2]
        ux = pts[b, 0] - pts[a, 0]; uy = pts[b, 1] - pts[a, 1]; uz = pts[b, 2] - pts[a, 2]
        vx = pts[c, 0] - pts[a, 0]; vy = pts[c, 1] - pts[a, 1]; vz = pts[c, 2] - pts[a, 2]
        cx = uy * vz - uz * vy; cy = uz * vx - ux * vz; cz = ux * vy - uy * vx
        tn[t, 0] = cx; tn[t, 1] = cy; tn[t, 2] = cz
        for k in range(3):
            v = faces[t, k]
            vn[v, 0] += cx; vn[v, 1] += cy; vn[v, 2] += cz
    for v in range(n):
        s = np.sqrt(vn[v, 0] ** 2 + vn[v, 1] ** 2 + vn[v, 2] ** 2)
        if s > 0:
            vn[v, 0] /= s; vn[v, 1] /= s; vn[v, 2] /= s
    marked = np.zeros(m, np.bool_)
    ijk = np.empty((m, 3), np.int64)
    lo = np.full(3, np.iinfo(np.int64).max, np.int64)
    third = 1.0 / 3.0
    for t in range(m):
        s = np.sqrt(tn[t, 0] ** 2 + tn[t, 1] ** 2 + tn[t, 2] ** 2)
        if s > 0:
            worst = 1.0
            for k in range(3):
                v = faces[t, k]
                d = (tn[t, 0] * vn[v, 0] + tn[t, 1] * vn[v, 1] + tn[t, 2] * vn[v, 2]) / s
                if d < worst:
                    worst = d
            n_node = at_node[faces[t, 0]] + at_node[faces[t, 1]] + at_node[faces[t, 2]]
            # a triangle joining a node vertex to an ordinary one is the border of such a face: the
            # crossings on lattice edges lying in the face's plane are undefined there, and the chamfer
            # they leave may bend less than the normals' test sees
            marked[t] = worst < cos_limit or (n_node > 0 and n_node < 3)
        for j in range(3):
            q = (pts[faces[t, 0], j] + pts[faces[t, 1], j] + pts[faces[t, 2], j]) * third
            ijk[t, j] = np.int64(np.floor((q - origin[j]) / h))
            if ijk[t, j] < lo[j]:
                lo[j] = ijk[t, j]
    # one key per cell, ``(i * s + j) * s + k`` from the lowest cell
    s = np.int64(1)
    for t in range(m):
        for j in range(3):
            if ijk[t, j] - lo[j] + 1 > s:
                s = ijk[t, j] - lo[j] + 1
    key = np.empty(m, np.int64)
    for t in range(m):
        key[t] = ((ijk[t, 0] - lo[0]) * s + ijk[t, 1] - lo[1]) * s + ijk[t, 2] - lo[2]
    return marked, key, lo, s, vn


@numba.njit(cache=True, nogil=True)
def _cell_index(key, cells):
    """Index of each key in the sorted `cells`, -1 where it is not there (binary search)."""
    out = np.full(key.shape[0], -1, np.int64)
    n = cells.shape[0]
    for t in range(key.shape[0]):
        k = key[t]
        a, b = 0, n
        while a < b:
            c = (a + b) >> 1
            if cells[c] < k:
                a = c + 1
            else:
                b = c
        if a < n and cells[a] == k:
            out[t] = a
    return out


@numba.njit(cache=True, nogil=True)
def _border_nodes(faces, at_node, axis):
    """Vertices at a node (on a lattice edge) in a triangle that also has an ordinary vertex."""
    out = np.zeros(at_node.shape[0], np.bool_)
    for t in range(faces.shape[0]):
        k = at_node[faces[t, 0]] + at_node[faces[t, 1]] + at_node[faces[t, 2]]
        if 0 < k < 3:
            for j in range(3):
                v = faces[t, j]
                if at_node[v] and axis[v] >= 0:
                    out[v] = True
    return out


@numba.njit(cache=True, nogil=True)
def _assemble(f, drop, new_faces, n_points):
    """The triangles not dropped followed by the new ones, and which of the points they use."""
    kept = 0
    for t in range(f.shape[0]):
        kept += not drop[t]
    out = np.empty((kept + new_faces.shape[0], 3), np.int64)
    used = np.zeros(n_points, np.bool_)
    r = 0
    for t in range(f.shape[0]):
        if not drop[t]:
            for j in range(3):
                out[r, j] = f[t, j]
                used[f[t, j]] = True
            r += 1
    for t in range(new_faces.shape[0]):
        for j in range(3):
            out[r, j] = new_faces[t, j]
            used[new_faces[t, j]] = True
        r += 1
    return out, used


@numba.njit(cache=True, nogil=True)
def _facing_kernel(points, faces, exact, n, min_facing):
    m = faces.shape[0]
    bad = np.zeros(m, np.bool_)
    for t in range(m):
        a, b, c = faces[t, 0], faces[t, 1], faces[t, 2]
        ux = points[b, 0] - points[a, 0]; uy = points[b, 1] - points[a, 1]; uz = points[b, 2] - points[a, 2]
        vx = points[c, 0] - points[a, 0]; vy = points[c, 1] - points[a, 1]; vz = points[c, 2] - points[a, 2]
        cx = uy * vz - uz * vy; cy = uz * vx - ux * vz; cz = ux * vy - uy * vx
        area2 = np.sqrt(cx * cx + cy * cy + cz * cz)
        wx = points[a, 0] - points[c, 0]; wy = points[a, 1] - points[c, 1]; wz = points[a, 2] - points[c, 2]
        zx = points[c, 0] - points[b, 0]; zy = points[c, 1] - points[b, 1]; zz = points[c, 2] - points[b, 2]
        scale = max(ux * ux + uy * uy + uz * uz, zx * zx + zy * zy + zz * zz, wx * wx + wy * wy + wz * wz)
        if area2 <= 1e-6 * scale:
            bad[t] = True
            continue
        best = -np.inf
        for k in range(3):
            v = faces[t, k]
            if v < n:
                cos = (cx * exact[v, 0] + cy * exact[v, 1] + cz * exact[v, 2]) / area2
                if cos < -min_facing:
                    bad[t] = True
                if cos > best:
                    best = cos
        if best < min_facing:
            bad[t] = True
    return bad

