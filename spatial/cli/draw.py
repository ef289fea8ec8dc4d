"""`implicad draw MODEL -o sheet.svg`: an engineering drawing of a part or an assembly."""

from __future__ import annotations

import os
import time

NAME = "draw"
HELP = "an engineering drawing: views, hidden lines, dimensions, sections, exploded assemblies (SVG/PDF/DXF/PNG)"
DESCRIPTION = (
    "Draw MODEL on an A4 or A3 sheet: front, top and side views placed by first-angle (ISO 5456-2) or "
    "third-angle (ASME Y14.3) projection and an isometric view, at one standard scale, with visible, "
    "hidden and centre lines, automatic dimensions, a title block and, with --section, SECTION A-A. "
    "An assembly file (defining `parts`) gives an isometric view with balloons and a parts list, its "
    "parts pulled apart with --explode; the parts list is also written as CSV beside the sheet. "
    "The format follows the extension of -o: .svg, .pdf, .dxf or .png. MODEL may also be a closed mesh "
    "(.stl, .ply, .obj, .vtp): its holes and sizes are measured from sections and the mesh. The title block "
    "states --units, else the units the model declares, else 'units of the model'."
)


def add_arguments(parser):
    from ..analysis.mass_core import UNITS

    parser.add_argument("model", metavar="MODEL", help="a .py model file (defining `solid`, `model()` or `parts`) or a .json CSG tree")
    parser.add_argument("-o", "--output", required=True, help="sheet to write: .svg, .pdf, .dxf or .png")
    parser.add_argument("--projection", choices=("first", "third"), default="first",
                        help="first-angle (ISO, default) or third-angle (ASME) projection")
    parser.add_argument("--section", metavar="PLANE", default=None,
                        help="cutting plane 'x=<v>', 'y=<v>' or 'z=<v>': the view along its normal becomes SECTION A-A")
    parser.add_argument("--explode", action="store_true", help="assemblies: pull the parts apart")
    parser.add_argument("--explode-axis", choices=("x", "y", "z"), default=None,
                        help="assemblies: explode along this axis (default: away from the centroid)")
    parser.add_argument("--sheet", choices=("A4", "A3"), default=None, help="sheet size (default A4 for parts, A3 for assemblies)")
    parser.add_argument("--name", default=None, help="title (default: the model file's name)")
    parser.add_argument("--material", default="steel", help="material named in the title block and parts list (default steel)")
    parser.add_argument("--density", type=float, default=None, metavar="KG_M3",
                        help="density for the parts list masses (default: the material's)")
    parser.add_argument("--resolution", type=int, default=None, metavar="N",
                        help="voxels across the longest side for the drawing mesh (default 160 for parts, 96 per assembly part)")
    parser.add_argument("--units", default=None, choices=sorted(UNITS),
                        help="length unit of the model (default: the units the model declares; "
                             "else the sheet says 'units of the model')")
    parser.add_argument("--csv", default=None, metavar="FILE", help="where to write the parts list (default: beside the sheet)")


def run(args) -> int:
    from . import CommandError
    from ..drafting.export import check_output, write_drawing

    try:
        check_output(args.output)
    except (ValueError, TypeError) as exc:
        raise CommandError(f"--output: {exc}") from None
    except FileNotFoundError:
        raise CommandError(f"--output: no such directory {os.path.dirname(os.path.abspath(args.output))}") from None
    if args.resolution is not None and not 16 <= args.resolution <= 1024:
        raise CommandError(f"--resolution: expected a whole number from 16 to 1024, got {args.resolution}")
    if args.density is not None and not args.density > 0:
        raise CommandError(f"--density: expected a positive number (kg/m^3), got {args.density}")
    if args.section is not None:
        from ..analysis import parse_plane

        try:
            parse_plane(args.section)
        except (ValueError, TypeError) as exc:
            raise CommandError(f"--section: {exc}") from None
    if args.csv is not None:
        folder = os.path.dirname(os.path.abspath(args.csv))
        if not os.path.isdir(folder):
            raise CommandError(f"--csv: no such directory {folder}")

    started = time.perf_counter()
    model, units = _load(args)
    name = args.name or os.path.splitext(os.path.basename(args.model))[0]
    if isinstance(model, dict):
        from ..drafting.assembly_sheet import assembly_drawing
        from ..drafting.parts_list import MATERIALS, write_csv

        if args.section is not None:
            raise CommandError("--section: sections are drawn for parts; this model is an assembly")
        if args.density is None and args.material not in MATERIALS:
            raise CommandError(f"--material: unknown material {args.material!r}; give --density "
                               f"or one of {', '.join(MATERIALS)}")
        drawing, rows = assembly_drawing(model, name=name, projection=args.projection, sheet=args.sheet or "A3",
                                         explode=args.explode or args.explode_axis is not None,
                                         axis=args.explode_axis, resolution=args.resolution or 96,
                                         material=args.material, density=args.density, units=units)
        write_drawing(drawing, args.output)
        csv_path = args.csv or os.path.splitext(args.output)[0] + ".csv"
        write_csv(rows, csv_path)
        print(f"{args.output}: {len(model)} parts, {len(rows)} items, scale {drawing.meta['scale']}; "
              f"parts list {csv_path}; {time.perf_counter() - started:.1f} s")
        return 0
    if args.explode or args.explode_axis:
        raise CommandError("--explode: the model is a single part; explode needs an assembly (a file defining `parts`)")
    from ..drafting.part_sheet import part_drawing

    drawing = part_drawing(model, name=name, projection=args.projection, sheet=args.sheet or "A4",
                           section=args.section, resolution=args.resolution or 160, material=args.material,
                           units=units)
    write_drawing(drawing, args.output)
    dims = sum(1 for g in drawing.walk() if g.cls == "dimension")
    print(f"{args.output}: {args.projection}-angle projection, scale {drawing.meta['scale']}, {dims} dimensions"
          f"{', section A-A' if args.section else ''}; units {drawing.meta['units']}; {time.perf_counter() - started:.1f} s")
    return 0


def _load(args):
    """The model (a solid or an assembly's parts) and its unit: ``--units``, else the declared one."""
    from .common import is_mesh_file, load_solid

    if is_mesh_file(args.model):
        return load_solid(args.model), args.units
    from implicit.models import load_any, load_model_units

    model = load_any(args.model)
    if args.units is not None or isinstance(model, dict):
        return model, args.units
    return model, load_model_units(args.model)[1]

