"""`implicad bom ASSEMBLY [-o bom.csv]`: the bill of materials of an assembly.

One row per distinct part (the same solid placed several times is counted):
item, parts, family and parameters, material and density, volume, mass,
count.  Materials come from the assembly file's ``materials`` and from
``--material part=name`` (a name of `spatial.analysis.MATERIALS` or
``name:density``).
"""

from __future__ import annotations

NAME = "bom"
HELP = "bill of materials of an assembly: items, families, materials, volumes, masses, counts (CSV, JSON)"
DESCRIPTION = (
    "List the distinct parts of an assembly (.py or .json) with their family and parameters, material, "
    "density, volume, mass and count; -o writes .csv, .json or .txt."
)


def add_arguments(parser) -> None:
    parser.add_argument("assembly", metavar="ASSEMBLY", help="assembly file (.py or .json)")
    parser.add_argument("--material", action="append", metavar="PART=MATERIAL",
                        help="material of a part: a known name (steel, aluminium, ...) or name:density (kg/m^3)")
    parser.add_argument("--default-material", metavar="MATERIAL", help="material of the parts not named")
    parser.add_argument("--units", default="mm", help="length unit of the model (default mm)")
    parser.add_argument("--tolerance", type=float, default=1e-3, help="relative volume error (default 1e-3)")
    parser.add_argument("-o", "--output", metavar="FILE", help="write .csv, .json or .txt")
    parser.add_argument("--json", action="store_true", help="print JSON")


def _material(text, what):
    if ":" in text:
        name, rho = text.rsplit(":", 1)
        try:
            return (name, float(rho))
        except ValueError:
            raise ValueError(f"{what}: expected name:density, got {text!r}") from None
    return text


def run(args) -> int:
    from implicit.models import load_assembly, load_materials

    from ..analysis.bom import bill_of_materials
    from ._output import check_output, write_text

    ext = check_output(args.output, (".csv", ".json", ".txt")) if args.output else None
    given = {}
    for item in args.material or []:
        if "=" not in item:
            raise ValueError(f"--material: expected PART=MATERIAL, got {item!r}")
        part, mat = item.split("=", 1)
        given[part] = _material(mat, "--material")
    default = _material(args.default_material, "--default-material") if args.default_material else None
    parts = load_assembly(args.assembly)
    materials = {**load_materials(args.assembly), **given}
    bom = bill_of_materials(parts, materials, default_material=default, units=args.units, tolerance=args.tolerance)
    if ext:
        write_text(args.output, {".csv": bom.to_csv, ".json": bom.to_json, ".txt": bom.table}[ext]())
    print(bom.to_json() if args.json else bom.table())
    if args.output and not args.json:
        print(f"wrote {args.output}")
    return 0
