"""A part from a family: an L bracket with two holes in each leg.

    implicad info examples/bracket.py
    implicad families
"""

from implicit.families import instance

solid = instance("l_bracket", width=30.0, leg_a=50.0, leg_b=40.0, thickness=4.0,
                 hole_diameter=6.0, holes_per_leg=2)


def main():
    print(solid.tree())
    return solid


if __name__ == "__main__":
    main()
