"""`implicad toolpath MODEL --tool-radius R -o part.ngc`: 2.5D milling from +z.

Pocketing and profile passes of a flat end mill on the part's exact offsets,
as LinuxCNC G-code; ``--verify`` simulates the program by material removal
and prints the gouge, the excess and a table per operation (``--picture``
draws the tool paths, ``--removal-picture`` the deviation on the part).
A feature narrower than the tool is refused with its coordinates.
"""

from __future__ import annotations

import json

NAME = "toolpath"
HELP = "2.5D milling tool paths as G-code (pockets, profiles, lead-ins), optionally verified by material removal"
DESCRIPTION = (
    "Plan 2.5D milling of a model seen from +z with a flat end mill: pocketing by successive exact "
    "offsets, profile passes at the tool radius from the part, step-downs to every floor, climb or "
    "conventional, lead-in arcs, rapids at a safe height; write RS-274 (LinuxCNC) G-code. "
    "--verify simulates the program on the stock and reports gouge and excess volumes."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json)")
    parser.add_argument("--tool-radius", type=float, required=True, metavar="R", help="flat end mill radius")
    parser.add_argument("-o", "--output", metavar="FILE", help="G-code file (.ngc, .nc, .gcode, .tap)")
    parser.add_argument("--stepover", type=float, default=0.4, help="step-over, fraction of the diameter (<= 0.5)")
    parser.add_argument("--step-down", type=float, default=None, metavar="DZ", help="largest cut depth (default R)")
    parser.add_argument("--direction", choices=("climb", "conventional"), default="climb")
    parser.add_argument("--feed", type=float, default=600.0, help="feed per minute (default 600)")
    parser.add_argument("--spindle", type=float, default=10000.0, help="spindle speed rev/min (default 10000)")
    parser.add_argument("--units", choices=("mm", "inch"), default="mm", help="model units: G21 or G20")
    parser.add_argument("--resolution", type=int, default=128, metavar="N", help="planning grid (default 128)")
    parser.add_argument("--verify", action="store_true", help="simulate the program and compare with the design")
    parser.add_argument("--picture", metavar="PNG", help="draw the tool paths from above")
    parser.add_argument("--removal-picture", metavar="PNG", help="the part coloured by gouge / excess (with --verify)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args) -> int:
    from implicit.models import load_model
    from implicit.solid import as_positive

    from ..manufacturing import removal_picture, toolpath, toolpath_picture, verify
    from ._output import check_output, write_text

    as_positive(args.tool_radius, "--tool-radius")
    if args.output:
        check_output(args.output, (".ngc", ".nc", ".gcode", ".tap"), "a G-code")
    for p in (args.picture, args.removal_picture):
        if p:
            check_output(p, (".png",), "a picture")
    if args.removal_picture and not args.verify:
        raise ValueError("--removal-picture needs --verify")
    solid = load_model(args.model)
    tp = toolpath(solid, args.tool_radius, stepover=args.stepover, step_down=args.step_down,
                  direction=args.direction, feed=args.feed, spindle=args.spindle, units=args.units,
                  resolution=args.resolution, title=args.model)
    if args.output:
        write_text(args.output, tp.to_gcode())
    summary = {"model": args.model, "tool_radius": tp.tool_radius, "depths": tp.depths,
               "operations": [op.name for op in tp.operations], "moves": tp.move_count,
               "cutting_length": tp.cutting_length(), "safe_z": tp.safe_z,
               "stock": [list(map(float, tp.stock[0])), list(map(float, tp.stock[1]))]}
    result = None
    if args.verify:
        result = verify(solid, tp, resolution=max(64, args.resolution))
        summary["verification"] = result.to_dict()
    if args.picture:
        toolpath_picture(tp, args.picture)
    if args.removal_picture:
        removal_picture(result, solid, args.removal_picture)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(f"tool paths for {args.model}: flat end mill r={tp.tool_radius:g}, {tp.direction}, "
          f"{len(tp.depths)} depths, {len(tp.operations)} operations, {tp.move_count} moves, "
          f"cutting length {summary['cutting_length']:.6g}")
    for op in tp.operations:
        print(f"  {op.name}")
    if result is not None:
        print(result.table())
    for p in (args.output, args.picture, args.removal_picture):
        if p:
            print(f"wrote {p}")
    return 0
