"""A pin in a plate's hole: the radial clearance stacked up from three tolerances.

The hole's diameter D (a hole_plate family parameter, 8 +0.05/-0), the pin's
diameter d (7.95 +0/-0.04) and the pin's placement off the hole's axis e
(+/-0.02) give the gap (D - d) / 2 - |e|.

    implicad stackup examples/stackup.py --samples 500 --picture stackup.png
"""

from implicit import cylinder
from implicit.families import instance
from spatial.inspection import Tolerance

#: The two parts whose signed gap is stacked up.
between = ("plate", "pin")

#: Toleranced parameters (normal: the limits at +/- 3 sigma).
tolerances = {
    "D": Tolerance(8.0, 0.05, 0.0),
    "d": Tolerance(7.95, 0.0, 0.04),
    "e": Tolerance.symmetric(0.0, 0.02),
}


def parts(values):
    """The plate with one hole of diameter D at the origin and the pin through it."""
    plate = instance("hole_plate", length=30.0, width=30.0, thickness=5.0, hole_diameter=values["D"],
                     rows=1, cols=1, margin=15.0)
    pin = cylinder(values["d"] / 2, 12.0).translate((values["e"], 0.0, 0.0))
    return {"plate": plate, "pin": pin}


def main():
    from spatial.inspection import stackup

    r = stackup(parts, tolerances, between=between, samples=100, seed=0)
    print(r.table())
    return r


if __name__ == "__main__":
    main()
