"""An L bracket with a fillet in its inner corner and one hole through each leg.

    implicad info examples/bracket_fillet.py
    implicad fea examples/bracket_fillet.py -o bracket.inp --size 2 --order 2 \\
        --fix hole_2.wall --load hole_1.wall=0,0,-500 --solve
"""

from implicit import box, cylinder
from implicit.families import instance

WIDTH, LEG_A, LEG_B, THICKNESS, FILLET = 30.0, 50.0, 40.0, 4.0, 5.0

bracket = instance("l_bracket", width=WIDTH, leg_a=LEG_A, leg_b=LEG_B, thickness=THICKNESS,
                   hole_diameter=6.0, holes_per_leg=1)
# The fillet: the square in the inner corner less the quarter circle of radius FILLET.
corner = box((FILLET, WIDTH, FILLET), center=(THICKNESS + FILLET / 2, WIDTH / 2, THICKNESS + FILLET / 2))
round_off = cylinder(FILLET, 2 * WIDTH, center=(THICKNESS + FILLET, WIDTH / 2, THICKNESS + FILLET), axis=(0, 1, 0))
solid = bracket | (corner - round_off)


def main():
    print(solid.tree())
    return solid


if __name__ == "__main__":
    main()
