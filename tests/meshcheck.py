"""Exact properties of boundary meshes, shared by the mesh tests."""

import numpy as np


def faces_of(mesh):
    return mesh.faces.reshape(-1, 4)[:, 1:]


def topology(mesh):
    """Edge use counts, Euler characteristic and manifold-vertex check of a triangle mesh."""
    f = faces_of(mesh)
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    edges, counts = np.unique(undirected, axis=0, return_counts=True)
    # consistent orientation: every directed edge appears once and its reverse once
    d_unique = np.unique(directed, axis=0)
    euler = mesh.n_points - edges.shape[0] + f.shape[0]
    return {
        "edge_counts": set(np.unique(counts).tolist()),
        "oriented": d_unique.shape[0] == directed.shape[0],
        "euler": int(euler),
        "degenerate": int(np.sum((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2]))),
        "duplicates": f.shape[0] - np.unique(np.sort(f, axis=1), axis=0).shape[0],
    }


def vertex_manifold(mesh):
    """True when the triangles around every vertex form ONE fan (no pinched vertex).

    The link of a vertex (the edges opposite to it) must be one connected cycle.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    f = faces_of(mesh)
    v = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    a = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    b = np.concatenate([f[:, 2], f[:, 0], f[:, 1]])
    n = np.int64(mesh.n_points)
    ka = v.astype(np.int64) * n + a
    kb = v.astype(np.int64) * n + b
    keys, inv = np.unique(np.concatenate([ka, kb]), return_inverse=True)
    m = keys.shape[0]
    g = coo_matrix((np.ones(v.shape[0]), (inv[: v.shape[0]], inv[v.shape[0]:])), shape=(m, m))
    _, labels = connected_components(g, directed=False)
    owner = keys // n
    per_vertex = np.unique(np.stack([owner, labels], 1), axis=0)[:, 0]
    return bool(np.all(np.bincount(per_vertex) <= 1))


def signed_volume(mesh):
    p = np.asarray(mesh.points, dtype=np.float64)
    f = faces_of(mesh)
    c = p.mean(axis=0)
    a, b, d = p[f[:, 0]] - c, p[f[:, 1]] - c, p[f[:, 2]] - c
    return float(np.einsum("ij,ij->i", a, np.cross(b, d)).sum() / 6.0)


def min_area(mesh):
    p = np.asarray(mesh.points, dtype=np.float64)
    f = faces_of(mesh)
    return float(np.linalg.norm(np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]]), axis=1).min() / 2)
