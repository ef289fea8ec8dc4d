"""`implicad slice MODEL --layer H -o slices.json|.svg|.csv`: layers of closed contours.

Each layer is the section at its mid-height: closed loops with holes, outer
loops counter-clockwise and holes clockwise (seen from +z).  Prints the
layer count and the volume by the layers against the part's height.
"""

from __future__ import annotations

NAME = "slice"
HELP = "cut a model into layers of closed contours (JSON, SVG or CSV) for additive manufacturing"
DESCRIPTION = (
    "Slice a model into horizontal layers of height H: each layer's closed contours (outer loops "
    "counter-clockwise, holes clockwise), area, and the volume of the layers. -o writes "
    "slices.json ({\"layers\": [{\"z\", \"area\", \"loops\"}]}), slices.svg (one panel per layer) or slices.csv."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json)")
    parser.add_argument("--layer", type=float, required=True, metavar="H", help="layer height")
    parser.add_argument("--resolution", type=int, default=256, metavar="N",
                        help="samples across each section (default 256)")
    parser.add_argument("-o", "--output", metavar="FILE", help="write .json, .svg or .csv")


def run(args) -> int:
    from implicit.models import load_model
    from implicit.solid import as_positive

    from ..manufacturing import slice as slice_solid
    from ._output import check_output, write_text

    as_positive(args.layer, "--layer")
    ext = check_output(args.output, (".json", ".svg", ".csv")) if args.output else None
    solid = load_model(args.model)
    s = slice_solid(solid, args.layer, resolution=args.resolution)
    if ext:
        write_text(args.output, {".json": s.to_json, ".svg": s.to_svg, ".csv": s.to_csv}[ext]())
    holes = sum(sum(ly.holes) for ly in s.layers)
    loops = sum(len(ly.loops) for ly in s.layers)
    print(f"slices of {args.model}: {len(s.layers)} layers of {s.layer:g} from z={s.z_bottom:.6g} to {s.z_top:.6g}")
    print(f"contours: {loops} ({holes} holes)")
    print(f"volume of the layers (sum of areas x H): {s.volume:.9g}")
    if args.output:
        print(f"wrote {args.output}")
    return 0
