"""Every property a boundary mesh of `spatial.mesh` must have, checked on one fuzz case.

`failures(case)` meshes a `fuzzgen.Case` and returns the kinds of failure
found (an empty list when the mesh is valid): closed, every edge in exactly
two triangles, one fan of triangles around every vertex, consistently
oriented and enclosing a positive volume, no zero-area, repeated-index or
duplicate triangles, only finite vertices, and a volume that agrees with a
Monte-Carlo estimate of the solid's volume.  The Monte-Carlo tolerance is
statistical (``Z`` standard errors of a binomial proportion); to it is added
the lattice's own error, at most half a voxel of thickness over the surface
(a vertex of marching cubes lies on its lattice edge, within one voxel of
the surface; refined vertices are on it, so the true error is far smaller).

A mesh that lost volume is judged by what the mesher said.  When it warned
of a wall thinner than two voxels (``the wall may be lost``), of a speck,
sliver or gap thinner than two voxels (``the feature may be lost``) or found no
surface at all (``no surface crosses the sampled nodes``), the loss is
the one announced if the mesh still holds all the material deeper than a
voxel (``-f >= L h``: every lattice line through such material has a node
inside it): ``V(-f >= L h) - tol <= V_mesh <= V + tol``, found as ``'thin
feature warned'`` (not a failure).  An unwarned loss is ``'thin feature
lost'`` when a lattice four times finer finds the volume, else ``'volume'``.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

#: Standard errors of the Monte-Carlo volume allowed (a false alarm once in ~1.7 million cases).
Z = 5.0
#: Monte-Carlo points per case.
MC_POINTS = 20000
#: ``features`` passed to `spatial.mesh` (None: the mesher's default); `bench/fuzz.py --features` sets it.
FEATURES = None


#: What the mesher says when it may lose a feature: a wall thinner than two voxels, a speck, sliver
#: or gap thinner than two voxels (`spatial.cells.specks`), or a part so small that no lattice node
#: falls inside it.
ANNOUNCED = ("the wall may be lost", "the feature may be lost", "no surface crosses the sampled nodes")
#: Kinds that are findings, not invalid meshes.
NOT_INVALID = ("volume", "thin feature lost", "thin feature warned")


def mesh_case(case, *, messages=None):
    """The case's mesh; the mesher's warnings appended to the list `messages` when given."""
    import spatial

    extra = {} if FEATURES is None else {"features": bool(FEATURES)}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = spatial.mesh(case.solid, voxel_size=case.voxel_size, bounds=case.bounds, progress=False, **extra)
    if messages is not None:
        messages.extend(str(w.message) for w in caught)
    return m


def mesh_failures(m, h):
    """Kinds of defect of a triangle mesh (empty list: valid)."""
    out = []
    pts = np.asarray(m.points, dtype=np.float64)
    if m.n_cells == 0:
        return out
    f = np.asarray(m.faces).reshape(-1, 4)
    if np.any(f[:, 0] != 3):
        return ["not triangles"]
    f = f[:, 1:].astype(np.int64)
    if not np.isfinite(pts).all():
        out.append("non-finite vertex")
        return out
    rep = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2])
    if rep.any():
        out.append("repeated index")
    if np.unique(np.sort(f, axis=1), axis=0).shape[0] != f.shape[0]:
        out.append("duplicate triangle")
    area2 = np.linalg.norm(np.cross(pts[f[:, 1]] - pts[f[:, 0]], pts[f[:, 2]] - pts[f[:, 0]]), axis=1)
    if np.any(area2 <= 1e-12 * h * h):
        out.append("zero-area triangle")
    n = np.int64(pts.shape[0])
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    und = np.sort(directed, axis=1)
    _, counts = np.unique(und[:, 0] * n + und[:, 1], return_counts=True)
    if np.any(counts == 1):
        out.append("open")
    if np.any(counts > 2):
        out.append("non-manifold edge")
    if np.unique(directed[:, 0] * n + directed[:, 1]).shape[0] != directed.shape[0]:
        out.append("orientation")
    if not out:
        from spatial.analysis.validity import topology

        t = topology(m)
        if t.nonmanifold_vertices:
            out.append("non-manifold vertex")
        if t.signed_volume <= 0:
            out.append("inside out")
    return out


def monte_carlo_volume(solid, bounds, seed, n=MC_POINTS):
    """``(volume, standard error)`` of `solid` inside the box `bounds` from `n` uniform points."""
    lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
    rng = np.random.default_rng(seed)
    p = lo + (hi - lo) * rng.random((n, 3))
    inside = np.count_nonzero(solid(p) < 0)
    box = float(np.prod(hi - lo))
    q = inside / n
    se = box * np.sqrt(max(q * (1 - q), 1.0 / n) / n)
    return box * q, se


def failures(case):
    """Kinds of failure of the case's mesh (empty list: valid); a crash is ``['crash: <error>']``."""
    said = []
    try:
        m = mesh_case(case, messages=said)
    except Exception as exc:  # noqa: BLE001 - every crash is a finding
        return [f"crash: {type(exc).__name__}: {str(exc)[:80]}"]
    h = float(case.voxel_size)
    out = mesh_failures(m, h)
    if out:
        return out
    if not volume_agrees(case, m, h):
        if any(w in s for s in said for w in ANNOUNCED):
            out.append("thin feature warned" if volume_agrees(case, m, h, warned=True) else "volume")
            return out
        # a feature thinner than the lattice may be lost (the mesh stays valid); it is a finding
        # of its own when a lattice four times finer finds the volume
        fine = mesh_case(replace(case, voxel_size=h / 4))
        out.append("thin feature lost" if volume_agrees(case, fine, h / 4) else "volume")
    return out


def volume_agrees(case, m, h, *, warned=False):
    """The mesh's volume agrees with the Monte-Carlo volume of the case's solid.

    `warned` (the mesher announced a wall thinner than two voxels): the mesh
    may lack that wall, not the material deeper than a voxel.
    """
    bounds = case.bounds if case.bounds is not None else case.solid.bounds
    lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
    v_mc, se = monte_carlo_volume(case.solid, bounds, case.seed) if np.all(hi > lo) else (0.0, 0.0)
    area = float(m.area) if m.n_cells else 0.0
    v = float(m.volume) if m.n_cells else 0.0
    tol = Z * se + 0.5 * h * area
    if not warned:
        return abs(v - v_mc) <= tol
    lip = max(float(case.solid.lipschitz), 1.0)
    deep = implicit_deeper(case.solid, lip * h)
    v_deep, se_deep = monte_carlo_volume(deep, bounds, case.seed) if np.all(hi > lo) else (0.0, 0.0)
    return v_deep - Z * se_deep - 0.5 * h * area <= v <= v_mc + tol


def implicit_deeper(solid, depth):
    """The material of `solid` deeper than `depth` below its surface (``f <= -depth``)."""
    import implicit

    return implicit.offset(solid, -depth)
