"""`implicad fea MODEL -o part.inp --size H`: tetrahedra for analysis, decks, CalculiX runs, results.

Remeshes the model's boundary, fills it with quality tetrahedra (TetGen plus
sliver smoothing and flips), names the boundary regions by the CSG faces
that make them, checks the mesh (dihedral angles, radius-edge ratio, volume
against the solid's mass properties: a mesh that misses them is not written
and the exit status is 1 unless ``--allow-poor``), writes it, and prints a
quality table and the name every face set got in the file.

With ``--fix`` and ``--load`` the ``.inp`` is a complete linear-static deck;
``--solve`` runs CalculiX on it.  ``implicad fea --results beam.frd`` reads
CalculiX results back and can draw them (``--picture``).
"""

from __future__ import annotations

import os
import sys

NAME = "fea"
HELP = "tetrahedral mesh, linear-static deck and CalculiX run (.inp .msh .vtu .bdf .med .stl .ply; --results .frd)"
DESCRIPTION = (
    "Mesh a model into tetrahedra for finite-element analysis: the boundary is remeshed to "
    "edge length SIZE, filled with TetGen and cleared of slivers; boundary regions are named "
    "by the CSG faces that make them (see 'implicad info'). The extension of --output picks "
    "the format: .inp (Abaqus/CalculiX), .msh (Gmsh 4.1 or 2.2), .vtu, .bdf/.nas (Nastran), "
    ".med (Salome / Code_Aster: a group per face), "
    ".stl/.ply (boundary only). With --fix and --load the .inp is a ready-to-run linear-static "
    "deck (units of the built-in materials: mm, N, MPa, t/mm^3); --solve runs CalculiX (ccx). "
    "'implicad fea --results JOB.frd' reads CalculiX results."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", nargs="?", help="model file (.py or .json)")
    parser.add_argument("-o", "--output", help="output file; its extension picks the format")
    parser.add_argument("--size", type=float, help="target element edge length")
    parser.add_argument("--order", type=int, choices=(1, 2), default=1, help="1: 4-node, 2: 10-node tetrahedra")
    parser.add_argument("--min-dihedral", type=float, default=10.0, help="smallest dihedral angle, degrees (10)")
    parser.add_argument("--max-dihedral", type=float, default=165.0, help="largest dihedral angle, degrees (165)")
    parser.add_argument("--radius-edge", type=float, default=3.0, help="largest radius-edge ratio (3)")
    parser.add_argument("--allow-poor", action="store_true",
                        help="write the mesh even when it misses the asked angles, ratio or volume (warns)")
    parser.add_argument("--format-version", choices=("4.1", "2.2"), default="4.1", help="Gmsh file version")
    parser.add_argument("--material", default="steel",
                        help="steel, aluminium, titanium or E,nu[,rho] (default steel: 210000 MPa, 0.3, 7.85e-9 t/mm^3)")
    parser.add_argument("--fix", nargs="+", default=[], metavar="FACE", help="faces clamped in x, y, z")
    parser.add_argument("--load", action="append", default=[], metavar="FACE=FX,FY,FZ",
                        help="total force spread over a face (repeatable)")
    parser.add_argument("--solve", action="store_true", help="run CalculiX (ccx) on the deck")
    parser.add_argument("--results", metavar="FRD", help="read CalculiX results (.frd) instead of meshing")
    parser.add_argument("--picture", metavar="PNG", help="with --results (or --solve): draw the deformed part")
    parser.add_argument("--progress", dest="progress", action="store_true", default=None,
                        help="always show the progress bar (default: only on a terminal)")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="never show the progress bar")


def _check(args):
    from . import CommandError
    from ..fea.deck import parse_load, parse_material
    from ..fea.files import fea_format

    if args.results:
        if args.model or args.output:
            raise CommandError("--results: give only the .frd file (no MODEL, no --output)")
        if not args.results.lower().endswith(".frd"):
            raise CommandError(f"--results: expected a .frd file, got {args.results!r}")
        return None, []
    if not args.model:
        raise CommandError("MODEL: expected a model file (or --results FRD)")
    if not args.output:
        raise CommandError("--output: expected the file to write")
    ext = fea_format(args.output)  # unknown extension: one line, before any work
    if args.size is None or not args.size > 0:
        raise CommandError(f"--size: expected a positive length, got {args.size}")
    material = parse_material(args.material)
    loads = [parse_load(t) for t in args.load]
    if (args.fix or loads or args.solve) and ext != ".inp":
        raise CommandError(f"--fix/--load/--solve: a deck is an .inp file, got {args.output!r}")
    if (loads or args.solve) and not args.fix:
        raise CommandError("--fix: expected at least one clamped face for a static deck")
    if args.picture and not args.solve:
        raise CommandError("--picture: needs --solve or --results")
    return material, loads


def run(args) -> int:
    import warnings

    material, loads = _check(args)
    if args.results:
        return _show_results(args.results, args.picture)
    from implicit.models import load_model
    from . import CommandError
    from ..fea.facets import FacetField
    from ..fea.files import set_names, write_fea
    from ..fea.surface import surface_for_fea  # noqa: F401  (imported before the bar starts)
    from ..fea.tetmesh import MeshQualityError, MeshQualityWarning, tet_mesh
    from ..files.progress import progress_bar

    from ..cells.budget import check_tet_memory

    from .common import load_solid

    solid = load_solid(args.model)
    if solid.is_bounded and not solid.is_empty_bounds:
        check_tet_memory(solid.bounds, args.size)       # refuse at once what would not fit
    known = FacetField(solid).names
    for face in list(args.fix) + [f for f, _ in loads]:
        if face not in known:
            raise CommandError(f"--fix/--load: no face named {face!r}; the model's faces are {', '.join(sorted(set(known)))}")
    with progress_bar(2, "fea", progress=args.progress, unit="step") as bar:
        bar.set_description("fea: tetrahedra")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", MeshQualityWarning)
            try:
                mesh = tet_mesh(solid, size=args.size, order=args.order, min_dihedral=args.min_dihedral,
                                max_dihedral=args.max_dihedral, radius_edge=args.radius_edge,
                                allow_poor=args.allow_poor)
            except MeshQualityError as exc:
                print(f"implicad: error: {exc}; nothing written", file=sys.stderr)
                return 1
        bar.update()
        bar.set_description("fea: writing")
        if args.fix:
            from ..fea.deck import write_static_deck

            names = write_static_deck(mesh, args.output, material=material, fix=args.fix, loads=loads)
        else:
            write_fea(mesh, args.output, format_version=args.format_version, material=material)
            names = set_names(mesh, args.output)
        bar.update()
    for w in caught:
        print(f"implicad: warning: {w.message}", file=sys.stderr)
    _report(mesh, args)
    if names:
        surf = " (the *SURFACE of each is NAME_F)" if args.output.lower().endswith(".inp") else ""
        print(f"face sets in {os.path.basename(args.output)}{surf}:")
        for face, nm in names.items():
            print(f"  {face} -> {nm}  ({len(mesh.face_sets[face])} triangles, {len(mesh.node_sets[face])} nodes)")
    if args.solve:
        return _solve(args, mesh, loads)
    return 0


def _report(mesh, args):
    q = mesh.quality
    print(f"wrote {args.output}: {q.n_elements} tetrahedra (order {mesh.order}), {len(mesh.points)} nodes")
    print(q.table())
    info = mesh.info
    print(f"{'surface deviation':<19}  {mesh.surface_deviation:.3g}")
    print(f"{'volume vs solid':<19}  {100 * info['volume_error']:.3f} % (mass properties {info['volume_estimate']:.8g}"
          f" +- {100 * info.get('volume_estimate_error', 0.0):.3f} %)")
    if info.get("off_surface_nodes"):
        print(f"{'off-surface nodes':<19}  {info['off_surface_nodes']} mid-edge nodes left on their chord "
              "(on the surface they would fold an element)")
    if info.get("surface_size") and abs(info["surface_size"] - args.size) > 1e-12:
        print(f"{'surface size':<19}  {info['surface_size']:.4g} (finer than --size: the surface at --size "
              "intersected itself or missed the solid's volume)")


def _solve(args, mesh, loads) -> int:
    import numpy as np

    from ..fea.solve import calculix_path, run_calculix

    if calculix_path() is None:
        print("implicad: warning: ccx (CalculiX) is not on the PATH; the deck is written, not solved",
              file=sys.stderr)
        return 0
    grid, res = run_calculix(args.output)
    print(f"solved {res.frd}")
    print(res.summary())
    disp = np.asarray(grid.point_data["DISP"])
    for face, _ in loads:
        u = disp[np.asarray(mesh.node_sets[face])].mean(axis=0)
        print(f"mean displacement of {face}: ({u[0]:.6g}, {u[1]:.6g}, {u[2]:.6g})")
    if args.picture:
        _picture(grid, args.picture)
    return 0


def _show_results(path, picture) -> int:
    from ..fea.frd import read_frd
    from ..fea.solve import summarize

    grid = read_frd(path)
    res = summarize(grid, path)
    print(f"{path}: {res.n_nodes} nodes, {res.n_elements} elements; results: {', '.join(grid.point_data.keys())}")
    print(res.summary())
    if picture:
        _picture(grid, picture)
    return 0


def _picture(grid, path) -> None:
    from ..drafting.results import draw_results

    draw_results(grid, path)
    print(f"wrote {path}")
