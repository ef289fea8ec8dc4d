"""The sharp edges and corners of a feature mesh as data: labelled polylines and points."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["FeatureCurves", "feature_edges"]


@dataclass
class FeatureCurves:
    """Sharp edges and corners of a mesh made with ``features=True``.

    Attributes
    ----------
    polylines : list of (k, 3) float ndarray
        Chains of mesh vertices along each sharp edge (closed loops repeat
        their first point at the end).
    vertices : list of (k,) int ndarray
        The mesh vertex indices of each polyline.
    labels : list of (str, str)
        The two CSG faces each polyline separates, e.g.
        ``("box_0.+x", "cylinder_1.wall")``.
    corners : (c, 3) float ndarray
        Points where three faces meet.
    corner_vertices : (c,) int ndarray
    corner_labels : list of (str, str, str)
    """

    polylines: list = field(default_factory=list)
    vertices: list = field(default_factory=list)
    labels: list = field(default_factory=list)
    corners: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    corner_vertices: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    corner_labels: list = field(default_factory=list)


def feature_edges(mesh) -> FeatureCurves:
    """Sharp edges (polylines) and corners (points) of a mesh, labelled by CSG faces.

    Reads the point data ``feature_rank`` / ``feature_facets`` and the field
    data ``facet_names`` that ``mesh(..., features=True)`` writes.  An edge
    of the mesh between two feature vertices sharing two faces belongs to
    the curve of those two faces; the curves are split at corners.

    Parameters
    ----------
    mesh : pyvista.PolyData

    Returns
    -------
    FeatureCurves

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing import mesh
    >>> curves = feature_edges(mesh(box(1.0), resolution=8, features=True))
    >>> len(curves.polylines), curves.corners.shape
    (12, (8, 3))
    >>> curves.labels[0]
    ('box_0.+x', 'box_0.+y')
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components, depth_first_order

    for name in ("feature_rank", "feature_facets"):
        if name not in mesh.point_data:
            raise ValueError(f"mesh: expected point data {name!r} (mesh with features=True)")
    names = [str(s) for s in np.asarray(mesh.field_data["facet_names"]).reshape(-1)]
    rank = np.asarray(mesh.point_data["feature_rank"])
    facets = np.asarray(mesh.point_data["feature_facets"]).reshape(-1, 3).astype(np.int64)
    pts = np.asarray(mesh.points, dtype=np.float64)
    out = FeatureCurves()
    corner = np.flatnonzero(rank == 3)
    out.corners = pts[corner]
    out.corner_vertices = corner
    out.corner_labels = [tuple(names[j] for j in sorted(facets[v]) if j >= 0) for v in corner]

    f = mesh.faces.reshape(-1, 4)[:, 1:].astype(np.int64)
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    e = np.unique(e[(rank[e[:, 0]] > 0) & (rank[e[:, 1]] > 0)], axis=0)
    if e.shape[0] == 0:
        return out
    # the two faces both ends share
    fa, fb = facets[e[:, 0]], facets[e[:, 1]]
    common = (fa[:, :, None] == fb[:, None, :]) & (fa[:, :, None] >= 0)
    shared = common.any(axis=2)
    keep = shared.sum(axis=1) == 2
    e, fa, shared = e[keep], fa[keep], shared[keep]
    if e.shape[0] == 0:
        return out
    pair = np.sort(fa[shared].reshape(-1, 2), axis=1)
    groups, inverse = np.unique(pair, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    for g, (i, j) in enumerate(groups):
        ge = e[inverse == g]
        verts, local = np.unique(ge, return_inverse=True)
        local = local.reshape(-1, 2)
        m = verts.shape[0]
        adj = coo_matrix((np.ones(local.shape[0]), (local[:, 0], local[:, 1])), shape=(m, m))
        adj = (adj + adj.T).tocsr()
        degree = np.diff(adj.indptr)
        n_comp, comp = connected_components(adj, directed=False)
        for k in range(n_comp):
            members = np.flatnonzero(comp == k)
            ends = members[degree[members] == 1]
            start = int(ends.min()) if ends.shape[0] else int(members.min())
            order = depth_first_order(adj, start, directed=False, return_predecessors=False)
            chain = verts[order]
            if ends.shape[0] == 0 and chain.shape[0] > 2:
                chain = np.r_[chain, chain[0]]
            out.polylines.append(pts[chain])
            out.vertices.append(chain)
            out.labels.append((names[i], names[j]))
    return out
