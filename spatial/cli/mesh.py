"""`implicad mesh MODEL -o part.stl`: a watertight boundary mesh of a model.

The output format follows the extension (STL binary, PLY, OBJ, VTP, VTK); an
unknown one is refused before any work.  A progress bar shows on a terminal;
the command ends with one summary line: triangles, vertices, watertight,
seconds and distance evaluations.  Warnings (a voxel coarser than the
thinnest wall) take one line each on stderr; an empty mesh is not written
(exit 1).
``--workers N`` (a local Dask cluster) or
``--scheduler ADDRESS`` meshes brick by brick on a cluster (the same
triangles), with Dask's progress bar; a ``.pvtp`` output is then written in
parts (one .vtp per brick, nothing gathered).
Sharp edges and corners are rebuilt (`spatial.mesh`'s feature pass) unless
``--no-features`` asks for the plain marching-cubes mesh; a ``.pvtp`` in parts
is plain (the feature pass needs the whole mesh).
"""

from __future__ import annotations

import contextlib
import sys
import time
import warnings

NAME = "mesh"
HELP = "write a watertight boundary mesh (STL, PLY, OBJ, VTP, VTK) of a model"
DESCRIPTION = (
    "Mesh a model's boundary with marching cubes over the octree's boundary cells and write it; "
    "the format follows the output's extension (.stl binary, .ply, .obj, .vtp, .vtk). "
    "Give the cell size with --voxel-size or the cells across the part with --resolution; with neither, "
    "the cell size comes from the part's size and its thinnest wall (four cells through it). "
    "With --workers N (a local Dask cluster of N processes) or --scheduler ADDRESS (a running Dask "
    "scheduler) the part is meshed brick by brick on the cluster -- the same triangles, the same default "
    "cell size -- with Dask's progress bar; a .pvtp output is then written in parts, one .vtp per brick. "
    "Sharp edges and corners are rebuilt (a vertex on every edge and corner of the CSG faces); "
    "--no-features writes the plain marching-cubes mesh (faster, edges cut by chamfers about a cell wide), "
    "as a .pvtp in parts always is."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py defining `solid`, or .json)")
    parser.add_argument("-o", "--output", required=True, metavar="FILE", help="mesh file to write")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--voxel-size", type=float, metavar="H", help="edge of the finest cells")
    size.add_argument("--resolution", type=int, metavar="N",
                      help="finest cells across the longest side (default: from the size and the thinnest wall)")
    parser.add_argument("--bounds", type=float, nargs=6, metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"),
                        help="region to mesh (needed for unbounded models)")
    parser.add_argument("--no-refine", action="store_true", help="keep interpolated vertices (no projection)")
    parser.add_argument("--features", dest="features", action="store_const", const=True, default=None,
                        help="rebuild sharp edges and corners (the default; not with a .pvtp in parts)")
    parser.add_argument("--no-features", dest="features", action="store_const", const=False,
                        help="the plain marching-cubes mesh: faster, edges and corners cut by small chamfers")
    parser.add_argument("--progress", dest="progress", action="store_const", const=True, default=None,
                        help="always show the progress bar")
    parser.add_argument("--quiet", dest="progress", action="store_const", const=False,
                        help="never show the progress bar")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="mesh brick by brick on a local Dask cluster of N worker processes")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="mesh brick by brick on the Dask cluster of this scheduler (tcp://host:port)")
    parser.add_argument("--brick", type=int, metavar="B",
                        help="voxels per side of one task's octree cell (with --workers/--scheduler; default 256)")


def _load(path):
    from .common import load_solid

    return load_solid(path)


def _cluster_options(args):
    """``client=`` / ``workers=`` / ``brick=`` of the distributed mesher, checked; None for this process."""
    if args.workers is None and args.scheduler is None:
        if args.brick is not None:
            raise ValueError("--brick: only with --workers or --scheduler")
        if args.output.lower().endswith(".pvtp"):
            raise ValueError(f"{args.output}: a .pvtp (mesh in parts) needs --workers or --scheduler")
        return None
    from ..distributed.cluster import check_client
    from ..distributed.plan import DEFAULT_BRICK, check_brick
    from ..meshing import DEFAULT_BLOCK

    client, workers = check_client(args.scheduler or "local", args.workers)
    brick = check_brick(DEFAULT_BRICK if args.brick is None else args.brick, DEFAULT_BLOCK)
    return dict(client=client, workers=workers, brick=brick)


def run(args) -> int:
    from ..meshing.boundary import mesh
    from ..files.meshes import mesh_format, save_mesh
    from ..files.surface import arrays_only

    cluster = _cluster_options(args)
    in_parts = cluster is not None and args.output.lower().endswith(".pvtp")
    if not in_parts:
        mesh_format(args.output)  # unknown extension: refused before any work
    elif args.features:
        raise ValueError(f"--features: a .pvtp in parts ({args.output}) is written brick by brick, without "
                         "the feature pass (it needs the whole mesh); give another format or --no-features")
    bounds = None
    if args.bounds is not None:
        bounds = (args.bounds[:3], args.bounds[3:])
    solid = _load(args.model)
    t0 = time.perf_counter()
    options = dict(voxel_size=args.voxel_size, resolution=args.resolution, bounds=bounds,
                   refine=not args.no_refine, progress=args.progress)
    if args.features is not None:
        options["features"] = args.features
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if cluster is None:
            # an STL is written from the arrays: pyvista and VTK are never loaded (0.3 s)
            with arrays_only() if args.output.lower().endswith(".stl") else contextlib.nullcontext():
                surface = mesh(solid, **options)
        else:
            from ..distributed import mesh as mesh_on_cluster

            surface = mesh_on_cluster(solid, **options, **cluster, parts=args.output if in_parts else None)
    for w in caught:  # one line each, without the source line Python would add
        print(f"implicad: warning: {str(w.message).splitlines()[0]}", file=sys.stderr)
    if in_parts:
        print(f"{args.output}: {surface.triangles} triangles in {len(surface.parts)} parts, "
              f"{time.perf_counter() - t0:.2f} s, {surface.evaluations} evaluations")
        return 0
    if surface.n_cells == 0:
        # nothing to write: said in one line (a mesh writer would print its own errors)
        h = float(surface.field_data["voxel_size"][0]) if "voxel_size" in surface.field_data else 0.0
        print(f"implicad: error: the mesh is empty at voxel size {h:.4g} (no boundary found); "
              "nothing written", file=sys.stderr)
        return 1
    watertight = _save_and_check(surface, args.output, save_mesh)
    seconds = time.perf_counter() - t0
    evaluations = int(surface.field_data["evaluations"][0]) if "evaluations" in surface.field_data else 0
    print(f"{args.output}: {surface.n_cells} triangles, {surface.n_points} vertices, "
          f"watertight {'yes' if watertight else 'no'}, {seconds:.2f} s, {evaluations} evaluations")
    return 0


def _save_and_check(surface, path, save_mesh) -> bool:
    """Write `surface` to `path` and tell whether it is watertight.

    For arrays (the STL path) the edge count runs on a second thread while the
    file is written: both hold the interpreter's lock only briefly (the
    records are filled by a compiled pass, the edges sorted by numpy), so the
    two overlap on two cores.  A PolyData is checked after the write (VTK's
    filters are not run beside its writer).
    """
    from ..files.surface import TriangleArrays

    if not isinstance(surface, TriangleArrays):
        save_mesh(surface, path)
        return surface.n_cells > 0 and bool(surface.is_manifold)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=1) as pool:
        check = pool.submit(lambda: surface.n_cells > 0 and bool(surface.is_manifold))
        save_mesh(surface, path)
        return check.result()
