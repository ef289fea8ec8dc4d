"""`implicad section MODEL --plane z=0.5`: a planar cross-section.

Prints the section's area, centroid and second moments of area; ``-o``
writes a picture (``.png``, ``.pdf``) or the polylines (``.svg``, ``.json``)
by the file's extension, ``--svg`` / ``--json`` write those formats to a
given file.  Every file is written to a temporary name and renamed.
"""

from __future__ import annotations

import json
import os

NAME = "section"
HELP = "cut a model by a plane: loops, holes, area and second moments; plot or polylines"
DESCRIPTION = (
    "Cut a model by a plane ('x=..', 'y=..', 'z=..' or --point/--normal), print the section's area, "
    "centroid and second moments of area, and write a picture (-o section.png) or the closed "
    "polylines (--svg FILE, --json FILE; '-' prints JSON)."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json)")
    parser.add_argument("--plane", default=None, help="plane 'x=<v>', 'y=<v>' or 'z=<v>' (default z=0)")
    parser.add_argument("--point", type=float, nargs=3, metavar=("X", "Y", "Z"), help="point on the plane")
    parser.add_argument("--normal", type=float, nargs=3, metavar=("NX", "NY", "NZ"), help="normal of the plane")
    parser.add_argument("--resolution", type=int, default=256, metavar="N",
                        help="samples across the section (default 256)")
    parser.add_argument("-o", "--output", metavar="FILE", help="write .png/.pdf picture, or .svg/.json polylines")
    parser.add_argument("--svg", metavar="FILE", help="write the polylines as SVG")
    parser.add_argument("--json", metavar="FILE", nargs="?", const="-",
                        help="write the section as JSON (to stdout without FILE)")


def _plane(args):
    if args.point is not None or args.normal is not None:
        if args.plane is not None:
            raise ValueError("give either --plane or --point/--normal, not both")
        if args.point is None or args.normal is None:
            raise ValueError("--point and --normal go together")
        return (tuple(args.point), tuple(args.normal))
    return args.plane or "z=0"


def _atomic(path, write, binary=False):
    """Write through `write(handle)` to a temporary file, then rename it."""
    from ..files.atomic import atomic_write as _atomic_write

    def write_file(tmp):
        with open(tmp, "wb" if binary else "w") as fh:
            write(fh)

    _atomic_write(path, write_file)


def svg_text(sec, *, width_px: float = 800.0) -> str:
    """The section's loops as one SVG path (even-odd fill: holes stay empty)."""
    import numpy as np

    if not sec.loops:
        return '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"/>\n'
    pts = np.concatenate(sec.loops)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(max(hi - lo)) or 1.0
    scale = width_px / span
    pad = 0.05 * span
    w, h = (hi - lo + 2 * pad) * scale
    parts = []
    for lp in sec.loops:
        xy = (lp - lo + pad) * scale
        xy[:, 1] = h - xy[:, 1]                 # SVG's y axis points down
        parts.append("M " + " L ".join(f"{x:.4f},{y:.4f}" for x, y in xy) + " Z")
    d = " ".join(parts)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.1f}" height="{h:.1f}" '
            f'viewBox="0 0 {w:.4f} {h:.4f}">\n'
            f'  <!-- section area {sec.area:.9g}; plane point {sec.point.tolist()} normal {sec.normal.tolist()};'
            f' 1 model unit = {scale:.6g} px -->\n'
            f'  <path d="{d}" fill="#9ab" fill-rule="evenodd" stroke="#123" stroke-width="1"/>\n</svg>\n')


def plot(sec, path, title=""):
    """Draw the section (material filled, holes empty) to a picture file."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    fig, ax = plt.subplots(figsize=(6, 6), dpi=120)
    try:
        if sec.loops:
            verts = np.concatenate([np.vstack([lp, lp[:1]]) for lp in sec.loops])
            codes = np.concatenate([[Path.MOVETO] + [Path.LINETO] * (len(lp) - 1) + [Path.CLOSEPOLY]
                                    for lp in sec.loops])
            ax.add_patch(PathPatch(Path(verts, codes), facecolor="#9ab", edgecolor="#123", lw=1.2))
            for lp, hole in zip(sec.loops, sec.holes):
                ax.plot(*np.vstack([lp, lp[:1]]).T, color="#c33" if hole else "#123", lw=1.2)
            ax.plot(*sec.centroid, "k+", ms=12)
            lo, hi = verts.min(axis=0), verts.max(axis=0)
            pad = 0.05 * float(max(hi - lo))
            ax.set_xlim(lo[0] - pad, hi[0] + pad)
            ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_aspect("equal")
        e1, e2 = sec.frame[0], sec.frame[1]
        ax.set_xlabel(f"u along ({e1[0]:g}, {e1[1]:g}, {e1[2]:g})")
        ax.set_ylabel(f"v along ({e2[0]:g}, {e2[1]:g}, {e2[2]:g})")
        ax.set_title(f"{title}\narea {sec.area:.6g}, {len(sec.loops)} loops "
                     f"({sum(sec.holes)} holes), + centroid", fontsize=10)
        ax.grid(True, lw=0.3)
        fmt = os.path.splitext(os.fspath(path))[1].lstrip(".").lower() or "png"
        _atomic(path, lambda fh: fig.savefig(fh, format=fmt), binary=True)
    finally:
        plt.close(fig)


def run(args) -> int:
    from implicit.models import load_model

    from ..analysis.section import parse_plane, section

    plane = _plane(args)
    parse_plane(plane)                      # bad planes fail before any work
    outputs = [p for p in (args.output, args.svg, args.json if args.json not in (None, "-") else None) if p]
    for p in outputs:
        folder = os.path.dirname(os.path.abspath(p))
        if not os.path.isdir(folder):
            raise FileNotFoundError(2, "No such directory", folder)
    if args.output:
        ext = os.path.splitext(args.output)[1].lower()
        if ext not in (".png", ".pdf", ".svg", ".json"):
            raise ValueError(f"{args.output}: expected a .png, .pdf, .svg or .json file name")
    from .common import load_solid

    solid = load_solid(args.model)
    sec = section(solid, plane, resolution=args.resolution)
    label = f"point {tuple(args.point)} normal {tuple(args.normal)}" if args.point else (args.plane or "z=0")
    if sec.is_empty:
        from . import NoResult

        raise NoResult(f"the plane {label} misses {args.model}: no material in the section "
                       "(nothing written)")
    if args.output:
        ext = os.path.splitext(args.output)[1].lower()
        if ext == ".svg":
            _atomic(args.output, lambda fh: fh.write(svg_text(sec)))
        elif ext == ".json":
            _atomic(args.output, lambda fh: json.dump(sec.to_dict(), fh))
        else:
            plot(sec, args.output, title=f"{os.path.basename(args.model)}: {label}")
    if args.svg:
        _atomic(args.svg, lambda fh: fh.write(svg_text(sec)))
    if args.json and args.json != "-":
        _atomic(args.json, lambda fh: json.dump(sec.to_dict(), fh))
    if args.json == "-":
        print(json.dumps(sec.to_dict()))
        return 0
    print(f"section of {args.model} by {label}")
    print(f"loops:     {len(sec.loops)} ({sum(sec.holes)} holes)")
    print(f"area:      {sec.area:.9g}")
    print(f"centroid:  ({', '.join(f'{c:.9g}' for c in sec.centroid3d)})")
    print(f"Ixx, Iyy, Ixy (centroid, in-plane axes): {sec.Ixx:.9g}, {sec.Iyy:.9g}, {sec.Ixy:.9g}")
    print(f"polar:     {sec.polar:.9g}")
    for p in outputs:
        print(f"wrote {p}")
    return 0
