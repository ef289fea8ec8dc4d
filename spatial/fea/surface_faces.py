"""Clusters confined to the CSG faces: a surface whose nodes take the part's corners and edges.

The free clustering of `spatial.fea.surface_clusters` lets a cluster span two
faces; at a size near a wall's thickness (a beam 10 thick at size 10) its
cells cover whole sections and the snapping onto the edges afterwards cannot
recover them: the surface cuts across the part.  Here the feature mesh
(`spatial.fea.surface_start`) is split into its faces first (each triangle
goes to the facet of the CSG tree that decides its centre), and

* every vertex where three or more faces meet (or a corner of the feature mesh)
  becomes a node, solved onto its facets;
* every curve between two faces is cut into pieces of about the size; the cut
  points become nodes, solved onto the curve's two facets;
* each face gets nodes of its own inside it (spaced like a Poisson disk, then
  moved by Lloyd steps to the centres of their cells), none within half a
  size of its boundary;
* every vertex of a face goes to the nearest node of that face or of its
  boundary, measured along the face (Dijkstra on the mesh of the face alone),
  so that no cell crosses from one face into another;
* the triangles are the dual of those cells: one per triangle of the feature
  mesh whose three corners lie in three cells.

References
----------
S. Valette, J.-M. Chassery, R. Prost, "Generic remeshing of 3D triangular
meshes with metric-dependent discrete Voronoi diagrams", IEEE TVCG 14(2), 2008,
doi:10.1109/TVCG.2007.70430 (the dual of discrete Voronoi cells).
"""

from __future__ import annotations

import numpy as np

from .facets import FacetField, independent_facets, project_to_surface, solve_on_facets
from .surface_quality import _is_closed_manifold, _normals, mesh_faces

__all__ = ["face_clusters"]

#: Least distance of two nodes placed inside a face, times the size (the Poisson-disk start).
SEED_SPACING = 0.8
#: Least distance of a node inside a face from the face's boundary, times the size.
SEED_CLEARANCE = 0.5
#: Faces whose normals agree to this cosine along their common boundary make one face (no crease).
SMOOTH_COSINE = 0.99
#: Pieces of a face smaller than this, times the size squared, join the neighbour they share most
#: boundary with (a strip of triangles along the line where two touching solids' faces meet).
SLIVER_AREA = 0.1
#: Lloyd steps moving the nodes inside the faces to the centres of their cells.
LLOYD_STEPS = 5


def face_clusters(mesh, ff: FacetField, size, seed=0):
    """Nodes and triangles of a surface of edge about `size` whose cells keep to the faces of `ff`.

    Parameters
    ----------
    mesh : pyvista.PolyData
        The solid's feature mesh (closed and manifold, ``feature_rank`` and ``feature_facets``
        in its point data), much finer than `size`.
    ff : FacetField
        The facets of the solid.
    size : float
        Target edge length.
    seed : int
        Seed of the Poisson-disk order of the nodes inside the faces.

    Returns
    -------
    points : (n, 3) float ndarray or None
        Nodes, on the solid (corners and edges solved onto their facets); None when the
        cells do not make a closed, manifold surface.
    faces : (m, 3) int ndarray or None
        Outward triangles.
    fixed : (n,) bool ndarray or None
        The nodes on corners and edges.

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing import mesh
    >>> part = box((100.0, 10.0, 10.0), center=(50.0, 0.0, 0.0))
    >>> p, f, fixed = face_clusters(mesh(part, voxel_size=2.5, features=True), FacetField(part), 10.0)
    >>> len(p), int(fixed.sum()), float(abs(p[:, 1:]).max())
    (44, 44, 5.0)
    """
    pts = np.asarray(mesh.points, dtype=np.float64)
    tris = mesh_faces(mesh)
    n = pts.shape[0]
    rank = np.asarray(mesh.point_data["feature_rank"]) if "feature_rank" in mesh.point_data else np.zeros(n)
    ffacets = (np.asarray(mesh.point_data["feature_facets"], dtype=np.int64).reshape(-1, 3)
               if "feature_facets" in mesh.point_data else np.full((n, 3), -1, np.int64))
    if len(ffacets) != n or len(tris) == 0 or not _is_closed_manifold(tris):
        return None, None, None
    k = len(ff.names)
    _, region, _ = ff(pts[tris].mean(axis=1))
    region = _merge_smooth(ff, pts, tris, np.asarray(region, dtype=np.int64), n)
    region = _merge_slivers(pts, tris, region, n, SLIVER_AREA * size**2)
    # one copy of each vertex per face it lies on
    ukey, copy_of = np.unique((tris * k + region[:, None]).reshape(-1), return_inverse=True)
    copy_of = copy_of.reshape(-1, 3)
    copy_vert = ukey // k
    faces_at = np.bincount(copy_vert, minlength=n)
    edges, pair = _boundary_edges(tris, region, n)
    bdeg = np.bincount(edges.reshape(-1), minlength=n)
    junction = (bdeg > 0) & ((faces_at >= 3) | (bdeg != 2) | (rank == 3))
    voxel = float(np.asarray(mesh.field_data["voxel_size"]).reshape(-1)[0]) if "voxel_size" in mesh.field_data \
        else size / 4.0
    chains = _chains(edges, pair, junction)
    # the curves' vertices put onto their facets first: their lengths are then the curves' own
    on_curve = np.zeros((n, 3))
    jv = np.flatnonzero(junction)
    jsets = [_facets_at(ukey, k, v, ffacets[v] if rank[v] == 3 else ()) for v in jv]
    cv, csets = [], []
    for path, _, (ra, rb) in chains:
        inner = path[~junction[path]]
        cv.append(inner)
        csets += [[ra, rb, *[int(f) for f in ffacets[v] if rank[v] == 2 and f >= 0 and f not in (ra, rb)]]
                  for v in inner]
    cv = np.concatenate(cv) if cv else np.zeros(0, np.int64)
    on_curve[jv] = _place(ff, pts[jv], jsets, np.full(len(jv), 3), size, voxel)
    on_curve[cv] = _place(ff, pts[cv], csets, np.full(len(cv), 2), size, voxel)
    seeds, sets, want, label = [on_curve[jv]], list(jsets), [3] * len(jv), np.full(n, -1, dtype=np.int64)
    label[jv] = np.arange(len(jv))
    count = len(jv)
    for path, closed, (ra, rb) in chains:
        kept = _unfolded(on_curve[path])
        q = on_curve[path[kept]]
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))])
        arc = arc[np.cumsum(kept) - 1]  # a vertex left out sits where the last one kept does
        q = on_curve[path]
        length = arc[-1]
        pieces = max(3 if closed else 1, int(round(length / size)))
        step = length / pieces
        at = np.arange(0 if closed else 1, pieces) * step
        seeds.append(np.stack([np.interp(at, arc, q[:, d]) for d in range(3)], axis=1))
        sets += [[ra, rb]] * len(at)
        want += [2] * len(at)
        own = dict(zip(range(0 if closed else 1, pieces), range(count, count + len(at))))
        count += len(at)
        j = np.rint(arc / step).astype(np.int64)
        for i, v in enumerate(path):
            if junction[v]:
                continue
            jj = j[i] % pieces if closed else j[i]
            label[v] = own[jj] if jj in own else label[path[0] if jj == 0 else path[-1]]
    seeds = np.concatenate(seeds).reshape(-1, 3)
    seeds = _place(ff, seeds, sets, np.asarray(want, dtype=np.int64), size, voxel)
    boundary_seeds = len(seeds)
    if boundary_seeds and (label[bdeg > 0] < 0).any():
        return None, None, None
    face_copies = _poisson_seeds(pts, copy_vert, bdeg, seeds, size, seed)
    area = _vertex_areas(pts, tris, copy_of, len(ukey))
    copies_label = None
    for step_no in range(LLOYD_STEPS + 1):
        copies_label = _cells(pts, copy_of, copy_vert, label, seeds, face_copies)
        if step_no == LLOYD_STEPS or face_copies.size == 0:
            break
        face_copies = _lloyd(pts, copy_vert, copies_label, area, face_copies, boundary_seeds)
    nodes = np.concatenate([seeds, project_to_surface(ff.solid, pts[copy_vert[face_copies]])]).reshape(-1, 3)
    lab = copies_label[copy_of]
    distinct = (lab[:, 0] != lab[:, 1]) & (lab[:, 1] != lab[:, 2]) & (lab[:, 0] != lab[:, 2])
    out = lab[distinct]
    _, first = np.unique(np.sort(out, axis=1), axis=0, return_index=True)
    out = out[np.sort(first)]
    if len(out) < 4 or not _is_closed_manifold(out) or np.unique(out).size != len(nodes):
        return None, None, None
    if not np.isfinite(nodes).all() or (np.linalg.norm(_normals(nodes, out), axis=1) <= 0).any():
        return None, None, None
    fixed = np.zeros(len(nodes), dtype=bool)
    fixed[:boundary_seeds] = True
    return nodes, out, fixed


def _merge_smooth(ff, pts, tris, region, n):
    """`region` with faces that meet without a crease (the coplanar faces of two touching solids, a
    fillet running into a plane) taken as one: the median cosine of their normals along their common
    boundary is over `SMOOTH_COSINE`.  Each set of such faces is named by its first facet."""
    edges, pair = _boundary_edges(tris, region, n)
    if len(edges) == 0:
        return region
    mid = 0.5 * (pts[edges[:, 0]] + pts[edges[:, 1]])
    ga = ff.gradients_of(mid, pair[:, 0])
    gb = ff.gradients_of(mid, pair[:, 1])
    cos = np.einsum("ij,ij->i", ga, gb) / np.maximum(np.linalg.norm(ga, axis=1) * np.linalg.norm(gb, axis=1), 1e-300)
    uk, inv = np.unique(pair, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    parent = np.arange(len(ff.names))

    def find(x):
        while parent[x] != x:
            x = parent[x]
        return x

    for i, (a, b) in enumerate(uk.tolist()):
        if np.median(cos[inv == i]) > SMOOTH_COSINE:
            ra, rb = find(a), find(b)
            parent[max(ra, rb)] = min(ra, rb)
    root = np.array([find(x) for x in range(len(parent))], dtype=np.int64)
    return root[region]


def _merge_slivers(pts, tris, region, n, least):
    """`region` with each connected piece of a face of area under `least` given to the neighbouring
    piece it shares the longest boundary with."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    area = 0.5 * np.linalg.norm(_normals(pts, tris), axis=1)
    m = len(tris)
    he = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    hf = np.tile(np.arange(m), 3)
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    order = np.argsort(key, kind="stable")
    f1, f2 = hf[order[0::2]], hf[order[1::2]]
    length = np.linalg.norm(pts[he[order[0::2], 0]] - pts[he[order[0::2], 1]], axis=1)
    for _ in range(8):
        same = region[f1] == region[f2]
        g = coo_matrix((np.ones(int(same.sum())), (f1[same], f2[same])), shape=(m, m))
        count, piece = connected_components(g, directed=False)
        piece_area = np.bincount(piece, weights=area, minlength=count)
        small = np.flatnonzero(piece_area < least)
        if small.size == 0 or small.size == count:
            break
        cross = ~same
        a, b, w = piece[f1[cross]], piece[f2[cross]], length[cross]
        a, b, w = np.concatenate([a, b]), np.concatenate([b, a]), np.concatenate([w, w])
        sel = np.isin(a, small) & ~np.isin(b, small)
        if not sel.any():
            break
        pk = a[sel] * count + b[sel]
        uk, inv = np.unique(pk, return_inverse=True)
        tot = np.bincount(inv.reshape(-1), weights=w[sel])
        src, dst = uk // count, uk % count
        best = np.lexsort((-tot, src))
        first = np.ones(best.size, dtype=bool)
        first[1:] = src[best][1:] != src[best][:-1]
        piece_region = np.zeros(count, dtype=np.int64)
        piece_region[piece] = region
        piece_region[src[best][first]] = piece_region[dst[best][first]]
        region = piece_region[piece]
    return region


def _boundary_edges(tris, region, n):
    """Edges of the mesh between triangles of two faces, ``(e, 2)``, and those faces, ``(e, 2)``."""
    he = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    hf = np.tile(np.arange(len(tris)), 3)
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    order = np.argsort(key, kind="stable")
    h1, h2 = order[0::2], order[1::2]
    cross = region[hf[h1]] != region[hf[h2]]
    pair = np.sort(np.stack([region[hf[h1]], region[hf[h2]]], axis=1), axis=1)
    return he[h1][cross], pair[cross]


def _facets_at(ukey, k, v, extra):
    """The faces around vertex `v` (its copies), then `extra` facets."""
    lo, hi = np.searchsorted(ukey, [v * k, (v + 1) * k])
    own = [int(x) for x in ukey[lo:hi] % k]
    return own + [int(f) for f in extra if f >= 0 and f not in own]


def _chains(edges, pair, junction):
    """The curves between faces as vertex paths: ``(path, closed, (face_a, face_b))`` from junction to junction,
    or closed loops without one."""
    adj = {}
    for e, (a, b) in enumerate(edges.tolist()):
        adj.setdefault(a, []).append(e)
        adj.setdefault(b, []).append(e)
    used = np.zeros(len(edges), dtype=bool)

    def walk(start, e):
        path, cur = [start], start
        while True:
            used[e] = True
            a, b = edges[e]
            nxt = int(b if a == cur else a)
            path.append(nxt)
            if junction[nxt]:
                return np.asarray(path), False
            rest = [x for x in adj[nxt] if not used[x]]
            if not rest:
                return np.asarray(path), nxt == start
            cur, e = nxt, rest[0]

    out = []
    for j in sorted(v for v in adj if junction[v]):
        for e in adj[j]:
            if not used[e]:
                out.append((*walk(j, e), tuple(pair[e])))
    for e in range(len(edges)):
        if not used[e]:
            out.append((*walk(int(edges[e][0]), e), tuple(pair[e])))
    return out


def _unfolded(q, cosine=-0.5):
    """Which points of a path to keep so that it never turns back on itself (turns with cosine under
    `cosine`): near a concave corner the faces of the feature mesh can overlap by a voxel, and the
    curve between them runs back and forth there.  The ends are kept."""
    keep = np.ones(len(q), dtype=bool)
    while True:
        idx = np.flatnonzero(keep)
        if idx.size < 3:
            return keep
        d = np.diff(q[idx], axis=0)
        d /= np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]
        turn = np.einsum("ij,ij->i", d[:-1], d[1:])
        bad = np.flatnonzero(turn < cosine)
        if bad.size == 0:
            return keep
        keep[idx[bad[0] + 1]] = False


def _poisson_seeds(pts, copy_vert, bdeg, seeds, size, seed):
    """Copies of inner vertices of the faces, at least ``SEED_SPACING * size`` from each other and the
    boundary nodes, and ``SEED_CLEARANCE * size`` from the faces' boundaries, taken in random order."""
    from scipy.spatial import cKDTree

    inner = np.flatnonzero(bdeg[copy_vert] == 0)
    if inner.size == 0:
        return inner
    p = pts[copy_vert[inner]]
    keep = np.ones(inner.size, dtype=bool)
    if (bdeg > 0).any():
        d, _ = cKDTree(pts[bdeg > 0]).query(p)
        keep &= d >= SEED_CLEARANCE * size
    if seeds.size:
        d, _ = cKDTree(seeds).query(p)
        keep &= d >= SEED_SPACING * size
    inner, p = inner[keep], p[keep]
    order = np.random.default_rng(seed).permutation(inner.size)
    r = SEED_SPACING * size
    grid, taken = {}, []
    for i in order:
        cell = tuple(np.floor(p[i] / r).astype(np.int64))
        near = False
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for q in grid.get((cell[0] + dx, cell[1] + dy, cell[2] + dz), ()):
                        if np.sum((p[q] - p[i]) ** 2) < r * r:
                            near = True
                            break
                    if near:
                        break
                if near:
                    break
        if not near:
            grid.setdefault(cell, []).append(i)
            taken.append(i)
    return inner[np.asarray(taken, dtype=np.int64)]


def _vertex_areas(pts, tris, copy_of, ncopies):
    """A third of the area of the triangles around each copy."""
    area = 0.5 * np.linalg.norm(_normals(pts, tris), axis=1)
    return np.bincount(copy_of.reshape(-1), weights=np.repeat(area / 3.0, 3), minlength=ncopies)


def _cells(pts, copy_of, copy_vert, label, seeds, face_copies):
    """The node each copy goes to: the nearest along its face (boundary vertices keep their curve's node)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    nc = len(copy_vert)
    e = np.concatenate([copy_of[:, [0, 1]], copy_of[:, [1, 2]], copy_of[:, [2, 0]]])
    w = np.linalg.norm(pts[copy_vert[e[:, 0]]] - pts[copy_vert[e[:, 1]]], axis=1)
    rows, cols, wts = [e[:, 0], e[:, 1]], [e[:, 1], e[:, 0]], [w, w]
    tiny = 1e-12 * max(float(np.ptp(pts, axis=0).max()), 1.0)
    on = np.flatnonzero(label[copy_vert] >= 0)  # boundary copies: from their curve's node
    s = label[copy_vert[on]]
    rows.append(nc + s)
    cols.append(on)
    wts.append(np.linalg.norm(pts[copy_vert[on]] - seeds[s], axis=1) + tiny)
    nf = len(face_copies)
    boundary_seeds = len(seeds)
    rows.append(nc + boundary_seeds + np.arange(nf))
    cols.append(face_copies)
    wts.append(np.full(nf, tiny))
    size = nc + boundary_seeds + nf
    g = coo_matrix((np.concatenate(wts), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)).tocsr()
    _, _, src = dijkstra(g, directed=True, indices=np.arange(nc, size), min_only=True, return_predecessors=True)
    lab = src[:nc] - nc
    lab[on] = s
    return lab


def _lloyd(pts, copy_vert, lab, area, face_copies, boundary_seeds):
    """Each inner node moved to the vertex of its cell nearest the cell's centre."""
    j = lab - boundary_seeds
    mine = np.flatnonzero(j >= 0)
    j = j[mine]
    nf = len(face_copies)
    wsum = np.bincount(j, weights=area[mine], minlength=nf)
    centre = np.stack([np.bincount(j, weights=area[mine] * pts[copy_vert[mine], d], minlength=nf)
                       for d in range(3)], axis=1) / np.maximum(wsum, 1e-300)[:, None]
    dist = np.linalg.norm(pts[copy_vert[mine]] - centre[j], axis=1)
    order = np.lexsort((dist, j))
    first = np.ones(order.size, dtype=bool)
    first[1:] = j[order][1:] != j[order][:-1]
    out = face_copies.copy()
    out[j[order][first]] = mine[order][first]
    return out


def _place(ff, p, sets, want, size, voxel):
    """Points of corners (`want` 3) and curves (2) solved onto that many crossing facets of their `sets`
    (else of those within a tenth of a voxel), each kept where it is (projected onto the solid) when
    no such facets or no solution close by is found."""
    solid = ff.solid
    p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
    if len(p) == 0:
        return p
    out = project_to_surface(solid, p)
    _, _, fv = ff(p)
    near = np.abs(fv) < 0.1 * voxel
    first = np.zeros_like(near)
    for i, s in enumerate(sets):
        near[s, i] = True
        first[s, i] = True  # the point's own faces
    picked = np.full((len(p), 3), -1, dtype=np.int64)
    for count in (3, 2):
        rows = np.flatnonzero((want >= count) & (picked[:, 1] < 0))
        if rows.size == 0:
            continue
        got = independent_facets(ff, p[rows], first[:, rows], count=count)
        miss = (got < 0).any(axis=1)
        if miss.any():
            got[miss] = independent_facets(ff, p[rows[miss]], near[:, rows[miss]], count=count)
        ok = (got >= 0).all(axis=1)
        picked[rows[ok], :count] = got[ok]
    rows = np.flatnonzero(picked[:, 1] >= 0)
    if rows.size:
        q = solve_on_facets(ff, p[rows], picked[rows], iters=12)
        _, _, fq = ff(q)
        use = picked[rows]
        on = np.where(use >= 0, np.abs(fq[np.maximum(use, 0), np.arange(len(rows))[:, None]]), 0.0)
        tol = 1e-9 * max(float(np.abs(p).max()), 1.0)
        good = np.isfinite(q).all(axis=1) & (on.max(axis=1) < tol) & (np.abs(solid(q)) < tol)
        good &= np.linalg.norm(q - p[rows], axis=1) < 0.5 * size
        out[rows[good]] = q[good]
    return out
