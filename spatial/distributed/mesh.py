"""Boundary meshes on a Dask cluster: one task per brick of the octree.

The client classifies the octree down to bricks (`plan`); each BOUNDARY brick
becomes a task that classifies the levels below, samples its nodes, runs
marching cubes on its blocks and refines its vertices (`worker.mesh_brick`);
the bricks' meshes are fused by lattice-edge id -- in memory, or as parts on
disk under a .pvtp index.  The mesh is the single-process one triangle for
triangle: the same cells, voxels and crossing edges; only the nodes on the
planes between bricks are evaluated once per brick.
"""

from __future__ import annotations

import os
import time
import warnings

import numpy as np

from ..cells.thickness import default_voxel_size
from ..meshing import DEFAULT_BLOCK, empty_mesh
from ..meshing.boundary import _warn_thin
from ..meshing.features import sharp_polydata
from .cluster import check_client, connect
from .parts import PartitionedMesh, merge_parts, write_pvtp
from .plan import DEFAULT_BRICK, plan_bricks
from .run import run_bricks
from .warn import user_warnings
from .worker import mesh_brick_specks, write_brick_part

__all__ = ["mesh"]


def _check_parts(parts):
    if parts is None:
        return None
    if not isinstance(parts, (str, os.PathLike)):
        raise TypeError(f"parts: expected a .pvtp file name, got {type(parts).__name__}")
    path = os.path.abspath(os.fspath(parts))
    if os.path.splitext(path)[1].lower() != ".pvtp":
        raise ValueError(f"parts: expected a .pvtp file name, got {os.fspath(parts)!r}")
    if not os.path.isdir(os.path.dirname(path)):
        raise ValueError(f"parts: the folder {os.path.dirname(path)!r} does not exist")
    return path


def _warn_specks(plan, parts, announced, name_by):
    """The single-process mesher's lost-feature warning from the bricks' candidates: measured here, all
    bricks' together, so that the budget, the thinnest feature and the count are the ones of one process
    (a cell lies in one brick: no candidate comes twice)."""
    found = [p["specks"] for p in parts if p.get("specks") is not None]
    if not found:
        return None
    from ..cells.specks import examine, warn_feature

    h = plan.spec.voxel_size
    feat = examine(plan.lattice.solid, np.concatenate([f["points"] for f in found]).reshape(-1, 3),
                   np.concatenate([f["side"] for f in found]), np.concatenate([f["depth"] for f in found]), h,
                   cells=sum(int(p["boundary_cells"]) for p in parts), name_by=name_by)
    return warn_feature(feat, h, announced)


@user_warnings
def mesh(solid, *, client=None, workers=None, voxel_size=None, resolution=None, bounds=None, refine=True,
         progress=None, block=DEFAULT_BLOCK, brick=DEFAULT_BRICK, parts=None, features=None):
    """Closed, outward-oriented boundary mesh of a solid, meshed brick by brick on a Dask cluster.

    Parameters
    ----------
    solid : Solid
    client : distributed.Client, str or None
        The cluster: a client, a scheduler address (``"tcp://host:8786"``) or
        ``"local"`` / None for a `distributed.LocalCluster` started for this
        call (`workers` processes, default 2, on 127.0.0.1).
    workers : int, optional
        Worker processes of the local cluster.
    voxel_size, resolution, bounds, refine, progress, block
        As `spatial.meshing.mesh` (with neither `voxel_size` nor
        `resolution`, the same default voxel from the part's size and
        thinnest wall); `progress` shows Dask's progress bar.
    features : bool or None
        Rebuild sharp edges and corners as `spatial.meshing.mesh` does: the
        bricks' meshes are fused on the client and the feature pass
        (`spatial.meshing.features.sharpen`) runs there over the whole mesh,
        so the result is the single-process one.  None (the default): True,
        except with `parts`, whose bricks are written unfused so that the
        feature pass, which needs the whole mesh, cannot run: the parts are
        plain marching-cubes meshes (the single-process ``features=False``
        mesh, brick by brick).  True with `parts` is refused.
    brick : int
        Voxels per side of the octree cell one task meshes (a power of two,
        a multiple of `block`); it bounds a worker's memory.
    parts : str, optional
        A .pvtp file: the bricks' meshes are written by the workers as .vtp
        parts in the folder ``<name>_parts`` beside it (a shared file system
        for a remote cluster) and a `PartitionedMesh` is returned; nothing is
        gathered.  Default: the parts are fused into one mesh in memory.

    Returns
    -------
    pyvista.PolyData or PartitionedMesh
        The mesh of `spatial.meshing.mesh` at the same lattice, triangle for
        triangle; ``field_data`` also holds ``bricks``.

    Examples
    --------
    >>> from implicit import sphere
    >>> surface = mesh(sphere(1.0), resolution=32, workers=2, brick=16)  # doctest: +SKIP
    >>> surface.is_manifold  # doctest: +SKIP
    True
    """
    t0 = time.perf_counter()
    check_client(client, workers)
    index = _check_parts(parts)
    if features is not None and not isinstance(features, (bool, np.bool_)):
        raise TypeError(f"features: expected True, False or None, got {features!r}")
    if features is None:
        features = index is None  # the feature pass needs the whole mesh: parts stay plain
    if features and index is not None:
        raise ValueError("features: the feature pass needs the whole mesh; give parts= or features=True, not both")
    if voxel_size is None and resolution is None:
        from implicit import Solid

        if not isinstance(solid, Solid):
            raise TypeError(f"solid: expected an implicit.Solid, got {type(solid).__name__}")
        # the voxel of the single-process mesher: from the part's size and its thinnest wall
        voxel_size = default_voxel_size(solid, bounds)
    plan = plan_bricks(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds, refine=refine,
                       block=block, brick=brick)
    h = plan.spec.voxel_size
    # the warnings of the single-process mesher: the thinnest wall (the tree's, else the field's), then
    # the features lost whatever their faces, from every brick's candidates
    announced = _warn_thin(plan.lattice.solid, h, plan.lattice.bounds)
    if plan.lattice.empty or plan.bricks.shape[0] == 0:
        what = "the solid is empty (its bounds enclose nothing)" if plan.lattice.empty else \
            "no boundary in the region (the solid is empty there or fills it)"
        warnings.warn(f"mesh: {what}; returning an empty mesh", RuntimeWarning, stacklevel=2)
        return empty_mesh(h if voxel_size else 0.0, plan.evaluations)
    evaluations, cells, blocks = plan.evaluations, 0, 0
    with connect(client, workers) as c:
        if index is None:
            results = [None] * plan.bricks.shape[0]
            for i, part in run_bricks(c, mesh_brick_specks, plan.spec, plan.bricks, progress=progress, name="mesh"):
                evaluations += part["evaluations"]
                cells += part["boundary_cells"]
                blocks += part["blocks"]
                results[i] = part
        else:
            folder = os.path.splitext(index)[0] + "_parts"
            os.makedirs(folder, exist_ok=True)
            paths = [(os.path.join(folder, f"part_{i:06d}.vtp"),) for i in range(plan.bricks.shape[0])]
            infos = [None] * len(paths)
            for i, info in run_bricks(c, write_brick_part, plan.spec, plan.bricks, progress=progress,
                                      extra=paths, name="mesh-part"):
                infos[i] = info
    _warn_specks(plan, results if index is None else infos, announced, solid)
    if index is not None:
        for i in infos:
            i.pop("specks", None)
        written = [i for i in infos if i["path"]]
        write_pvtp(index, [os.path.relpath(i["path"], os.path.dirname(index)) for i in written])
        return PartitionedMesh(index=index, parts=[i["path"] for i in written],
                               triangles=sum(i["triangles"] for i in infos),
                               part_points=sum(i["points"] for i in infos), voxel_size=h,
                               evaluations=plan.evaluations + sum(i["evaluations"] for i in infos),
                               seconds=time.perf_counter() - t0, bricks=infos)
    import pyvista as pv

    points, faces = merge_parts(results)
    if faces.shape[0] == 0:
        warnings.warn("mesh: no surface crosses the sampled nodes (features thinner than the voxel size?); "
                      "returning an empty mesh", RuntimeWarning, stacklevel=2)
        return empty_mesh(h, evaluations)
    if features:
        out = sharp_polydata(plan.lattice.solid, points, faces, np.asarray(plan.lattice.origin, dtype=np.float64), h)
    else:
        out = pv.PolyData.from_regular_faces(points, faces)
    out.field_data["voxel_size"] = np.array([h])
    out.field_data["evaluations"] = np.array([int(evaluations)], dtype=np.int64)
    out.field_data["boundary_cells"] = np.array([cells], dtype=np.int64)
    out.field_data["blocks"] = np.array([blocks], dtype=np.int64)
    out.field_data["bricks"] = np.array([plan.bricks.shape[0]], dtype=np.int64)
    out.field_data["seconds"] = np.array([time.perf_counter() - t0])
    return out
