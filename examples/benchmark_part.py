"""The benchmark part: a sphere-box intersection drilled through along x, y and z.

Volume 0.988789504774, genus 5 (Euler characteristic -8).

    implicad info examples/benchmark_part.py
"""

from implicit import box, cylinder, sphere


def model():
    """The benchmark part as a CSG tree."""
    body = sphere(1.0) & box(1.5)
    drills = [cylinder(0.5, 4.0, axis=axis) for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    return body - drills[0] - drills[1] - drills[2]


def main():
    part = model()
    print(part.tree())
    print(f"nodes {part.count_nodes()}, primitives {part.count_primitives()}")
    return part


if __name__ == "__main__":
    main()
