"""A small assembly: a plate, a bolt through one of its holes and a block.

The bolt's shank (diameter 10) sits in a hole of diameter 8, so the plate and
the bolt interfere; the block stands clear of both.

    implicad interfere examples/assembly.py
    implicad bom examples/assembly.py -o bom.csv
"""

from implicit import box
from implicit.families import instance


def assembly():
    """Named parts, placed in the assembly's frame."""
    plate = instance("hole_plate", length=100.0, width=60.0, thickness=5.0, hole_diameter=8.0,
                     rows=2, cols=3, margin=12.0)
    # Over-size bolt in the hole at (-38, -18): interferes with the plate.
    bolt = instance("hex_bolt", diameter=10.0, length=20.0, head_height=5.0,
                    across_flats=16.0).translate((-38.0, -18.0, 2.5))
    block = box((20.0, 20.0, 10.0), center=(0.0, 0.0, 20.0))
    return {"plate": plate, "bolt": bolt, "block": block}


#: Part name -> material (a name known to spatial.analysis.MATERIALS, or (name, kg/m^3)).
materials = {"plate": "aluminium", "bolt": "steel", "block": ("oak", 700.0)}


def main():
    parts = assembly()
    for name, part in parts.items():
        print(name, part.bounds[0].tolist(), part.bounds[1].tolist())
    return parts


if __name__ == "__main__":
    main()
