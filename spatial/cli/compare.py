"""`implicad compare MODEL`: every representation scheme of one part, measured.

Prints the Markdown table (storage in memory and in its file, build seconds,
volume and its error against the best reference, seconds for the point
queries, the questions each answers) and the seed's claims checked with
figures; ``--json`` prints ``{"representations": [...], ...}``; ``--chart``
writes the bar chart (storage and error, log scales).
"""

from __future__ import annotations

import json

NAME = "compare"
HELP = "compare every representation scheme of a model: storage, build time, volume error, queries"
DESCRIPTION = ("Build every representation scheme that applies to MODEL (CSG tree, half-space form, sweep, "
               "primitive instance, analytical volume, octree cells, occupancy grids, B-rep, wireframe, B-spline "
               "patches, OpenVDB level set) and measure each on the same part.")


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json) or closed mesh file")
    parser.add_argument("--resolution", type=int, default=64, metavar="N",
                        help="cells across the part for cells, grids, meshes and level sets (default 64)")
    parser.add_argument("--queries", type=int, default=100_000, metavar="Q",
                        help="point-membership queries timed per representation (default 100000)")
    parser.add_argument("--reference", type=float, default=None, metavar="V", help="the exact volume, when known")
    parser.add_argument("--chart", metavar="PNG", help="write the bar chart of storage and error")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args) -> int:
    from . import CommandError
    from ..compare import compare
    from .common import load_solid, progress_of

    if args.chart and not args.chart.lower().endswith(".png"):
        raise CommandError(f"--chart: expected a .png file name, got {args.chart!r}")
    solid = load_solid(args.model)
    table = compare(solid, resolution=args.resolution, reference=args.reference, n_queries=args.queries,
                    progress=progress_of(args))
    if args.chart:
        table.chart(args.chart)
    if args.json:
        print(json.dumps(table.to_dict(), indent=1, allow_nan=False))
    else:
        print(table.markdown())
    return 0
