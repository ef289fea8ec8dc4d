"""The representation schemes of one part, each built by the project and measured.

Every builder returns a `Representation`: its storage (as held in memory and
in its file), the seconds to build it, its volume, the seconds for the
membership queries and the questions it answers.  `schemes(solid, ...)`
lists every scheme with whether it applies to the part and why not.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

from implicit.serialize import from_json, to_json

from ..analysis.mass import mass_properties
from ..cells import BOUNDARY, EMPTY, FULL, OccupancyGrid, Octree, import_openvdb, load_vdb, save_vdb
from ..files import save_mesh
from ..meshing import mesh as mesh_solid
from .brep import brep
from .halfspace import half_space_form

__all__ = ["Representation", "ANSWERS", "build_all", "query_points", "deep_size"]

#: The B-rep's membership queries are timed on 1 / BREP_QUERY_SHARE of the points and scaled.
BREP_QUERY_SHARE = 10

#: The questions a representation may answer.
ANSWERS = ("inside/outside", "mass properties", "rendering", "exact boundary", "tool paths")


@dataclass
class Representation:
    """One scheme measured on the part (None where a figure does not apply)."""

    name: str
    bytes: int | None = None
    file_bytes: int | None = None
    build_seconds: float | None = None
    volume: float | None = None
    volume_error: float | None = None
    query_seconds: float | None = None
    answers: list = field(default_factory=list)
    applies: bool = True
    note: str = ""
    details: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in ("name", "bytes", "file_bytes", "build_seconds", "volume",
                                             "volume_error", "query_seconds", "answers", "applies", "note")}
        out["details"] = _plain(self.details)
        return out


def _plain(x):
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return x


def deep_size(solid) -> int:
    """Bytes of a CSG tree as held: its nodes, their parameter dicts and values, and arrays."""
    seen = set()

    def size(x):
        if id(x) in seen:
            return 0
        seen.add(id(x))
        if isinstance(x, np.ndarray):
            return x.nbytes + 112
        n = sys.getsizeof(x)
        if isinstance(x, dict):
            n += sum(size(k) + size(v) for k, v in x.items())
        elif isinstance(x, (list, tuple)):
            n += sum(size(v) for v in x)
        return n

    total = 0
    for node in solid.walk():
        total += size(node) + size(node.params)
        for slot in getattr(type(node), "__slots__", ()):
            if slot.startswith("_") and slot not in ("_children", "_params", "__weakref__"):
                total += size(getattr(node, slot, None))
    return int(total)


def query_points(solid, n=100_000, seed=0) -> np.ndarray:
    """`n` points uniform in the part's bounds (seeded)."""
    lo, hi = solid.require_bounds()
    return np.random.default_rng(seed).uniform(lo, hi, size=(n, 3))


def _timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def _file_size(write, suffix):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "rep" + suffix)
        write(path)
        return os.path.getsize(path)


def _root(solid):
    """The solid under any family instance and pure transforms (the scheme's own node)."""
    node = solid
    while node.kind in ("family", "affine"):
        node = node.children[0]
    return node


# -- the schemes ---------------------------------------------------------------------

def csg(solid, pts, ctx):
    text = to_json(solid)
    _, build = _timed(from_json, text)
    solid.contains(pts)  # the first large call compiles the tree: time the second
    inside, q = _timed(solid.contains, pts)
    ctx["truth"] = inside
    leaves = sum(1 for n in solid.walk() if not n.children)
    return Representation("CSG tree", deep_size(solid), len(text.encode()), build, ctx["mass"].volume, None, q,
                          list(ANSWERS), note=f"{solid.count_nodes()} nodes, {leaves} leaves",
                          details={"nodes": solid.count_nodes(), "leaves": leaves, "depth": solid.depth()})


def half_space(solid, pts, ctx):
    form, build = _timed(half_space_form, solid)
    if form is None:
        return Representation("half-space form", applies=False,
                              note="not a Boolean of planar half-spaces (curved leaves)")
    ctx["half_space"] = form
    vol = form.volume()
    _, q = _timed(form.contains, pts)
    return Representation("half-space form", form.nbytes, len(json.dumps(form.to_dict()).encode()), build, vol,
                          None, q, list(ANSWERS), note=f"{len(form.pieces)} convex pieces, {form.n_planes} planes",
                          details={"pieces": len(form.pieces), "planes": form.n_planes})


def sweep(solid, pts, ctx):
    node = _root(solid)
    if node.kind not in ("extrude", "revolve", "sweep_curve", "helical_coil"):
        return Representation("sweep", applies=False, note="not built as a sweep")
    text = to_json(node)
    _, build = _timed(from_json, text)
    _, q = _timed(node.contains, pts)
    return Representation("sweep", deep_size(node), len(text.encode()), build, ctx["mass"].volume, None, q,
                          list(ANSWERS), note=f"{node.kind} of a profile")


def instancing(solid, pts, ctx):
    if solid.kind != "family":
        return Representation("primitive instancing", applies=False, note="not a family instance")
    from implicit.families import instance
    call = {"family": solid.params["family"], "params": solid.params["params"]}
    text = json.dumps(call)
    _, build = _timed(instance, call["family"], **call["params"])
    _, q = _timed(solid.contains, pts)
    return Representation("primitive instancing", sys.getsizeof(call["params"]) + deep_size_params(call["params"]),
                          len(text.encode()), build, ctx["mass"].volume, None, q, list(ANSWERS),
                          note=f"{call['family']} with {len(call['params'])} parameters")


def deep_size_params(params):
    return int(sum(sys.getsizeof(k) + sys.getsizeof(v) for k, v in params.items()))


def _parallelepiped(n, d, verts):
    """Corner and edge vectors of a convex piece that is a parallelepiped, else None."""
    if len(verts) != 8:
        return None
    tol = 1e-9 * max(1.0, float(np.abs(verts).max()))
    active = [i for i in range(len(d)) if np.sum(np.abs(verts @ n[i] - d[i]) < tol * 10) >= 4]
    if len(active) != 6:
        return None
    v0 = verts[np.lexsort(verts.T[::-1])[0]]
    dist = np.linalg.norm(verts - v0, axis=1)
    # the three neighbours of v0: the vertices sharing two of its three planes
    on = np.array([[abs(v @ n[i] - d[i]) < tol * 10 for i in active] for v in verts])
    here = on[np.argmin(dist)]
    nb = [j for j in range(8) if np.sum(on[j] & here) == 2]
    if len(nb) != 3:
        return None
    A = (verts[nb] - v0).T
    if abs(np.linalg.det(A)) < tol:
        return None
    return v0, A


def analytical(solid, pts, ctx):
    from parametric.volumes import BezierVolume
    node = _root(solid)
    vols = []
    if node.kind == "volume_solid":
        from implicit.parametric_solids import volume_from_dict
        vols = [volume_from_dict(node.params["volume"])]
        maps = None
    else:
        form = ctx.get("half_space")
        if form is None:
            return Representation("analytical (trivariate)", applies=False,
                                  note="no trivariate form: not a union of parallelepipeds or a B-spline volume")
        maps = []
        t0 = time.perf_counter()
        for (n, d), verts in zip(form.pieces, form.piece_vertices()):
            pp = _parallelepiped(n, d, verts)
            if pp is None:
                return Representation("analytical (trivariate)", applies=False,
                                      note="a convex piece is not a parallelepiped")
            v0, A = pp
            u = np.array([0.0, 1.0])
            grid = v0 + np.einsum("ij,abcj->abci", A, np.stack(np.meshgrid(u, u, u, indexing="ij"), -1))
            vols.append(BezierVolume(grid))
            maps.append((v0, np.linalg.inv(A)))
        build = time.perf_counter() - t0
    if maps is None:
        build = 0.0
    vol = float(sum(v.mass_properties().volume for v in vols))
    nbytes = int(sum(np.asarray(v.control_points).nbytes for v in vols))
    if maps:
        def inside(p):
            out = np.zeros(len(p), bool)
            for v0, inv in maps:
                u = (p - v0) @ inv.T
                out |= np.all((u >= 0) & (u <= 1), axis=1)
            return out
        _, q = _timed(inside, pts)
    else:
        _, q = _timed(node.contains, pts)
    return Representation("analytical (trivariate)", nbytes, nbytes, build, vol, None, q, list(ANSWERS),
                          note=f"{len(vols)} trivariate Bezier volume(s), Gauss quadrature",
                          details={"volumes": len(vols)})


def octree(solid, pts, ctx):
    N = ctx["resolution"]
    tree, build = _timed(Octree.from_solid, solid, resolution=N, progress=False)
    lo_v, hi_v = tree.volume_bounds()
    vol = mass_properties(tree, solid=solid).volume
    stats = tree.level_stats()
    # membership: paint the leaves' states into the finest lattice, then look points up
    shape = np.full(3, 2 ** tree.depth)
    origin, h = np.asarray(tree.origin), tree.voxel_size

    def lookup(p):
        ijk = np.floor((p - origin) / h).astype(np.int64)
        ok = np.all((ijk >= 0) & (ijk < shape), axis=1)
        state = np.full(len(p), EMPTY, dtype=np.int8)
        leaf_index = np.asarray(tree.index)
        size = np.rint(np.asarray(tree.size) / h).astype(np.int64)
        # sort leaves by Morton-free key: test every leaf level by level (few levels)
        for level in np.unique(tree.level):
            sel = tree.level == level
            s = int(size[sel][0])
            keys = leaf_index[sel] // s
            table = {}
            code = (keys[:, 0] * shape[1] + keys[:, 1]) * shape[2] + keys[:, 2]
            order = np.argsort(code)
            code_sorted = code[order]
            pk = ijk[ok] // s
            pc = (pk[:, 0] * shape[1] + pk[:, 1]) * shape[2] + pk[:, 2]
            pos = np.clip(np.searchsorted(code_sorted, pc), 0, len(code_sorted) - 1)
            hit = code_sorted[pos] == pc
            st = np.asarray(tree.state)[sel][order][pos]
            idx = np.flatnonzero(ok)[hit]
            state[idx] = st[hit]
            del table
        return state

    states, q = _timed(lookup, pts)
    unknown = float(np.mean(states == BOUNDARY))
    return Representation("octree cells", tree.nbytes, tree.nbytes, build, vol, None, q,
                          ["inside/outside", "mass properties", "rendering"],
                          note=f"{len(tree)} leaves; volume in [{lo_v:.6g}, {hi_v:.6g}]; "
                               f"{unknown:.1%} of queries fall in BOUNDARY cells",
                          details={"levels": stats, "volume_bounds": [lo_v, hi_v], "boundary_query_fraction": unknown})


def _grid_lookup(grid, p):
    ijk = np.floor((p - grid.origin) / grid.voxel_size).astype(np.int64)
    shape = np.array(grid.distance.shape)
    ok = np.all((ijk >= 0) & (ijk < shape), axis=1)
    out = np.zeros(len(p), bool)
    i = ijk[ok]
    out[ok] = grid.distance[i[:, 0], i[:, 1], i[:, 2]] <= 0
    return out


def occupancy(solid, pts, ctx):
    N = ctx["resolution"]
    grid, build = _timed(OccupancyGrid.from_solid, solid, resolution=N, progress=False)
    ctx["grid"] = grid
    occ = grid.occupancy
    _, q = _timed(_grid_lookup, grid, pts)
    bits = Representation("occupancy grid (bool voxels)", int(occ.nbytes), int(np.packbits(occ).nbytes), build,
                          grid.volume("count"), None, q, ["inside/outside", "mass properties", "rendering"],
                          note=f"{'x'.join(map(str, occ.shape))} voxels, one byte each (a bit in the file)")
    dist = Representation("occupancy grid (sampled distances)", int(grid.distance.nbytes), int(grid.distance.nbytes),
                          build, grid.volume("fraction"), None, q,
                          ["inside/outside", "mass properties", "rendering", "tool paths"],
                          note="float32 distances; fractional occupancy volume")
    return [bits, dist]


def boundary(solid, pts, ctx):
    N = ctx["resolution"]
    t0 = time.perf_counter()
    m = mesh_solid(solid, resolution=N, progress=False)
    rep = brep(solid, m)
    build = time.perf_counter() - t0
    ctx["mesh"], ctx["brep"] = m, rep
    vol = mass_properties(m).volume
    file_bytes = _file_size(lambda path: save_mesh(m, path), ".ply")
    import pyvista as pv
    # VTK's point-in-surface test costs ~0.1 ms a point: time a tenth of the points and scale
    probe = pv.PolyData(pts[: len(pts) // BREP_QUERY_SHARE])
    select = getattr(probe, "select_interior_points", None) or probe.select_enclosed_points
    sel, q = _timed(select, m, check_surface=False)
    q *= BREP_QUERY_SHARE
    lhs, rhs = rep.euler_poincare
    return Representation("B-rep (faces by CSG leaf)", rep.nbytes, file_bytes, build, vol, None, q,
                          ["inside/outside", "mass properties", "rendering", "exact boundary"],
                          note=f"V={rep.V} E={rep.E} F={rep.F} L={rep.L} B={rep.B} G={rep.G}: "
                               f"F-E+V-L={lhs}, 2(B-G)={rhs} {'holds' if rep.holds else 'FAILS'}; "
                               f"{m.n_cells} triangles; queries timed on a tenth of the points, scaled",
                          details=rep.to_dict())


def wireframe(solid, pts, ctx):
    rep = ctx.get("brep")
    if rep is None:
        return Representation("wireframe", applies=False, note="needs the B-rep")
    source = "edges where the CSG face changes"
    seg = rep.edge_segments
    t0 = time.perf_counter()
    np.unique(np.round(np.asarray(seg).reshape(-1, 3), 12), axis=0, return_inverse=True)
    from_brep = time.perf_counter() - t0  # the B-rep's edges as a wireframe
    t_features = 0.0
    try:  # the meshing room's sharp feature curves, where it provides them
        from ..meshing import feature_edges
        t0 = time.perf_counter()
        curves = feature_edges(mesh_solid(solid, resolution=ctx["resolution"], features=True, progress=False))
        lines = [np.stack([c[:-1], c[1:]], axis=1) for c in curves.polylines if len(c) > 1]
        if lines:
            seg = np.concatenate(lines)
            source = f"feature edges of the sharp-feature mesh: {len(curves.polylines)} curves"
            t_features = time.perf_counter() - t0
    except (ImportError, TypeError, ValueError) as exc:
        source += f" (no feature curves: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
    seg = np.asarray(seg, dtype=np.float64).reshape(-1, 2, 3)
    t0 = time.perf_counter()
    flat = seg.reshape(-1, 3)
    uniq, inv = np.unique(np.round(flat, 12), axis=0, return_inverse=True)
    lines = inv.reshape(-1, 2)
    build = time.perf_counter() - t0 + t_features
    ctx["wire"] = (uniq, lines)
    nbytes = int(uniq.nbytes + lines.nbytes)

    def write(path):
        import pyvista as pv
        cells = np.column_stack([np.full(len(lines), 2), lines]).ravel()
        pv.PolyData(uniq, lines=cells).save(path)

    return Representation("wireframe", nbytes, _file_size(write, ".vtp"), build, None, None, None,
                          ["rendering"], note=f"{len(lines)} segments ({source}); no inside/outside, no volume",
                          details={"from_brep_seconds": from_brep, "source": source})


def patches(solid, pts, ctx):
    from ..convert import fit_star_surface
    try:
        fit, build = _timed(fit_star_surface, solid, n_control=(16, 8))
    except ValueError as exc:
        return Representation("B-spline patches", applies=False, note=f"no fit: {str(exc).splitlines()[0]}")
    scale = float(np.max(np.subtract(*solid.require_bounds()[::-1])))
    if not np.isfinite(fit.max_deviation) or fit.max_deviation > 0.05 * scale:
        return Representation("B-spline patches", applies=False,
                              note=f"not star-shaped: the radial fit deviates {fit.max_deviation:.3g}")
    surf = fit.surface
    vol = _star_volume(fit.radial)
    nbytes = int(np.asarray(surf.control_points).nbytes + np.asarray(surf.knots_u).nbytes
                 + np.asarray(surf.knots_v).nbytes)
    _, q = _timed(fit.solid.contains, pts)
    return Representation("B-spline patches", nbytes, nbytes, build, vol, None, q,
                          ["inside/outside", "mass properties", "rendering", "exact boundary"],
                          note=f"closed bicubic B-spline, {np.asarray(surf.control_points).shape[0]}x"
                               f"{np.asarray(surf.control_points).shape[1]} controls, deviation {fit.max_deviation:.2g}")


def _star_volume(radial, n_theta=256, n_phi=96):
    """Volume inside ``r(theta, phi)``: the integral of r^3 / 3 sin(phi) (periodic rule in theta, Gauss in phi)."""
    x, w = np.polynomial.legendre.leggauss(n_phi)
    phi = 0.5 * np.pi * (x + 1.0)
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    r = np.asarray(radial.grid(theta / (2 * np.pi), 1.0 - phi / np.pi))[..., 0]
    return float((2 * np.pi / n_theta) * (0.5 * np.pi) * np.sum(r ** 3 / 3.0 * (np.sin(phi) * w)[None, :]))


def level_set(solid, pts, ctx):
    try:
        import_openvdb()
    except ImportError as exc:
        return Representation("OpenVDB level set", applies=False, note=str(exc).splitlines()[0])
    N = ctx["resolution"]
    lo, hi = solid.require_bounds()
    h = float(np.max(hi - lo)) / N
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "part.vdb")
        grid = ctx.get("grid")
        source = solid if grid is None else grid
        _, build = _timed(save_vdb, source, path, voxel_size=h if grid is None else None)
        file_bytes = os.path.getsize(path)
        vdb = import_openvdb()
        grids, _ = vdb.readAll(path)
        mem = int(grids[0].memUsage())
        active = int(grids[0].activeVoxelCount())
        gs = load_vdb(path)
    d = np.asarray(gs.distance, dtype=np.float64)
    vol = float(np.clip(0.5 - d / gs.voxel_size, 0.0, 1.0).sum()) * gs.voxel_size ** 3
    _, q = _timed(gs.contains, pts)
    return Representation("OpenVDB level set", mem, file_bytes, build, vol, None, q,
                          ["inside/outside", "mass properties", "rendering", "tool paths"],
                          note=f"{active} active voxels (narrow band)")


BUILDERS = (csg, half_space, sweep, instancing, analytical, octree, occupancy, boundary, wireframe, patches,
            level_set)


def build_all(solid, *, resolution=64, reference=None, n_queries=100_000, progress=None):
    """Every scheme measured on `solid`: ``(rows, reference_volume, reference_note, context)``."""
    from ..files import progress_bar
    pts = query_points(solid, n_queries)
    ctx = {"resolution": resolution}
    ctx["mass"] = mass_properties(solid, resolution=resolution)
    rows = []
    with progress_bar(len(BUILDERS), "compare", progress) as bar:
        for builder in BUILDERS:
            bar.set_description(builder.__name__)
            out = builder(solid, pts, ctx)
            rows.extend(out if isinstance(out, list) else [out])
            bar.update(1)
    if reference is not None:
        ref, why = float(reference), "given"
    elif ctx.get("half_space") is not None:
        ref, why = ctx["half_space"].volume(), "half-space form (exact)"
    else:
        fine = mass_properties(solid, resolution=2 * resolution)
        ref, why = fine.volume, f"extrapolated mesh integral at N={2 * resolution} (estimated error {fine.error.volume:.2g})"
    for r in rows:
        if r.volume is not None and ref:
            r.volume_error = abs(r.volume - ref) / abs(ref)
    return rows, ref, why, ctx
