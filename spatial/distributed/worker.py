"""What runs on a worker: one brick of the octree, meshed, integrated or sampled.

Every function here is a pure function of its plain-data arguments (a
`BrickSpec` and a brick's integer index), importable by reference on any
worker.  The solid is rebuilt from its JSON once per worker process and kept
with its compiled evaluator (`solid_from_json`).
"""

from __future__ import annotations

import functools
import os
import resource
import time
import warnings

import numpy as np

from ..cells.lattice import CHILD_OFFSETS, Lattice
from ..meshing import mesh_cells
from ..meshing.boundary import boundary_cells_2h

__all__ = ["solid_from_json", "mesh_brick", "mesh_brick_specks", "brick_moments", "write_brick_part", "brick_band", "peak_rss",
           "mesh_brick_normals", "shared_normals", "brick_area_moments", "brick_rim", "brick_area_moments_again"]


@functools.lru_cache(maxsize=8)
def solid_from_json(text):
    """The solid of a JSON tree, rebuilt and its evaluator compiled once per process (keyed by the text)."""
    from implicit.serialize import from_json

    solid = from_json(text)
    # compiles the tape now; the cache keeps the solid, hence its compiled evaluator, alive
    solid(np.zeros((4096, 3)))
    return solid


def _lattice(spec):
    solid = solid_from_json(spec.json)
    bounds = (np.array(spec.bounds[0]), np.array(spec.bounds[1]))
    return Lattice(solid, np.array(spec.origin), spec.voxel_size, np.array(spec.shape), bounds)


def _start(spec, brick, lattice):
    """Where a brick's classification starts: its children.  A lattice of 8 voxels or fewer (depth 3 at
    most) is one brick, the root, whose children lie below the levels `boundary_cells_2h` classifies by
    bounds: it is classified whole, as one process does."""
    if spec.level == 0 and lattice.depth <= 3:
        return None
    return (spec.level + 1, (2 * brick[:, None, :] + CHILD_OFFSETS).reshape(-1, 3))


def mesh_brick(spec, brick, specks=False):
    """Mesh the boundary inside one brick.

    Parameters
    ----------
    spec : BrickSpec
    brick : (3,) int
        Index of the brick (an octree cell of level ``spec.level``).
    specks : bool
        Also return, as ``specks``, the brick's candidates for a lost feature
        (`spatial.cells.specks.speck_candidates`: ``points``, ``side``,
        ``depth``; None when the classification sampled no centres), for the
        client to measure with every brick's.

    Returns
    -------
    dict
        ``points`` (v, 3) float64, ``faces`` (f, 3) int32 (outward, indices
        into `points`), ``edges`` (v,) int64 lattice-edge id of every vertex
        (``3 * node + axis``, node ids with ``spec.stride``), ``shared`` (v,)
        bool: the vertex lies on an edge in a face of the brick (another brick
        may hold it too), ``evaluations``, ``boundary_cells``, ``blocks``,
        ``seconds`` (wall) and ``cpu_seconds`` (this process).
    """
    t0, c0 = time.perf_counter(), time.process_time()
    lattice = _lattice(spec)
    brick = np.asarray(brick, dtype=np.int32).reshape(1, 3)
    start = _start(spec, brick, lattice)
    found = boundary_cells_2h(lattice, False, start=start)
    cells = found.pop("cells")
    out = dict(points=np.empty((0, 3)), faces=np.empty((0, 3), np.int32), edges=np.empty(0, np.int64),
               shared=np.empty(0, bool), evaluations=int(found["evaluations"]), boundary_cells=int(cells.shape[0]),
               blocks=0)
    if specks:
        out["specks"] = _brick_specks(lattice, cells, found)
    if cells.shape[0]:
        with warnings.catch_warnings():
            # a brick the surface only grazes may hold no triangle: not worth a warning per brick
            warnings.simplefilter("ignore", RuntimeWarning)
            surface = mesh_cells(lattice.solid, lattice.origin, lattice.voxel_size, cells, cell_size=2,
                                 refine=spec.refine, progress=False, evaluations=found["evaluations"],
                                 block=spec.block, centre_values=found.pop("centres"),
                                 uniform_cells=found.pop("uniform"), uniform_parents=found.pop("uniform_parents"),
                                 node_values=found.pop("nodes"), stride=spec.stride, edge_ids=True)
        out["evaluations"] = int(surface.field_data["evaluations"][0])
        if surface.n_cells:
            edges = np.asarray(surface.point_data["edge_id"], dtype=np.int64)
            out.update(points=np.asarray(surface.points, dtype=np.float64),
                       faces=np.asarray(surface.regular_faces, dtype=np.int32), edges=edges,
                       shared=on_brick_faces(edges, spec), blocks=int(surface.field_data["blocks"][0]))
    out["seconds"] = time.perf_counter() - t0
    out["cpu_seconds"] = time.process_time() - c0
    return out


def _brick_specks(lattice, cells, found):
    """The brick's candidates for a lost feature (its neighbours beyond the brick are sampled)."""
    if found["centres"] is None:
        return None
    from ..cells.specks import speck_candidates

    pts, side, depth = speck_candidates(lattice.solid, lattice.origin, lattice.voxel_size, cells, found["centres"],
                                        uniform=found["uniform"], uniform_parents=found["uniform_parents"])
    return dict(points=pts, side=side, depth=depth)


def mesh_brick_specks(spec, brick):
    """`mesh_brick` with the brick's candidates for a lost feature (``specks``)."""
    return mesh_brick(spec, brick, specks=True)


def on_brick_faces(edges, spec):
    """Vertices whose lattice edge lies in a plane between bricks (the only ones two bricks can share)."""
    stride, size = np.int64(spec.stride), spec.brick_voxels
    axis = edges % 3
    node = edges // 3
    z = node % stride
    y = (node // stride) % stride
    x = node // (stride * stride)
    out = np.zeros(edges.shape[0], dtype=bool)
    for k, coord in enumerate((x, y, z)):
        out |= (axis != k) & (coord % size == 0)
    return out


def brick_moments(spec, brick, center, correct=True):
    """Raw moments (14,) of the corrected mesh inside one brick, and what it cost.

    The moments of a closed mesh are sums over its triangles (divergence
    theorem, `spatial.analysis.mass_solid.level_moments`), and every triangle
    lies in exactly one brick: the sum over the bricks is the mesh's.
    """
    from ..analysis.mass_solid import level_moments

    part = mesh_brick(spec, brick)
    vec = np.zeros(14)
    if part["faces"].shape[0]:
        vec = level_moments(solid_from_json(spec.json), part["points"], part["faces"],
                            np.asarray(center, dtype=np.float64), voxel_size=spec.voxel_size, correct=correct)
    return dict(moments=vec, triangles=int(part["faces"].shape[0]), evaluations=part["evaluations"],
                seconds=part["seconds"])


def write_brick_part(spec, brick, path):
    """Mesh one brick and write it to `path` (.vtp, with the ``edge_id`` of every vertex).

    Returns the part's figures (no arrays but its few candidates for a lost
    feature, ``specks``, as `mesh_brick` gives them): ``path`` (None when
    the brick holds no triangle), ``points``, ``triangles``, ``shared``,
    ``evaluations``, ``seconds``.
    """
    import pyvista as pv

    from ..files.atomic import atomic_write

    part = mesh_brick(spec, brick, specks=True)
    n = int(part["faces"].shape[0])
    t0, c0 = time.perf_counter(), time.process_time()
    info = dict(path=None, points=int(part["points"].shape[0]), triangles=n,
                shared=int(np.count_nonzero(part["shared"])), evaluations=part["evaluations"],
                boundary_cells=part["boundary_cells"], seconds=part["seconds"], cpu_seconds=part["cpu_seconds"],
                specks=part["specks"])
    if n:
        poly = pv.PolyData.from_regular_faces(part.pop("points"), part.pop("faces"))
        poly.point_data["edge_id"] = part.pop("edges")
        poly.point_data["shared"] = part.pop("shared").astype(np.uint8)
        atomic_write(path, lambda tmp: poly.save(tmp, binary=True), ".vtp")
        info["path"] = os.fspath(path)
    info["write_seconds"] = time.perf_counter() - t0
    info["write_cpu_seconds"] = time.process_time() - c0
    info["peak_rss"] = peak_rss()
    return info


def brick_band(spec, brick):
    """The field at every lattice node of the brick's boundary cells (the narrow band a level set keeps).

    Returns
    -------
    dict
        ``nodes`` (j, 3) int32 lattice indices, ``values`` (j,) float32,
        ``evaluations``.
    """
    lattice = _lattice(spec)
    brick = np.asarray(brick, dtype=np.int32).reshape(1, 3)
    start = _start(spec, brick, lattice)
    found = boundary_cells_2h(lattice, False, start=start)
    cells = np.asarray(found["cells"], dtype=np.int64)
    if cells.shape[0] == 0:
        return dict(nodes=np.empty((0, 3), np.int32), values=np.empty(0, np.float32),
                    evaluations=int(found["evaluations"]))
    # the cells' 27 nodes each, marked on a bitmap of the brick's nodes (no sort)
    n = spec.brick_voxels + 1
    lo = brick[0].astype(np.int64) * spec.brick_voxels
    base = ((2 * cells[:, 0] - lo[0]) * n + 2 * cells[:, 1] - lo[1]) * n + 2 * cells[:, 2] - lo[2]
    marked = np.zeros(n ** 3, dtype=bool)
    for i in range(3):
        for j in range(3):
            for k in range(3):
                marked[base + (i * n + j) * n + k] = True
    del base
    flat = np.flatnonzero(marked)
    del marked
    nodes = np.stack([flat // (n * n), (flat // n) % n, flat % n], axis=1) + lo
    del flat
    values = np.empty(nodes.shape[0], dtype=np.float32)
    chunk = 1 << 18
    for a in range(0, nodes.shape[0], chunk):
        values[a:a + chunk] = lattice.solid(lattice.origin + nodes[a:a + chunk] * lattice.voxel_size)
    return dict(nodes=nodes.astype(np.int32), values=values,
                evaluations=int(found["evaluations"]) + int(nodes.shape[0]))


def peak_rss():
    """Peak resident memory of this process, in bytes (Linux reports kilobytes)."""
    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024


def mesh_brick_normals(spec, brick):
    """`mesh_brick` plus the brick's share of the area-weighted vertex normals, ``normals`` (v, 3): the sum
    of the cross products of the brick's triangles at each vertex.  A vertex off the brick's faces has
    all its triangles in the brick; one on a face gets the rest from its neighbours (`brick_area_moments`)."""
    part = mesh_brick(spec, brick)
    pts, tri = part["points"], part["faces"].astype(np.int64)
    vn = np.zeros_like(pts)
    if tri.shape[0]:
        a = pts[tri[:, 0]]
        cross = np.cross(pts[tri[:, 1]] - a, pts[tri[:, 2]] - a)
        for q in range(3):  # the order of `spatial.analysis.mass_area.true_area`
            np.add.at(vn, tri[:, q], cross)
    part["normals"] = vn
    return part


def shared_normals(part):
    """The lattice-edge ids and partial normals of a brick's vertices on its faces (all its neighbours
    need of it)."""
    keep = part["shared"]
    return dict(edges=part["edges"][keep], normals=part["normals"][keep])


def brick_area_moments(part, spec, center, edges, normals, correct=True):
    """Raw moments (14,) of the corrected mesh of one brick (`part` from `mesh_brick_normals`), the true
    area weighed with the whole mesh's vertex normals: ``normals`` (k, 3) summed over every brick at the
    sorted lattice-edge ids ``edges`` (k,) of this brick's shared vertices."""
    from ..analysis.mass_solid import level_moments

    vec = np.zeros(14)
    if part["faces"].shape[0]:
        vn = part["normals"].copy()
        rows = np.flatnonzero(part["shared"])
        if rows.size:
            at = np.searchsorted(edges, part["edges"][rows])
            vn[rows] = normals[at]
        vec = level_moments(solid_from_json(spec.json), part["points"], part["faces"],
                            np.asarray(center, dtype=np.float64), voxel_size=spec.voxel_size, correct=correct,
                            vertex_normals=vn)
    return dict(moments=vec, triangles=int(part["faces"].shape[0]))


def brick_rim(spec, brick):
    """`shared_normals` of a brick meshed here, nothing kept (the brick is meshed again for its moments)."""
    return shared_normals(mesh_brick_normals(spec, brick))


def brick_area_moments_again(spec, brick, center, edges, normals, correct=True):
    """`brick_area_moments` of a brick meshed again (the same mesh: meshing is a pure function of the
    brick), so that no worker holds a mesh between the two rounds."""
    return brick_area_moments(mesh_brick_normals(spec, brick), spec, center, edges, normals, correct=correct)
