"""`implicad families`: the part families and their parameters."""

from __future__ import annotations

import json

NAME = "families"
HELP = "list the part families and their parameters"
DESCRIPTION = (
    "List the parameterised part families (primitive instancing) with their parameters: "
    "name, type, default, unit, allowed range and description. Build one in a model file "
    "with implicit.families.instance(NAME, **params)."
)


def add_arguments(parser) -> None:
    parser.add_argument("name", nargs="?", metavar="NAME", help="show only this family")
    parser.add_argument("--json", action="store_true", help="print JSON instead of text")


def run(args) -> int:
    from implicit.families import families, family

    chosen = [family(args.name)] if args.name else list(families().values())
    if args.json:
        print(json.dumps([f.describe() for f in chosen], indent=1))
        return 0
    blocks = []
    for fam in chosen:
        rows = [("parameter", "type", "default", "unit", "range", "description")]
        for p in fam.parameters:
            d = p.describe()
            default = f"{d['default']:g}" if isinstance(d["default"], float) else str(d["default"])
            rows.append((d["name"], d["type"], default, d["unit"], d["range"], d["description"]))
        widths = [max(len(r[i]) for r in rows) for i in range(5)]
        lines = [f"{fam.name}: {fam.description}"]
        for r in rows:
            lines.append("  " + "  ".join(r[i].ljust(widths[i]) for i in range(5)) + "  " + r[5])
        blocks.append("\n".join(line.rstrip() for line in lines))
    print("\n\n".join(blocks))
    return 0
