"""`implicad info MODEL`: what a model file holds.

Prints the CSG tree (indented), the bounds, node and primitive counts,
whether the field is an exact distance or a bound, the faces on the boundary
(the names of the FEA face sets, see ``implicad fea --fix``), and the
parameters of every family instance; ``--json`` prints the same as one JSON object.
An assembly file lists each part.
"""

from __future__ import annotations

import json
from collections import Counter

import numpy as np

NAME = "info"
HELP = "show a model's CSG tree, bounds, counts and family parameters"
DESCRIPTION = (
    "Show what a model file holds: the CSG tree, its bounds, node and primitive counts, "
    "whether the field is an exact signed distance or a conservative bound, and the "
    "parameters of family instances. MODEL is a .py file defining 'solid' or 'model()' "
    "(or 'parts'/'assembly()' for an assembly) or a .json CSG tree."
)


def add_arguments(parser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json) or closed mesh file (.stl, .ply, .obj, .vtp)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    parser.add_argument("--no-tree", action="store_true", help="leave the tree out of the text output")


def _bounds(solid):
    lo, hi = solid.bounds
    if solid.is_empty_bounds:
        return None, "empty"
    if not solid.is_bounded:
        return [[None if not np.isfinite(v) else float(v) for v in lo],
                [None if not np.isfinite(v) else float(v) for v in hi]], "unbounded"
    return [lo.tolist(), hi.tolist()], "finite"


def summary(solid) -> dict:
    """Plain-data facts about `solid` (what ``info --json`` prints for it)."""
    from implicit.families import FamilyInstance
    from implicit.serialize import to_dict

    box, state = _bounds(solid)
    kinds = Counter(node.kind for node in solid.walk())
    fams = [{"family": n.family_name, "params": n.values,
             "units": {p.name: p.unit for p in _family_params(n.family_name)}}
            for n in solid.walk() if isinstance(n, FamilyInstance)]
    leaves = [n for n in solid.walk() if not n.children]
    return {
        "kind": solid.kind,
        "nodes": solid.count_nodes(),
        "primitives": solid.count_primitives(),
        "exact_primitives": sum(1 for n in leaves if n.exact),
        "depth": solid.depth(),
        "field": "exact" if solid.exact else "bound",
        "lipschitz": solid.lipschitz,
        "bounds": box,
        "bounds_state": state,
        "kinds": dict(sorted(kinds.items())),
        "families": fams,
        "faces": _faces(solid),
        "tree": to_dict(solid),
    }


def _faces(solid):
    """The CSG faces on the boundary: the names FEA face sets get (``implicad fea --fix``)."""
    from spatial.fea.facets import face_names

    return face_names(solid)


def _family_params(name):
    from implicit.families import family
    return family(name).parameters


def _fmt_vec(v, infinite: str) -> str:
    """A corner as text; `infinite` ("-inf" or "inf") stands for None."""
    return "(" + ", ".join(infinite if x is None else f"{x:g}" for x in v) + ")"


def _text(name: str, solid, show_tree: bool) -> list[str]:
    info = summary(solid)
    lines = [f"model: {name}"]
    if show_tree:
        lines.append("tree:")
        lines.extend("  " + line for line in solid.tree().splitlines())
    field = ("exact signed distance" if info["field"] == "exact"
             else "conservative bound (|f| <= distance)")
    bound_leaves = info["primitives"] - info["exact_primitives"]
    lines.append(f"nodes: {info['nodes']}  primitives: {info['primitives']} ({info['exact_primitives']} exact, "
                 f"{bound_leaves} bound)  depth: {info['depth']}")
    lines.append("kinds: " + ", ".join(f"{k} {n}" for k, n in info["kinds"].items()))
    lines.append(f"field: {field}, Lipschitz {info['lipschitz']:g}")
    if info["bounds_state"] == "empty":
        lines.append("bounds: empty")
    else:
        lo, hi = info["bounds"]
        text = f"bounds: {_fmt_vec(lo, '-inf')} .. {_fmt_vec(hi, 'inf')}"
        if info["bounds_state"] == "finite":
            size = np.subtract(hi, lo)
            text += f"  size {size[0]:g} x {size[1]:g} x {size[2]:g}"
        else:
            text += "  (unbounded: pass --bounds x0 y0 z0 x1 y1 z1 to commands that decompose it)"
        lines.append(text)
    lines.append("faces (FEA face sets): " + (", ".join(info["faces"]) or "none"))
    for fam in info["families"]:
        lines.append(f"family: {fam['family']}")
        for key, value in fam["params"].items():
            unit = fam["units"].get(key, "")
            shown = f"{value:g}" if isinstance(value, float) else str(value)
            lines.append(f"  {key} = {shown}{' ' + unit if unit and unit != 'count' else ''}")
    return lines


def run(args) -> int:
    from implicit.models import load_any

    from .common import is_mesh_file, load_solid

    loaded = load_solid(args.model) if is_mesh_file(args.model) else load_any(args.model)
    if args.json:
        if isinstance(loaded, dict):
            out = {"model": args.model, "parts": {k: summary(v) for k, v in loaded.items()}}
        else:
            out = {"model": args.model, **summary(loaded)}
        print(json.dumps(out, indent=1, allow_nan=False))
        return 0
    if isinstance(loaded, dict):
        print(f"assembly: {args.model}  ({len(loaded)} parts)")
        for part_name, part in loaded.items():
            print()
            print("\n".join(_text(f"{args.model} [{part_name}]", part, not args.no_tree)))
    else:
        print("\n".join(_text(args.model, loaded, not args.no_tree)))
    return 0
