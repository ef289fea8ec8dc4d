"""`implicad fea MODEL -o part.msh --size H`: a tetrahedral mesh for analysis.

Remeshes the model's boundary, fills it with quality tetrahedra (TetGen plus
sliver smoothing), names the boundary regions by the CSG faces that make
them, writes the mesh (the output extension picks the format) and prints a
quality table.
"""

from __future__ import annotations

import sys

NAME = "fea"
HELP = "tetrahedral mesh for finite-element analysis (.msh .inp .vtu .bdf .stl .ply)"
DESCRIPTION = (
    "Mesh a model into tetrahedra for finite-element analysis: the boundary is remeshed to "
    "edge length SIZE, filled with TetGen and cleared of slivers; boundary regions are named "
    "by the CSG faces that make them (node sets and element-side sets). The extension of "
    "--output picks the format: .msh (Gmsh 4.1 or 2.2), .inp (Abaqus/CalculiX), .vtu, "
    ".bdf/.nas (Nastran), .stl/.ply (boundary only)."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json)")
    parser.add_argument("-o", "--output", required=True, help="output file; its extension picks the format")
    parser.add_argument("--size", type=float, required=True, help="target element edge length")
    parser.add_argument("--order", type=int, choices=(1, 2), default=1, help="1: 4-node, 2: 10-node tetrahedra")
    parser.add_argument("--min-dihedral", type=float, default=10.0, help="smallest dihedral angle, degrees (10)")
    parser.add_argument("--max-dihedral", type=float, default=165.0, help="largest dihedral angle, degrees (165)")
    parser.add_argument("--radius-edge", type=float, default=1.5, help="largest radius-edge ratio asked of TetGen (1.5)")
    parser.add_argument("--format-version", choices=("4.1", "2.2"), default="4.1", help="Gmsh file version")
    parser.add_argument("--strict", action="store_true", help="fail instead of warning when a quality check fails")
    parser.add_argument("--progress", dest="progress", action="store_true", default=None,
                        help="always show the progress bar (default: only on a terminal)")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="never show the progress bar")


def run(args) -> int:
    import warnings

    from . import CommandError
    from ..fea.files import fea_format, write_fea

    fea_format(args.output)  # unknown extension: one line, before any work
    if not args.size > 0:
        raise CommandError(f"--size: expected a positive length, got {args.size:g}")
    from ..cells.budget import check_tet_memory
    from implicit.models import load_model
    from ..fea.surface import surface_for_fea
    from ..files.progress import progress_bar
    from ..fea.tetmesh import MeshQualityWarning, tet_mesh

    solid = load_model(args.model)
    if solid.is_bounded and not solid.is_empty_bounds:
        check_tet_memory(solid.bounds, args.size)       # refuse at once what would not fit
    with progress_bar(3, "fea", progress=args.progress, unit="step") as bar:
        bar.set_description("fea: surface")
        surface = surface_for_fea(solid, size=args.size)
        bar.update()
        bar.set_description("fea: tetrahedra")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", MeshQualityWarning)
            mesh = tet_mesh(solid, size=args.size, order=args.order, min_dihedral=args.min_dihedral,
                            max_dihedral=args.max_dihedral, radius_edge=args.radius_edge, surface=surface,
                            strict=args.strict)
        bar.update()
        bar.set_description("fea: writing")
        write_fea(mesh, args.output, format_version=args.format_version)
        bar.update()
    for w in caught:
        print(f"implicad: warning: {w.message}", file=sys.stderr)
    q = mesh.quality
    print(f"wrote {args.output}: {q.n_elements} tetrahedra (order {mesh.order}), {len(mesh.points)} nodes")
    print(q.table())
    print(f"{'surface deviation':<19}  {mesh.surface_deviation:.3g}")
    print(f"{'volume vs estimate':<19}  {100 * mesh.info['volume_error']:.3f} %")
    names = [k for k in mesh.face_sets if k != "surface"]
    print("boundary sets: " + ", ".join(f"{k} ({len(mesh.face_sets[k])})" for k in names))
    return 0
