"""A part for 2.5D milling (mm): a plate with a raised boss, a pocket and two through-holes.

    implicad toolpath examples/milled_plate.py --tool-radius 3 -o plate.ngc --verify \
        --picture toolpath.png --removal-picture removal.png
    implicad slice examples/milled_plate.py --layer 1 -o slices.svg
"""

from implicit import box, cylinder


def model():
    plate = box((80.0, 60.0, 10.0), center=(0.0, 0.0, 5.0))
    boss = box((40.0, 30.0, 8.0), center=(-10.0, 0.0, 14.0))
    pocket = box((16.0, 20.0, 6.0), center=(28.0, 0.0, 8.0))          # 5 mm deep from the top at z=10
    holes = cylinder(4.0, 40.0, center=(-10.0, 0.0, 0.0)) | cylinder(5.0, 40.0, center=(28.0, 20.0, 0.0))
    return (plate | boss) - pocket - holes


def main(resolution=64):
    """Plan the milling with a 3 mm end mill, verify it; the verification."""
    from spatial.manufacturing import toolpath, verify

    part = model()
    program = toolpath(part, 3.0, resolution=resolution, title="milled plate")
    result = verify(part, program, resolution=resolution)
    print(result.table())
    return result


if __name__ == "__main__":
    main()
