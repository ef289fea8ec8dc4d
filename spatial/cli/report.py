"""`implicad report MODEL -o out/`: the full report of a part.

Writes the mesh, mass properties with bounds, validity and topology, a
section, the drawing sheet, a shaded view and the representation comparison
as ``report.md`` (pictures beside it), ``report.html`` (one self-contained
page) and ``report.json``; a progress bar over the stages on a terminal.
"""

from __future__ import annotations

import json
import os

NAME = "report"
HELP = "write the full report of a model (Markdown, HTML, JSON and pictures)"
DESCRIPTION = ("Mesh, measure, check, section, draw and compare MODEL, and write report.md, report.html "
               "(self-contained) and report.json with the pictures into the output folder.")


def add_arguments(parser) -> None:
    from ..analysis.mass import UNITS

    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json) or closed mesh file")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="folder to write the report into")
    parser.add_argument("--resolution", type=int, default=96, metavar="N", help="cells across the part (default 96)")
    parser.add_argument("--compare-resolution", type=int, default=48, metavar="N",
                        help="cells across the part for the representation comparison (default 48)")
    parser.add_argument("--density", type=float, default=1.0, help="density in kg/m^3 (default 1)")
    parser.add_argument("--units", default=None, choices=sorted(UNITS), help="length unit (default: as declared)")
    parser.add_argument("--reference", type=float, default=None, metavar="V", help="the exact volume, when known")
    parser.add_argument("--json", action="store_true", help="print the written files as one JSON object")


def run(args) -> int:
    from . import CommandError
    from ..compare.report import report
    from .common import load_model_and_units, progress_of

    if os.path.exists(args.output) and not os.path.isdir(args.output):
        raise CommandError(f"--output: {args.output} exists and is not a folder")
    if not 8 <= args.resolution <= 1024:
        raise CommandError(f"--resolution: expected a whole number from 8 to 1024, got {args.resolution}")
    solid, declared = load_model_and_units(args.model)
    units = args.units or declared
    name = os.path.splitext(os.path.basename(args.model))[0]
    paths = report(solid, args.output, name=name, resolution=args.resolution,
                   compare_resolution=args.compare_resolution, density=args.density, units=units,
                   units_assumed=units is None, reference=args.reference, progress=progress_of(args))
    if args.json:
        print(json.dumps({"report": paths}, indent=1))
    else:
        if units is None:
            print("units: m assumed (the model declares none)")
        print(f"report: {paths['markdown']}")
        print(f"        {paths['html']} (self-contained), {paths['json']}")
    return 0
