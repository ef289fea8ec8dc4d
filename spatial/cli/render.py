"""`implicad render`: a picture of a part or an assembly."""

from __future__ import annotations

import os
import time

from ..drafting.render import STYLES, VIEWS

NAME = "render"
HELP = "draw a part or an assembly to a PNG picture"
DESCRIPTION = (
    "Mesh MODEL and draw it off-screen: shaded, wire-frame, triangles or hidden-line, from one view "
    "or as a four-view drawing sheet. An assembly file (defining `parts`) draws every part in its "
    "own colour, pulled apart with --explode."
)


def add_arguments(parser):
    parser.add_argument("model", metavar="MODEL", help="a .py model file (defining `solid`, `model()` or `parts`) or a .json CSG tree")
    parser.add_argument("-o", "--output", required=True, help="picture to write (.png)")
    parser.add_argument("--style", choices=STYLES, default="shaded", help="drawing style (default: shaded)")
    parser.add_argument("--view", choices=sorted(VIEWS), default="iso", help="camera direction (default: iso)")
    parser.add_argument("--views", action="store_true",
                        help="four pictures: front, top and side views placed by --projection, and iso "
                             "(for a dimensioned drawing see `implicad draw`)")
    parser.add_argument("--projection", choices=("first", "third"), default="first",
                        help="placement of --views: first angle (ISO, default) or third angle (ASME)")
    parser.add_argument("--cells", action="store_true",
                        help="draw the octree cells coloured by class (FULL, BOUNDARY) instead of the surface")
    parser.add_argument("--resolution", type=int, default=96, help="cells across the longest side for meshing (default: 96)")
    parser.add_argument("--explode", type=float, default=None, metavar="F",
                        help="for assemblies: pull parts apart by F times the assembly radius")
    parser.add_argument("--size", type=int, nargs=2, default=(900, 700), metavar=("W", "H"), help="picture size in pixels")


def run(args) -> int:
    from . import CommandError
    from ..drafting.render import exploded_view, render, render_views

    if not args.output.lower().endswith(".png"):
        raise CommandError(f"--output: pictures are written as PNG, expected a name ending in .png, got {args.output!r}")
    if not 8 <= args.resolution <= 1024:
        raise CommandError(f"--resolution: expected a whole number from 8 to 1024, got {args.resolution}")
    if args.explode is not None and args.explode < 0:
        raise CommandError(f"--explode: expected a non-negative number, got {args.explode}")
    folder = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(folder):
        raise CommandError(f"--output: no such directory {folder}")

    from implicit.models import load_assembly, load_model

    from ..drafting.part_views import part_mesh

    started = time.perf_counter()
    parts = _load_parts(args.model, load_model, load_assembly)
    if args.cells:
        from implicit import union

        from ..cells import Octree
        from ..drafting.render import render_cells

        solid = next(iter(parts.values())) if len(parts) == 1 else union(*parts.values())
        tree = Octree.from_solid(solid, resolution=args.resolution, progress=False)
        render_cells(tree, args.output, window_size=args.size)
        print(f"{args.output}: {len(tree)} octree leaves, {time.perf_counter() - started:.2f} s")
        return 0
    # The drawing mesh: its lattice is shifted off the round numbers faces sit on.
    meshes = {name: part_mesh(solid, resolution=args.resolution) for name, solid in parts.items()}
    if args.explode is not None and len(meshes) > 1:
        exploded_view(meshes, args.output, factor=args.explode, style=args.style, window_size=args.size)
    elif args.views:
        render_views(meshes if len(meshes) > 1 else next(iter(meshes.values())), args.output,
                     style=args.style, window_size=args.size, projection=args.projection, solid=parts)
    else:
        render(meshes if len(meshes) > 1 else next(iter(meshes.values())), args.output,
               style=args.style, view=args.view, window_size=args.size, solid=parts)
    triangles = sum(m.n_cells for m in meshes.values())
    print(f"{args.output}: {len(meshes)} part(s), {triangles} triangles, {time.perf_counter() - started:.2f} s")
    return 0


def _load_parts(path, load_model, load_assembly):
    """Named solids of an assembly file, or the single solid of a part (or mesh) file."""
    from .common import is_mesh_file, load_solid

    if is_mesh_file(path):
        return {"part": load_solid(path)}
    try:
        return dict(load_assembly(path))
    except (ValueError, TypeError):
        return {"part": load_model(path)}
