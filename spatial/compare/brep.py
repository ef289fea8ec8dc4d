"""Boundary representation from a closed mesh: faces by CSG leaf, edges, loops, the Euler-Poincare law.

Every triangle of a closed boundary mesh is given to the CSG leaf whose
surface it lies on (the leaf with the smallest ``|f|`` at its centroid, the
leaves taken in world coordinates); triangles of one leaf whose leaf
normals differ by more than `CREASE_DEGREES` are kept apart (the six sides
of a box), and components of fewer than `MIN_FACE_TRIANGLES` triangles (the
chamfer marching cubes leaves along a sharp edge) join a neighbour.  Then:

* faces ``F``: connected regions of one label;
* vertices ``V``: mesh vertices where three or more faces meet, one vertex
  on every closed edge that has none, and one on every face with no edge
  (the seed's "seminal" body: one face, one vertex);
* edges ``E``: chains of mesh edges between two faces, cut at vertices;
* loops ``L``: the inner loops (rings), a face's boundary loops minus one;
* bodies ``B`` (shells) and genus ``G`` from the mesh itself.

The Euler-Poincare law ``F - E + V - L = 2 (B - G)`` then checks the face
grouping against the mesh's own topology.

References
----------
M. Mantyla, An Introduction to Solid Modeling, Computer Science Press, 1988
(Euler operators and the Euler-Poincare formula with rings).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .leaves import world_leaves

__all__ = ["BRep", "brep", "CREASE_DEGREES", "MIN_FACE_TRIANGLES"]

#: Leaf normals further apart than this split a leaf's triangles into faces.
CREASE_DEGREES = 30.0
#: Leaves closer than this (relative to the part's size) at a triangle both carry it.
COINCIDENT = 1e-7
#: A face is flat when this share of its triangles has one normal (to 1e-9).
FLAT_SHARE = 0.8
#: Alternating projections of wireframe vertices onto the two surfaces of their edge.
EDGE_PROJECTIONS = 12
#: Components smaller than this merge into a neighbouring face.
MIN_FACE_TRIANGLES = 4


@dataclass(frozen=True)
class BRep:
    """Topology of a boundary representation and the faces of its mesh.

    Attributes
    ----------
    V, E, F, L, B, G : int
        Vertices, edges, faces, inner loops, bodies (shells), genus.
    face_of_triangle : (n_tri,) int
        Face id of every mesh triangle.
    face_leaf : list of str
        The CSG leaf each face lies on.
    edge_segments : (m, 2, 3) float
        The mesh edges between faces: the wireframe.
    nbytes : int
        Storage: mesh points and triangles, face ids, edge list.
    """

    V: int
    E: int
    F: int
    L: int
    B: int
    G: int
    face_of_triangle: np.ndarray = field(repr=False)
    face_leaf: list = field(repr=False)
    edge_segments: np.ndarray = field(repr=False)
    nbytes: int = 0

    @property
    def euler_poincare(self) -> tuple:
        """``(F - E + V - L, 2 (B - G))``."""
        return self.F - self.E + self.V - self.L, 2 * (self.B - self.G)

    @property
    def holds(self) -> bool:
        lhs, rhs = self.euler_poincare
        return lhs == rhs

    def to_dict(self) -> dict:
        lhs, rhs = self.euler_poincare
        return {"V": self.V, "E": self.E, "F": self.F, "L": self.L, "B": self.B, "G": self.G,
                "F-E+V-L": lhs, "2(B-G)": rhs, "euler_poincare_holds": self.holds, "bytes": self.nbytes}


def _components(n, a, b):
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    g = coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    return connected_components(g, directed=False)


def _triangles(mesh):
    faces = np.asarray(mesh.faces).reshape(-1, 4)
    if faces.size and np.any(faces[:, 0] != 3):
        raise ValueError("mesh: expected triangles only")
    return np.asarray(mesh.points, dtype=np.float64), faces[:, 1:].astype(np.int64)


def _edge_table(tri):
    """Unique edges (m, 2), and for each the two triangles holding it (m, 2)."""
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    owner = np.tile(np.arange(len(tri)), 3)
    e = np.sort(e, axis=1)
    order = np.lexsort((e[:, 1], e[:, 0]))
    e, owner = e[order], owner[order]
    if len(e) % 2 or np.any(np.any(e[0::2] != e[1::2], axis=1)):
        raise ValueError("mesh: expected a closed 2-manifold mesh (every edge in two triangles)")
    return e[0::2], np.column_stack([owner[0::2], owner[1::2]])


def _label_triangles(solid, pts, tri, edges, pairs):
    leaves = world_leaves(solid)
    cen = pts[tri].mean(axis=1)
    values = np.abs(np.stack([leaf(cen) for _, leaf in leaves]))
    leaf = np.argmin(values, axis=0)
    normal = np.zeros_like(cen)
    for i, (_, w) in enumerate(leaves):
        sel = leaf == i
        if sel.any():
            g = w.gradient(cen[sel])
            normal[sel] = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    t0, t1 = pairs[:, 0], pairs[:, 1]
    cos = np.einsum("ij,ij->i", normal[t0], normal[t1])
    # coplanar faces of two leaves (a union's shared bottom) make one face
    scale = float(np.max(np.ptp(pts, axis=0))) or 1.0
    offset = np.abs(np.einsum("ij,ij->i", normal[t0], cen[t1] - cen[t0]))
    shared = (offset < COINCIDENT * scale) & (cos > 1.0 - 1e-9)
    join = ((leaf[t0] == leaf[t1]) | shared) & (cos >= np.cos(np.radians(CREASE_DEGREES)))
    _, comp = _components(len(tri), t0[join], t1[join])
    for _ in range(8):  # tiny components take the label of a big neighbour
        sizes = np.bincount(comp)
        tiny = sizes[comp] < MIN_FACE_TRIANGLES
        if not tiny.any():
            break
        for a, b in ((t0, t1), (t1, t0)):
            take = tiny[a] & ~tiny[b]
            comp[a[take]] = comp[b[take]]
            leaf[a[take]] = leaf[b[take]]
        tiny = np.bincount(comp, minlength=comp.max() + 1)[comp] < MIN_FACE_TRIANGLES
    same = comp[t0] == comp[t1]
    n_faces, face = _components(len(tri), t0[same], t1[same])
    face_leaf = [""] * n_faces
    face_leaf_idx = np.zeros(n_faces, dtype=np.int64)
    face_leaf_idx[face] = leaf
    face_leaf = [leaves[i][0] for i in face_leaf_idx]
    carriers = _carriers(n_faces, face, normal, cen, face_leaf_idx, leaves)
    return n_faces, face, face_leaf, carriers


def _carriers(n_faces, face, normal, cen, face_leaf_idx, leaves):
    """Per face, its surface as ``f(points) -> (values, gradients)``: its plane when flat, else its leaf."""
    def mean_normal(weights):
        m = np.zeros((n_faces, 3))
        np.add.at(m, face, normal * weights[:, None])
        return m / np.maximum(np.linalg.norm(m, axis=1, keepdims=True), 1e-300)

    mean = mean_normal(np.ones(len(face)))
    # the chamfer triangles marching cubes leaves along sharp edges must not tilt a flat face
    mean = mean_normal((np.einsum("ij,ij->i", normal, mean[face]) > 0.999).astype(float))
    flat_tri = np.einsum("ij,ij->i", normal, mean[face]) > 1.0 - 1e-9
    share = np.bincount(face, weights=flat_tri, minlength=n_faces) / np.maximum(np.bincount(face, minlength=n_faces), 1)
    offset = np.zeros(n_faces)
    np.add.at(offset, face, np.where(flat_tri, np.einsum("ij,ij->i", cen, mean[face]), 0.0))
    offset /= np.maximum(np.bincount(face, weights=flat_tri, minlength=n_faces), 1)
    spread = np.where(share >= FLAT_SHARE, 0.0, 1.0)
    out = []
    for f in range(n_faces):
        if spread[f] < 1e-9:
            n, d = mean[f], offset[f]
            out.append(lambda p, n=n, d=d: (p @ n - d, np.broadcast_to(n, p.shape)))
        else:
            solid = leaves[face_leaf_idx[f]][1]
            out.append(lambda p, s=solid: (s(p), s.gradient(p)))
    return out


def _project_edges(pts, ce, f0, f1, carriers):
    """Edge segments (m, 2, 3) with their ends moved onto both faces' surfaces.

    Marching cubes leaves a staircase along a sharp edge; alternating Newton
    steps ``p -= f grad f / |grad f|^2`` onto the two faces' carriers (a
    plane, or the CSG leaf) bring each end onto their intersection curve.
    Ends that would move further than a few cells (corners of three faces)
    stay where they are.
    """
    seg = pts[ce].copy()
    if not len(ce):
        return seg
    span = float(np.max(np.ptp(pts, axis=0))) or 1.0
    limit = 0.05 * span
    for a, b in np.unique(np.column_stack([f0, f1]), axis=0):
        sel = (f0 == a) & (f1 == b)
        p = seg[sel].reshape(-1, 3)
        start = p.copy()
        for _ in range(EDGE_PROJECTIONS):
            for carrier in (carriers[a], carriers[b]):
                v, g = carrier(p)
                p = p - (v / np.maximum(np.einsum("ij,ij->i", g, g), 1e-300))[:, None] * g
        bad = ~np.isfinite(p).all(axis=1) | (np.linalg.norm(p - start, axis=1) > limit)
        p[bad] = start[bad]
        seg[sel] = p.reshape(-1, 2, 3)
    return seg


def brep(solid, mesh) -> BRep:
    """The boundary representation of `solid` from its closed mesh.

    Parameters
    ----------
    solid : implicit.Solid
        The CSG tree whose leaves name the faces.
    mesh : pyvista.PolyData
        A closed, manifold triangle mesh of `solid` (`spatial.mesh`).

    Examples
    --------
    >>> import spatial
    >>> from implicit import box, cylinder
    >>> part = box((2, 2, 1)) - cylinder(0.4, 2)
    >>> rep = brep(part, spatial.mesh(part, resolution=24))
    >>> rep.F, rep.G, rep.holds
    (7, 1, True)
    """
    pts, tri = _triangles(mesh)
    if len(tri) == 0:
        raise ValueError("mesh: the mesh has no triangles")
    edges, pairs = _edge_table(tri)
    F, face, face_leaf, carriers = _label_triangles(solid, pts, tri, edges, pairs)
    nv = len(pts)
    # shells and genus from the mesh itself
    n_shell, shell = _components(nv, edges[:, 0], edges[:, 1])
    used = np.zeros(nv, bool)
    used[tri.ravel()] = True
    shell_ids = np.unique(shell[used])
    chi = (np.bincount(shell[used[np.arange(nv)] & used], minlength=n_shell)
           - np.bincount(shell[edges[:, 0]], minlength=n_shell)
           + np.bincount(shell[tri[:, 0]], minlength=n_shell))[shell_ids]
    B = len(shell_ids)
    G = int(np.sum((2 - chi) // 2))
    # edges between faces
    f0, f1 = face[pairs[:, 0]], face[pairs[:, 1]]
    cut = f0 != f1
    ce, cf0, cf1 = edges[cut], f0[cut], f1[cut]
    # vertices: where three or more faces meet
    vf = np.unique(np.column_stack([np.repeat(tri, 1, axis=0).ravel(), np.repeat(face, 3)]), axis=0)
    n_faces_at = np.bincount(vf[:, 0], minlength=nv)
    corner = n_faces_at >= 3
    # chains of cut edges joined at non-corner vertices
    m = len(ce)
    ends = np.concatenate([ce[:, 0], ce[:, 1]])
    idx = np.concatenate([np.arange(m), np.arange(m)])
    keep = ~corner[ends]
    order = np.argsort(ends[keep], kind="stable")
    ke, ki = ends[keep][order], idx[keep][order]
    link = ke[1:] == ke[:-1]
    n_chain, chain = _components(m, ki[:-1][link], ki[1:][link]) if m else (0, np.zeros(0, int))
    touches = np.zeros(n_chain, bool)
    if m:
        np.logical_or.at(touches, chain, corner[ce[:, 0]] | corner[ce[:, 1]])
    E = n_chain
    V = int(corner.sum()) + int((~touches).sum())
    # loops: per face, components of its cut edges joined at shared vertices
    fe = np.concatenate([cf0, cf1])
    eidx = np.concatenate([np.arange(m), np.arange(m)])
    loops = 0
    faces_with_loops = 0
    if m:
        k = len(fe)
        node_v = np.concatenate([np.column_stack([fe, ce[eidx % m, 0]]), np.column_stack([fe, ce[eidx % m, 1]])])
        node_id = np.concatenate([np.arange(k), np.arange(k)])
        key = node_v[:, 0] * nv + node_v[:, 1]
        order = np.argsort(key, kind="stable")
        ks, ns = key[order], node_id[order]
        link = ks[1:] == ks[:-1]
        n_loop, loop = _components(k, ns[:-1][link], ns[1:][link])
        loop_face = np.zeros(n_loop, dtype=np.int64)
        loop_face[loop] = fe
        per_face = np.bincount(loop_face, minlength=F)
        loops = int(per_face.sum())
        faces_with_loops = int((per_face > 0).sum())
    L = loops - faces_with_loops
    V += F - faces_with_loops  # a face with no edge carries one vertex
    seg = _project_edges(pts, ce, cf0, cf1, carriers)
    nbytes = int(pts.nbytes + tri.nbytes + face.nbytes + ce.nbytes)
    return BRep(V=V, E=E, F=F, L=L, B=B, G=G, face_of_triangle=face, face_leaf=face_leaf, edge_segments=seg,
                nbytes=nbytes)
