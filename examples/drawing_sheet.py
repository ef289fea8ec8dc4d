"""Engineering drawings of a part and of the example assembly.

A flanged pipe (a family part) on an A3 sheet in first-angle projection with
SECTION A-A through its axis, the same part in third-angle projection as DXF,
and the exploded assembly of examples/assembly.py with balloons and a parts
list (also as CSV).

    python examples/drawing_sheet.py            # writes into ./out
    implicad draw examples/drawing_sheet.py -o pipe.pdf --section y=0 --sheet A3
"""

import os
import sys

from implicit.families import instance

solid = instance("flanged_pipe", outer_diameter=60.0, wall=5.0, length=120.0, flange_diameter=120.0,
                 flange_thickness=12.0, bolt_holes=4, hole_diameter=12.0, bolt_circle=90.0)


def main(out_dir="out", resolution=160):
    """Write the sheets into `out_dir`; returns their paths."""
    from spatial.drafting import assembly_drawing, part_drawing, write_csv, write_drawing

    os.makedirs(out_dir, exist_ok=True)
    paths = []
    # The pipe stands along z; lie it down along x so the front view shows its length.
    pipe = solid.rotate(90, axis=(0, 1, 0))
    sheet = part_drawing(pipe, name="flanged pipe DN50", section="y=0", sheet="A3", resolution=resolution,
                         material="steel")
    paths.append(write_drawing(sheet, os.path.join(out_dir, "pipe_section.svg")))
    paths.append(write_drawing(sheet, os.path.join(out_dir, "pipe_section.pdf")))
    third = part_drawing(pipe, name="flanged pipe DN50", projection="third", sheet="A3", resolution=resolution)
    paths.append(write_drawing(third, os.path.join(out_dir, "pipe_third_angle.dxf")))
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from assembly import assembly

    exploded, rows = assembly_drawing(assembly(), name="plate assembly", axis="z", resolution=max(32, resolution // 2))
    paths.append(write_drawing(exploded, os.path.join(out_dir, "assembly_exploded.png")))
    paths.append(write_csv(rows, os.path.join(out_dir, "assembly_parts.csv")))
    for p in paths:
        print(p)
    return paths


if __name__ == "__main__":
    main()
