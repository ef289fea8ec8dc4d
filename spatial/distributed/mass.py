"""Mass properties on a Dask cluster: per-brick partial moments, summed on the client.

The raw moments of a closed mesh (volume, first and second moments, area) and
its thin-shell correction are sums over its triangles, and every triangle
lies in exactly one brick; each task meshes its brick and returns 14 numbers.
Nothing but those numbers travels back; the client adds them exactly rounded
and the bricks' own sums are compensated (`spatial.analysis.mass_solid`'s kernels),
so volume, centroid and inertia are the single-process ones to rounding
(about 1e-15 relative, at any N).  The true area
(`spatial.analysis.mass_area`) weighs each triangle by its vertices' normals;
a vertex on a face between bricks has triangles in several bricks, so the
bricks first send the client their partial normals there, summed by
lattice-edge id and handed back (`level_moments_on`): the area is the
single-process one to rounding too.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import mass_properties as _mass_properties
from ..meshing import DEFAULT_BLOCK
from ..meshing.blocks import check_block
from .cluster import check_client, connect
from .plan import DEFAULT_BRICK, check_brick, plan_bricks
from .run import show
from .warn import user_warnings
from .worker import brick_area_moments, brick_area_moments_again, brick_rim, mesh_brick_normals, shared_normals

__all__ = ["mass_properties", "level_moments_on"]


def level_moments_on(client, *, brick=DEFAULT_BRICK, block=DEFAULT_BLOCK, progress=None, hold_meshes=True):
    """``moments(solid, h, center) -> (14,)``: the corrected mesh's raw moments at cell size ``h``, summed
    over the bricks meshed on `client`.

    Two rounds of tasks: each brick is meshed and keeps its mesh on its
    worker, sending back only the partial vertex normals of the vertices on
    its faces; the client sums those by lattice-edge id and hands every brick
    the sums at its own, and the brick integrates its triangles -- with the
    true area weighed by the whole mesh's vertex normals.  With
    ``hold_meshes=False`` no mesh is held between the rounds: each brick is
    meshed again in the second (the same mesh, for twice the meshing), so a
    worker's memory stays bounded by one brick.
    """

    def moments(solid, h, center):
        plan = plan_bricks(solid, voxel_size=h, block=block, brick=brick)
        k = plan.bricks.shape[0]
        if k == 0:
            return np.zeros(14)
        centre = tuple(float(v) for v in center)
        spec_f = client.scatter(plan.spec, broadcast=True, hash=False)
        bricks = [tuple(int(v) for v in b) for b in plan.bricks]
        meshes = [client.submit(mesh_brick_normals, spec_f, b, pure=False, key=f"moments-mesh-{i}-{spec_f.key}")
                  for i, b in enumerate(bricks)] if hold_meshes else []
        try:
            if hold_meshes:
                rims = [client.submit(shared_normals, m, pure=False, key=f"moments-rim-{i}-{spec_f.key}")
                        for i, m in enumerate(meshes)]
            else:
                rims = [client.submit(brick_rim, spec_f, b, pure=False, key=f"moments-rim-{i}-{spec_f.key}")
                        for i, b in enumerate(bricks)]
            show(rims, progress)
            rim = client.gather(rims)
            del rims
            edges = np.concatenate([r["edges"] for r in rim])
            uniq, inverse = np.unique(edges, return_inverse=True)
            sums = np.zeros((uniq.shape[0], 3))
            np.add.at(sums, inverse, np.concatenate([r["normals"] for r in rim]))  # brick order
            parts, bounds = [], np.cumsum([0] + [r["edges"].shape[0] for r in rim])
            for i in range(k):
                mine = inverse[bounds[i]:bounds[i + 1]]
                order = np.argsort(uniq[mine])
                args = (meshes[i], spec_f) if hold_meshes else (spec_f, bricks[i])
                parts.append(client.submit(brick_area_moments if hold_meshes else brick_area_moments_again, *args,
                                           centre, uniq[mine][order], sums[mine][order], pure=False,
                                           key=f"moments-area-{i}-{spec_f.key}"))
            del rim, edges, inverse, sums
            show(parts, progress)
            vecs = [out["moments"] for out in client.gather(parts)]
        finally:
            for m in meshes:
                m.release()
        # exactly rounded sums of the bricks' (each compensated): the same on every run, in any order
        stacked = np.array(vecs).reshape(-1, 14)
        return np.array([math.fsum(stacked[:, q]) for q in range(14)])

    return moments


@user_warnings
def mass_properties(solid, *, client=None, workers=None, density=1.0, units="m", tolerance=None,
                    voxel_size=None, resolution=None, brick=DEFAULT_BRICK, block=DEFAULT_BLOCK, progress=None,
                    hold_meshes=True):
    """Mass properties of a solid, its meshes integrated brick by brick on a Dask cluster.

    The same computation as `spatial.analysis.mass_properties` for a Solid
    (corrected marching cubes at ``N/4``, ``N/2``, ``N`` cells, Richardson
    extrapolation), each level's moments summed from per-brick partials.

    Parameters
    ----------
    solid : Solid
    client, workers
        See `spatial.distributed.mesh`.
    density, units, tolerance, voxel_size, resolution
        See `spatial.analysis.mass_properties`; with neither `voxel_size`
        nor `resolution` the levels are those the single-process path
        chooses (from the part's size and its thinnest wall), meshed plain
        and extrapolated (the single process rebuilds their sharp edges,
        which needs the whole mesh).
    brick, block
        See `spatial.distributed.mesh`.
    hold_meshes : bool
        Keep each brick's mesh on its worker between the two rounds of a
        level (default; Dask spills them to disk under memory pressure), or
        mesh every brick again for the second round (twice the meshing, a
        worker's memory bounded by one brick).  The same result either way.

    Returns
    -------
    MassProperties

    Examples
    --------
    >>> from implicit import sphere
    >>> props = mass_properties(sphere(1.0), resolution=32, workers=2, brick=16)  # doctest: +SKIP
    >>> round(props.volume, 2)  # doctest: +SKIP
    4.19
    """
    from implicit import Solid

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected an implicit.Solid, got {type(solid).__name__}")
    check_client(client, workers)
    check_brick(brick, check_block(block))
    if not isinstance(hold_meshes, (bool, np.bool_)):
        raise TypeError(f"hold_meshes: expected True or False, got {hold_meshes!r}")
    with connect(client, workers) as c:
        return _mass_properties(solid, density=density, units=units, tolerance=tolerance, voxel_size=voxel_size,
                                resolution=resolution,
                                moments=level_moments_on(c, brick=brick, block=block, progress=progress,
                                                         hold_meshes=bool(hold_meshes)))
