"""`implicad check MODEL`: is it a valid solid?  Exit status 1 when not.

Prints finiteness, boundedness, closed / manifold / oriented boundary, the
number of bodies, genus, and the Euler-Poincare terms; a mesh file is checked
as it is.
"""

from __future__ import annotations

import json

NAME = "check"
HELP = "check that a model is a valid solid (exit 1 if not)"
DESCRIPTION = (
    "Check a model (or a mesh file) for validity: finite field, bounded, boundary closed, "
    "2-manifold and outward-oriented, no degenerate or duplicate triangles, one body (no isolated "
    "parts; any number with --assembly); report bodies, shells, genus and the "
    "Euler-Poincare law F - E + V - L = 2(B - G). Exit status 1 when the solid is not valid."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json) or mesh file (.stl, .ply, ...)")
    parser.add_argument("--resolution", type=int, default=None, metavar="N",
                        help="cells across the model for its boundary mesh (default: from its size and "
                             "thinnest wall)")
    parser.add_argument("--assembly", action="store_true",
                        help="an assembly-like solid: several bodies are valid")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args) -> int:
    from ..analysis.validity import check
    from .mass import load_target

    from implicit import Solid

    from ..meshing import mesh as _mesh
    from .common import progress_of

    target = load_target(args.model)
    progress = progress_of(args)
    report = check(target, resolution=args.resolution, assembly=args.assembly,
                   mesher=lambda solid, h: _mesh(solid, voxel_size=h, progress=progress, features=False))
    of = (f"the boundary mesh of the solid at N={args.resolution}" if isinstance(target, Solid)
          else "the mesh file's triangles")
    if args.json:
        out = report.to_dict()
        out["volume_of"] = "mesh"
        print(json.dumps(out, indent=2))
    else:
        print(f"model:     {args.model}")
        print("\n".join(line.replace("volume:    ", "mesh volume: ", 1) + (f"  ({of}; `implicad mass` gives the solid's)"
                                                                           if line.startswith("volume:") else "")
                        for line in report.summary().splitlines()))
    return 0 if report.valid else 1
