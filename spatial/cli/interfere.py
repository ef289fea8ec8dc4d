"""`implicad interfere ASSEMBLY`: every pair of parts that interfere.

Bounding boxes are swept first, so only pairs whose boxes overlap are
checked in full.  Exit status 1 when some parts interfere.
"""

from __future__ import annotations

import json

NAME = "interfere"
HELP = "find interfering and touching parts of an assembly (exit 1 if any interfere)"
DESCRIPTION = (
    "Check an assembly (.py defining 'parts' or 'assembly()', or .json {\"parts\": {...}}) for "
    "interference: the shared volume of every overlapping pair with its error estimate, pairs "
    "that only touch, and the counts of the bounding-box pre-filter. Exit status 1 when parts interfere."
)


def add_arguments(parser) -> None:
    parser.add_argument("assembly", metavar="ASSEMBLY", help="assembly file (.py or .json)")
    parser.add_argument("--resolution", type=int, default=None, metavar="N",
                        help="cells across the smaller part of each pair (default 64)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args) -> int:
    from implicit.models import load_assembly

    from ..analysis.interference import check_assembly

    from ..meshing import mesh
    from .common import progress_of

    parts = load_assembly(args.assembly)
    progress = progress_of(args)
    report = check_assembly(parts, resolution=args.resolution,
                            mesher=lambda solid, h: mesh(solid, voxel_size=h, progress=progress, features=False))
    if args.json:
        print(json.dumps(report.to_dict(), indent=2))
    else:
        print(f"assembly: {args.assembly}: {report.parts} parts, {report.pairs_possible} pairs, "
              f"{report.candidates} with overlapping boxes checked in full")
        for a, b, r in report.interfering:
            print(f"INTERFERE  {a} / {b}: shared volume {r.volume:.6g} +/- {r.volume_error:.2g}")
        for a, b, _ in report.touching:
            print(f"touch      {a} / {b}")
        for a, b, r in report.possible_contact:
            print(f"possible contact  {a} / {b}: no shared volume resolved at voxel size {r.voxel_size:.3g}; "
                  f"clearance between 0 and {r.clearance:.3g}, shared volume at most {r.volume_error:.2g}")
        if not report.interfering:
            print("no interference resolved" if report.possible_contact else "no interference")
    return 1 if report.interfering else 0
