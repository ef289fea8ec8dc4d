"""`implicad inspect MODEL SCAN [--json] [--tolerance T]`: a produced part against its design.

The scan (STL, PLY, OBJ, VTP, VTK mesh or XYZ/TXT/CSV point cloud) is aligned
by best fit (or ``--datum`` planes, or not at all), each point's signed
deviation from the design is measured, and the statistics are printed with a
pass/fail verdict (exit status 1 on fail).  ``--picture`` and ``--histogram``
draw the colour map and the distribution.
"""

from __future__ import annotations

NAME = "inspect"
HELP = "compare a scanned part (mesh or point cloud) with its design: deviations, pass/fail, pictures"
DESCRIPTION = (
    "Align a scan (STL, PLY, OBJ, XYZ, ...) to the design by ICP (or --datum planes) and report the "
    "signed deviation of every point: max, min, mean, RMS, fraction within +/- tolerance, pass/fail "
    "(exit 1 on fail) and the 4x4 alignment transform."
)


def _datum(text):
    vals = [float(v) for v in text.replace(",", " ").split()]
    if len(vals) != 6:
        raise ValueError(f"--datum: expected 'px py pz nx ny nz', got {text!r}")
    return (tuple(vals[:3]), tuple(vals[3:]))


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json)")
    parser.add_argument("scan", metavar="SCAN", help="scan file: .stl .ply .obj .vtp .vtk .xyz .txt .csv .pts")
    parser.add_argument("--tolerance", type=float, default=0.1, metavar="T", help="band +/- T (default 0.1)")
    parser.add_argument("--align", choices=("icp", "datum", "none"), default=None,
                        help="best fit (default), datum planes (with --datum) or none")
    parser.add_argument("--datum", action="append", metavar="'PX PY PZ NX NY NZ'",
                        help="a datum plane of the design; give three: primary, secondary, tertiary")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.add_argument("--picture", metavar="PNG", help="colour map of the deviations, worst points labelled")
    parser.add_argument("--histogram", metavar="PNG", help="histogram of the deviations")


def run(args) -> int:
    from implicit.models import load_model
    from implicit.solid import as_positive

    from ..inspection import deviation_picture, histogram_picture, inspect, load_scan
    from ._output import check_output

    as_positive(args.tolerance, "--tolerance")
    datums = [_datum(t) for t in args.datum] if args.datum else None
    align = args.align or ("datum" if datums else "icp")
    if align == "datum" and (datums is None or len(datums) != 3):
        raise ValueError("--align datum: give three --datum planes")
    for p in (args.picture, args.histogram):
        if p:
            check_output(p, (".png",), "a picture")
    solid = load_model(args.model)
    points, mesh = load_scan(args.scan)
    r = inspect(solid, mesh if mesh is not None else points, tolerance=args.tolerance, align=align, datums=datums)
    if args.picture:
        deviation_picture(r, args.picture, solid=solid)
    if args.histogram:
        histogram_picture(r, args.histogram)
    if args.json:
        print(r.to_json())
    else:
        print(f"inspection of {args.scan} against {args.model}: {len(r.points)} points, {align} alignment")
        print(f"max {r.max_deviation:+.6g}  min {r.min_deviation:+.6g}  mean {r.mean_deviation:+.6g}  "
              f"RMS {r.rms_deviation:.6g}")
        print(f"within +/-{r.tolerance:g}: {100 * r.within_tolerance:.2f} %  ->  {'PASS' if r.passed else 'FAIL'}")
        print("alignment (scan -> design):")
        for row in r.transform:
            print("  " + "  ".join(f"{v: .9f}" for v in row))
        for k, w in enumerate(r.worst(), 1):
            print(f"worst {k}: {w['deviation']:+.6g} at ({', '.join(f'{c:.6g}' for c in w['point'])})")
        for p in (args.picture, args.histogram):
            if p:
                print(f"wrote {p}")
    return 0 if r.passed else 1
