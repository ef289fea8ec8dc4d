"""Tetrahedral meshes of solids for finite-element analysis.

`tet_mesh` remeshes the solid's boundary (`surface_for_fea`), fills it with
TetGen's quality Delaunay refinement, removes the slivers TetGen leaves by
smoothing interior vertices (each candidate position is scored by the worst
dihedral angle of the elements around the vertex), optionally adds mid-edge
nodes (10-node tetrahedra, boundary mid-nodes projected onto the true
surface), and names the boundary by the CSG facets that make it.

References
----------
H. Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator", ACM TOMS
41(2), 2015, doi:10.1145/2629697.
L. A. Freitag, C. Ollivier-Gooch, "Tetrahedral mesh improvement using swapping
and smoothing", IJNME 40, 1997 (optimisation-based smoothing).
"""

from __future__ import annotations

import os
import tempfile
import warnings
from contextlib import contextmanager

import numpy as np

from implicit.solid import Solid, as_positive
from .surface import (FacetField, _deviation, _is_closed_manifold, mesh_faces, project_to_surface,
                          self_intersections, surface_for_fea)
from .model import SIDE_NODES, TetMesh, _side_nodes  # noqa: F401
from .quality import _EDGES, dihedral_angles, radius_edge_ratio, tet_quality, tet_volumes

__all__ = ["TetMesh", "tet_mesh", "MeshQualityWarning", "SIDE_NODES"]

#: The two corners shared by sides i and j (``_SIDE_COMMON[i, j]``).
_SIDE_COMMON = np.array([[sorted(set(SIDE_NODES[i]) & set(SIDE_NODES[j])) if i != j else [0, 0]
                          for j in range(4)] for i in range(4)])

#: Volume of a regular tetrahedron of unit edge.
_REGULAR_VOLUME = 1.0 / (6.0 * np.sqrt(2.0))


#: Keep the remeshed surface as it is (TetGen -Y): its points stay on the true surface.
#: Without it TetGen splits boundary triangles and leaves flat slivers on the boundary
#: (274 elements under 5 degrees on a torus at size 0.08, none with it).
_KEEP_SURFACE = "Y"


@contextmanager
def _scratch_directory():
    """Run in a temporary working directory: TetGen drops files such as
    ``tetgen-tmpfile_skipped.node`` into the current one when it gives up on faces."""
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="implicad-tetgen-") as tmp:
        os.chdir(tmp)
        try:
            yield
        finally:
            os.chdir(old)


class MeshQualityWarning(UserWarning):
    """The mesher stopped short of the asked quality (e.g. at its Steiner-point cap)."""


# ---------------------------------------------------------------------------
# sliver removal
# ---------------------------------------------------------------------------

def _score(d, min_dihedral, max_dihedral):
    """Quality of elements from their dihedral angles ``(..., 6)``: both limits map to min_dihedral."""
    lo = d.min(axis=-1)
    hi = (180.0 - d.max(axis=-1)) * (min_dihedral / (180.0 - max_dihedral))
    return np.minimum(lo, hi)


def _element_score(points, tets, min_dihedral, max_dihedral, radius_edge=None):
    """`_score` of the elements, with a radius-edge ratio above `radius_edge` scored as a
    dihedral angle under the minimum (the ratio over the limit scales it down)."""
    sc = _score(dihedral_angles(points, tets), min_dihedral, max_dihedral)
    if radius_edge is not None:
        sc = np.minimum(sc, min_dihedral * radius_edge / np.maximum(radius_edge_ratio(points, tets), 1e-300))
    return sc


def _improve(points, tets, movable, min_dihedral, max_dihedral, *, rounds=40, seed=0, solid=None, slide=None,
             jitter=1.0, radius_edge=None):
    """Smooth movable vertices of bad elements until no element is bad or nothing moves.

    Each round takes an independent set of candidate vertices (no two in one
    element), tries the mean of the neighbours and random nearby positions,
    and keeps the one with the best worst-element score (never inverting one).
    """
    rng = np.random.default_rng(seed)
    pts = points.copy()
    n = pts.shape[0]
    flat = tets.reshape(-1)
    order = np.argsort(flat, kind="stable")
    vert_sorted = flat[order]
    tet_of = order // 4
    starts = np.searchsorted(vert_sorted, np.arange(n + 1))
    target = min_dihedral + 1.0
    n_trials = 24
    score = _element_score(pts, tets, min_dihedral, max_dihedral, radius_edge)
    for _ in range(rounds):
        bad = score < target
        if not bad.any():
            break
        cand = np.zeros(n, dtype=bool)
        cand[tets[bad].reshape(-1)] = True
        cand &= movable
        if not cand.any():
            break
        # Independent set: a vertex moves only if it has the smallest priority among the
        # candidates of all its elements (priorities drawn anew each round, so all get turns).
        prio = rng.permutation(n)
        key = np.where(cand[tets], prio[tets], n)
        tmin = key.min(axis=1)
        blocked = np.zeros(n, dtype=bool)
        blocked[flat[tmin[np.arange(flat.size) // 4] != prio[flat]]] = True
        verts = np.nonzero(cand & ~blocked)[0]
        if verts.size == 0:
            break
        # The pairs (vertex, element) around the moving vertices.
        counts = starts[verts + 1] - starts[verts]
        idx = np.repeat(starts[verts], counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
        pair_tet = tet_of[idx]
        pair_v = np.repeat(np.arange(verts.size), counts)
        seg = np.concatenate([[0], np.cumsum(counts)[:-1]])
        elem = tets[pair_tet]
        x = pts[elem]
        is_v = elem == verts[pair_v][:, None]
        # Trial positions: current, neighbour mean (two step lengths), random jitter.
        nbr_mean = np.zeros((verts.size, 3))
        np.add.at(nbr_mean, pair_v, x.sum(axis=1) - pts[verts[pair_v]])
        nbr_mean /= (3.0 * counts)[:, None]
        edge = np.zeros(verts.size)
        np.maximum.at(edge, pair_v, np.linalg.norm(x - pts[verts[pair_v]][:, None, :], axis=2).max(axis=1))
        cur = pts[verts]
        trials = [cur, nbr_mean, 0.5 * (cur + nbr_mean)]
        for k in range(n_trials):
            scale = (0.05 + 0.25 * (k % 4) / 3.0) * jitter * edge
            trials.append(cur + rng.normal(size=cur.shape) * scale[:, None] / np.sqrt(3.0))
        trials = np.stack(trials)  # (t, k, 3)
        if slide is not None:
            sl = slide[verts]
            if sl.any():
                tv = trials[1:, sl].reshape(-1, 3)
                trials[1:, sl] = project_to_surface(solid, tv, steps=3).reshape(trials.shape[0] - 1, -1, 3)
        best_score = None
        best = np.zeros(verts.size, dtype=np.intp)
        for j in range(trials.shape[0]):
            xt = np.where(is_v[:, :, None], trials[j][pair_v][:, None, :], x)
            vol = tet_volumes(xt.reshape(-1, 3), np.arange(xt.shape[0] * 4).reshape(-1, 4))
            sc = _element_score(xt.reshape(-1, 3), np.arange(xt.shape[0] * 4).reshape(-1, 4), min_dihedral, max_dihedral,
                                radius_edge)
            sc = np.where(vol > 0, sc, -np.inf)
            worst = np.minimum.reduceat(sc, seg)
            if best_score is None:
                best_score = worst
            else:
                better = worst > best_score + 1e-9
                best_score = np.where(better, worst, best_score)
                best[better] = j
        pts[verts] = trials[best, np.arange(verts.size)]
        # Only the elements around moved vertices change their score.
        touched = np.unique(pair_tet[best[pair_v] != 0])
        if touched.size:
            score[touched] = _element_score(pts, tets[touched], min_dihedral, max_dihedral, radius_edge)
    return pts


def _peel(points, tets, min_dihedral, max_dihedral):
    """Remove flat elements that have two sides on the boundary.

    Such a sliver lies on the surface (all four nodes on it); removing it
    leaves its two other sides as boundary, which stay on the surface.  An
    element is kept when its remaining sides' common edge is already on the
    boundary (the boundary would stop being manifold).  Returns the elements
    left and how many were removed.
    """
    score = _score(dihedral_angles(points, tets), min_dihedral, max_dihedral)
    bad = np.nonzero(score < min_dihedral)[0]
    if bad.size == 0:
        return tets, 0
    bfaces, belem, bside = _boundary_faces(tets)
    nb = np.bincount(belem, minlength=len(tets))
    cand = bad[nb[bad] == 2]
    if cand.size == 0:
        return tets, 0
    # The edge shared by the two inner sides must not be on the boundary already.
    on_b = np.zeros((len(tets), 4), dtype=bool)
    on_b[belem, bside] = True
    sides = on_b[cand]
    inner = np.nonzero(~sides)[1].reshape(-1, 2)
    edge = np.sort(tets[cand[:, None], _SIDE_COMMON[inner[:, 0], inner[:, 1]]], axis=1)
    bedges = np.sort(np.concatenate([bfaces[:, [0, 1]], bfaces[:, [1, 2]], bfaces[:, [2, 0]]]), axis=1)
    n = points.shape[0] + 1
    on_boundary = np.isin(edge[:, 0] * n + edge[:, 1], bedges[:, 0] * n + bedges[:, 1])
    # One removal per neighbourhood: no two removed elements may share a node.
    cand = cand[~on_boundary]
    if cand.size == 0:
        return tets, 0
    uniq, cnt = np.unique(tets[cand].reshape(-1), return_counts=True)
    cand = cand[~np.isin(tets[cand], uniq[cnt > 1]).any(axis=1)]
    keep = np.ones(len(tets), dtype=bool)
    keep[cand] = False
    return tets[keep], int(cand.size)


# ---------------------------------------------------------------------------
# boundary, quadratic nodes, sets
# ---------------------------------------------------------------------------

def _boundary_faces(tets):
    """Sides that belong to one element: (corner nodes (b, 3), element (b,), side (b,))."""
    m = len(tets)
    sides = tets[:, SIDE_NODES]  # (m, 4, 3)
    flat = sides.reshape(-1, 3)
    key = np.sort(flat, axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inv.reshape(-1)] == 1
    elem = np.repeat(np.arange(m), 4)[once]
    side = np.tile(np.arange(4), m)[once]
    return flat[once], elem, side


def _add_midnodes(points, tets):
    """10-node elements from 4-node ones: shared mid-edge nodes appended to the points."""
    edges = tets[:, _EDGES]  # (m, 6, 2)
    key = np.sort(edges.reshape(-1, 2), axis=1)
    uniq, inv = np.unique(key, axis=0, return_inverse=True)
    mid = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
    ids = points.shape[0] + inv.reshape(-1, 6)
    return np.concatenate([points, mid]), np.concatenate([tets, ids], axis=1), uniq


def _project_midnodes(solid, ff, points, tets10, boundary, n_corner, size):
    """Move mid-edge nodes of boundary edges onto the surface (onto feature curves
    when both end nodes lie on the same two facets); undo moves that fold an element."""
    pts = points.copy()
    b_edges = np.sort(np.concatenate([boundary[:, [0, 1]], boundary[:, [1, 2]], boundary[:, [2, 0]]]), axis=1)
    b_edges = np.unique(b_edges, axis=0)
    # Mid node of each boundary edge: look it up among the elements' edges.
    el_edges = np.sort(tets10[:, :4][:, _EDGES].reshape(-1, 2), axis=1)
    el_mid = tets10[:, 4:].reshape(-1)
    ekey = el_edges[:, 0] * (n_corner + 1) + el_edges[:, 1]
    bkey = b_edges[:, 0] * (n_corner + 1) + b_edges[:, 1]
    _, first = np.unique(ekey, return_index=True)
    pos = np.searchsorted(ekey[first], bkey)
    mids = el_mid[first[pos]]
    start = pts[mids].copy()
    moved = project_to_surface(solid, start, max_move=size)
    # Feature edges: both ends on the same pair of facets.
    _, _, fa = ff(pts[b_edges[:, 0]])
    _, _, fb = ff(pts[b_edges[:, 1]])
    tol = 1e-7 * max(size, 1.0)
    on_both = (np.abs(fa) < tol) & (np.abs(fb) < tol)  # (k, e)
    feature = on_both.sum(axis=0) >= 2
    if feature.any():
        from .facets import independent_facets, solve_on_facets

        ii = np.nonzero(feature)[0]
        sets = independent_facets(ff, start[ii], on_both[:, ii], count=2)
        ok = sets[:, 1] >= 0
        ii, sets = ii[ok], sets[ok]
        snapped = solve_on_facets(ff, start[ii], sets)
        good = (np.linalg.norm(snapped - start[ii], axis=1) < size) & np.isfinite(snapped).all(axis=1)
        good &= np.abs(solid(snapped)) < tol
        moved[ii[good]] = snapped[good]
    pts[mids] = moved
    from .quality import scaled_jacobian

    bad = scaled_jacobian(pts, tets10) <= MIN_CURVED_JACOBIAN
    if bad.any():
        # A curved boundary edge folds an element whose other nodes lie close to it: carry the
        # boundary displacement into the interior mid-edge nodes instead of giving it up.
        pts = _spread_curving(points, pts, tets10, mids)
    for _ in range(5):
        sj = scaled_jacobian(pts, tets10)
        bad = sj <= 0
        if not bad.any():
            break
        back = np.intersect1d(tets10[bad, 4:].reshape(-1), mids)
        pts[back] = points[back]
    return pts


#: Scaled Jacobian under which a curved element has its interior mid-edge nodes moved along.
MIN_CURVED_JACOBIAN = 0.2


def _spread_curving(straight, curved, tets10, boundary_mids, iterations=40):
    """Move interior mid-edge nodes by a smooth extension of the boundary mid-node moves.

    The displacement of the boundary mid-edge nodes (fixed) is extended to the
    other mid-edge nodes by Jacobi steps of a graph Laplacian (each mid node
    takes the mean displacement of the mid nodes of its elements), which
    bends the elements next to a curved boundary along with it.
    """
    n = len(straight)
    disp = curved - straight
    fixed = np.zeros(n, dtype=bool)
    fixed[boundary_mids] = True
    fixed[: int(tets10[:, :4].max()) + 1] = True  # corners stay
    mid = tets10[:, 4:]
    # Pairs of mid nodes sharing an element (both directions).
    i, j = np.triu_indices(6, 1)
    a = np.concatenate([mid[:, i].reshape(-1), mid[:, j].reshape(-1)])
    b = np.concatenate([mid[:, j].reshape(-1), mid[:, i].reshape(-1)])
    deg = np.bincount(a, minlength=n).astype(np.float64)
    free = ~fixed & (deg > 0)
    for _ in range(iterations):
        acc = np.zeros((n, 3))
        np.add.at(acc, a, disp[b])
        disp[free] = acc[free] / deg[free][:, None]
    out = curved.copy()
    out[free] = straight[free] + disp[free]
    return out


def _name_sets(ff, points, boundary, boundary_side, boundary_element, tets):
    """Face sets (by deciding facet at each face centre) and node sets."""
    centres = points[boundary].mean(axis=1)
    onsurf = project_to_surface(ff.solid, centres, steps=2)
    _, dec, _ = ff(onsurf)
    face_sets = {"surface": np.arange(len(boundary))}
    node_sets = {}
    side_all = _side_nodes(tets, boundary_element, boundary_side)
    node_sets["surface"] = np.unique(side_all)
    for k in np.unique(dec):
        sel = np.nonzero(dec == k)[0]
        name = ff.names[k]
        face_sets[name] = sel
        node_sets[name] = np.unique(side_all[sel])
    return face_sets, node_sets


# ---------------------------------------------------------------------------
# the mesher
# ---------------------------------------------------------------------------

def tet_mesh(solid, *, size, order=1, min_dihedral=10.0, radius_edge=1.5, max_dihedral=165.0,
             surface=None, steiner_cap=None, volume_tolerance=0.005, strict=False, seed=0) -> TetMesh:
    """Tetrahedral mesh of `solid` with elements of edge length about `size`.

    Parameters
    ----------
    solid : Solid
        A bounded solid.
    size : float
        Target edge length (surface and volume).
    order : {1, 2}
        4-node (linear) or 10-node (quadratic) tetrahedra; quadratic boundary
        mid-edge nodes lie on the true surface (on the feature curve for an
        edge along a sharp edge).
    min_dihedral, max_dihedral : float
        Dihedral angles (degrees) every element should keep within.
    radius_edge : float
        Largest circumradius-to-shortest-edge ratio asked of TetGen (> 1).
    surface : pyvista.PolyData, optional
        A closed boundary to fill; by default ``surface_for_fea(solid, size=size)``.
    steiner_cap : int, optional
        Most points TetGen may add (default: 20 times the expected node count).
    volume_tolerance : float
        Allowed relative difference between the mesh volume and the volume
        enclosed by the solid estimated from the boundary (see Notes).
    strict : bool
        Raise instead of warning when the quality or volume check fails.
    seed : int
        Seed of the smoothing's random trial positions.

    Returns
    -------
    TetMesh

    Raises
    ------
    TypeError
        When `solid` is not a Solid.
    ValueError
        On a bad option value, an inverted element, or (with `strict`) a
        quality or volume check that fails.

    Warns
    -----
    MeshQualityWarning
        When the asked quality was not reached (TetGen stopped at its
        Steiner-point cap, or slivers remain) or the volume check fails.

    Notes
    -----
    The volume check compares the mesh volume with the solid's volume
    estimated from the boundary triangles: for each triangle with vertices
    on the surface, the gap to the surface is about a quadratic bubble whose
    mean is 3/4 of its value at the centre, so
    ``V ~ V_mesh - 3/4 sum(area_i f(centre_i))``.

    Examples
    --------
    >>> from implicit import sphere
    >>> m = tet_mesh(sphere(1.0), size=0.4)          # doctest: +SKIP
    >>> m.quality.min_dihedral >= 10.0               # doctest: +SKIP
    True
    """
    import pyvista as pv

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    size = as_positive(size, "size")
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order: expected 1 or 2, got {order!r}")
    min_dihedral = as_positive(min_dihedral, "min_dihedral", allow_zero=True)
    max_dihedral = as_positive(max_dihedral, "max_dihedral")
    if not 0 <= min_dihedral < 70.5:
        raise ValueError(f"min_dihedral: expected degrees in [0, 70.5), got {min_dihedral!r}")
    if not 70.6 < max_dihedral <= 180:
        raise ValueError(f"max_dihedral: expected degrees in (70.6, 180], got {max_dihedral!r}")
    radius_edge = as_positive(radius_edge, "radius_edge")
    if radius_edge <= 1.0:
        raise ValueError(f"radius_edge: expected a ratio > 1 (TetGen does not terminate below), got {radius_edge!r}")
    volume_tolerance = as_positive(volume_tolerance, "volume_tolerance")
    if surface is not None and not isinstance(surface, pv.PolyData):
        raise TypeError(f"surface: expected a pyvista.PolyData, got {type(surface).__name__}")
    if steiner_cap is not None and (isinstance(steiner_cap, bool) or not isinstance(steiner_cap, (int, np.integer)) or steiner_cap < 0):
        raise ValueError(f"steiner_cap: expected a non-negative integer, got {steiner_cap!r}")
    if not solid.is_bounded or solid.is_empty_bounds:
        raise ValueError("solid: expected a bounded, non-empty solid")

    import tetgen

    if surface is None:
        surface = surface_for_fea(solid, size=size)
        sfaces = mesh_faces(surface)
    else:
        # TetGen aborts the whole process on such input: check it first.
        sfaces = mesh_faces(surface)
        if len(sfaces) == 0 or not _is_closed_manifold(sfaces):
            raise ValueError("surface: expected a closed, manifold triangle surface")
        crossing = self_intersections(surface)
        if crossing:
            raise ValueError(f"surface: {crossing} triangles intersect others; TetGen needs a surface "
                             "free of self-intersections")
    spts = np.asarray(surface.points, dtype=np.float64)
    enclosed = abs(float(surface.volume))
    expected_nodes = int(enclosed / (_REGULAR_VOLUME * size**3) / 5.0) + len(spts)
    cap = int(steiner_cap) if steiner_cap is not None else 20 * expected_nodes + 1000
    tg = tetgen.TetGen(spts, sfaces.astype(np.int32))
    switches = (f"pq{radius_edge:g}/{min_dihedral:g}a{_REGULAR_VOLUME * size**3:.6g}"
                f"o/{max_dihedral:g}O9/7S{cap}{_KEEP_SURFACE}Q")
    try:
        with _scratch_directory(), _native_stdout_silenced():
            nodes, elems, *_ = tg.tetrahedralize(switches=switches)
    except RuntimeError as exc:
        raise ValueError(f"surface: TetGen could not mesh it ({exc}); is it closed and free of "
                         "self-intersections (see self_intersections)?") from exc
    nodes = np.asarray(nodes, dtype=np.float64)
    elems = np.asarray(elems, dtype=np.int64)
    if len(elems) == 0:
        raise ValueError("solid: TetGen made no elements (the surface may intersect itself)")
    vol = tet_volumes(nodes, elems)
    neg = vol < 0
    elems[neg] = elems[neg][:, [0, 2, 1, 3]]
    info = {"tetgen_switches": switches, "steiner_cap": cap, "tetgen_points": int(len(nodes)),
            "surface_points": int(len(spts))}
    cap_hit = len(nodes) - len(spts) >= cap
    # Boundary nodes stay; interior nodes are smoothed to remove slivers.
    bfaces, belem, bside = _boundary_faces(elems)
    movable = np.ones(len(nodes), dtype=bool)
    movable[np.unique(bfaces)] = False
    # With -Y TetGen keeps the surface; count any point it still had to add on it.
    info["boundary_steiner_points"] = int(np.setdiff1d(np.unique(bfaces), np.arange(len(spts))).size)
    nodes = _improve(nodes, elems, movable, min_dihedral, max_dihedral, seed=seed, radius_edge=radius_edge)
    if np.any(_element_score(nodes, elems, min_dihedral, max_dihedral, radius_edge) < min_dihedral):
        # Slivers lying on the boundary: let boundary vertices off the sharp edges slide on the surface.
        _, _, fv = FacetField(solid)(nodes)
        on_feature = (np.abs(fv) < 1e-7 * max(size, 1.0)).sum(axis=0) >= 2
        slide = ~movable & ~on_feature
        nodes = _improve(nodes, elems, movable | slide, min_dihedral, max_dihedral, seed=seed + 1,
                         solid=solid, slide=slide, radius_edge=radius_edge)
        info["boundary_slid"] = True
        elems, peeled = _peel(nodes, elems, min_dihedral, max_dihedral)
        if peeled:
            info["peeled"] = peeled
            bfaces, belem, bside = _boundary_faces(elems)
        for extra in range(3):
            # Stubborn slivers: more rounds with fresh random trials.
            if not np.any(_element_score(nodes, elems, min_dihedral, max_dihedral, radius_edge) < min_dihedral):
                break
            nodes = _improve(nodes, elems, movable | slide, min_dihedral, max_dihedral, seed=seed + 2 + extra,
                             solid=solid, slide=slide, rounds=80, jitter=1.0 + extra, radius_edge=radius_edge)
    if np.any(tet_volumes(nodes, elems) <= 0):
        raise ValueError("tet_mesh: an element is inverted after meshing (zero or negative volume)")
    tets = elems
    n_corner = len(nodes)
    if order == 2:
        nodes, tets, _ = _add_midnodes(nodes, elems)
        ff = FacetField(solid)
        nodes = _project_midnodes(solid, ff, nodes, tets, bfaces, n_corner, size)
    ff = FacetField(solid)
    face_sets, node_sets = _name_sets(ff, nodes, bfaces, bside, belem, tets)
    quality = tet_quality(nodes, tets, min_dihedral=min_dihedral)
    if quality.min_scaled_jacobian <= 0:
        raise ValueError(f"tet_mesh: inverted element (scaled Jacobian {quality.min_scaled_jacobian:.3g})")
    # Volume check against the solid's volume estimated from the boundary.
    a, b, c = (nodes[bfaces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    linear = float(tet_volumes(nodes, tets[:, :4]).sum())
    estimate = linear - 0.75 * float(np.sum(area * solid((a + b + c) / 3.0)))
    rel = abs(quality.volume - estimate) / max(abs(estimate), 1e-300)
    info.update(volume_estimate=estimate, volume_error=rel, cap_hit=bool(cap_hit))
    bnodes = np.unique(bfaces)
    remap = np.zeros(len(nodes), dtype=np.int64)
    remap[bnodes] = np.arange(bnodes.size)
    dev = _deviation(solid, nodes[bnodes], remap[bfaces])
    problems = []
    if cap_hit:
        problems.append(f"TetGen stopped at its Steiner-point cap ({cap} points); raise steiner_cap or size")
    if quality.min_dihedral < min_dihedral - 1e-9 or quality.max_dihedral > max_dihedral + 1e-9:
        problems.append(f"dihedral angles {quality.min_dihedral:.2f}..{quality.max_dihedral:.2f} deg outside the asked "
                        f"{min_dihedral:g}..{max_dihedral:g} ({quality.n_below} elements below)")
    if rel > volume_tolerance:
        problems.append(f"mesh volume {quality.volume:.6g} differs from the solid's estimated {estimate:.6g} "
                        f"by {100 * rel:.2f} percent; use a smaller size")
    info["problems"] = problems
    for msg in problems:
        if strict:
            raise ValueError(f"tet_mesh: {msg}")
        warnings.warn(msg, MeshQualityWarning, stacklevel=2)
    return TetMesh(points=nodes, tets=tets, boundary=bfaces, boundary_element=belem, boundary_side=bside,
                   face_sets=face_sets, node_sets=node_sets, quality=quality, surface_deviation=dev, info=info)


@contextmanager
def _native_stdout_silenced():
    """Send file descriptor 1 to /dev/null: the TetGen wrapper prints from C++
    ("parsing switches", "success") even with its quiet switch."""
    import sys

    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):  # no real stdout (captured, closed)
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
