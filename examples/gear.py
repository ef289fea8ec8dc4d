"""A spur gear: 20 involute teeth (module 2, 20 degree pressure angle), a hub and a keyed bore.

    implicad info examples/gear.py
    implicad fea examples/gear.py -o gear.inp --size 2 --fix cylinder_2.wall --load extrude_0.side=0,500,0
"""

import numpy as np

from implicit import box, cylinder, extrude, polygon

TEETH = 20
MODULE = 2.0
PRESSURE_ANGLE = np.radians(20.0)
FACE_WIDTH = 10.0
HUB_RADIUS = 12.0
HUB_LENGTH = 20.0
BORE_RADIUS = 6.0
KEY_WIDTH = 4.0
KEY_DEPTH = 2.0
POINTS_PER_FLANK = 5


def _inv(alpha):
    return np.tan(alpha) - alpha


def gear_outline(teeth=TEETH, module=MODULE, pressure_angle=PRESSURE_ANGLE, n=POINTS_PER_FLANK):
    """Vertices (counter-clockwise) of the gear's outline: involute flanks, tip and root arcs."""
    rp = module * teeth / 2.0
    rb = rp * np.cos(pressure_angle)
    ra = rp + module
    rf = rp - 1.25 * module
    r = np.linspace(max(rb, rf), ra, n)
    # Half the tooth's angular thickness at radius r (involute function).
    half = np.pi / (2 * teeth) + _inv(pressure_angle) - _inv(np.arccos(np.clip(rb / r, -1, 1)))
    pitch = 2 * np.pi / teeth
    pts = []
    for k in range(teeth):
        c = k * pitch
        rise = [(rf, c - half[0])] + list(zip(r, c - half))            # right flank, root to tip
        fall = list(zip(r[::-1], c + half[::-1])) + [(rf, c + half[0])]  # left flank, tip to root
        pts.extend(rise + fall)
    pts = np.array(pts)
    return np.column_stack([pts[:, 0] * np.cos(pts[:, 1]), pts[:, 0] * np.sin(pts[:, 1])])


def gear():
    body = extrude(polygon(gear_outline()), FACE_WIDTH, center=(0.0, 0.0, FACE_WIDTH / 2))
    hub = cylinder(HUB_RADIUS, HUB_LENGTH, center=(0.0, 0.0, HUB_LENGTH / 2))
    bore = cylinder(BORE_RADIUS, 3 * HUB_LENGTH, center=(0.0, 0.0, HUB_LENGTH / 2))
    key = box((KEY_WIDTH, 2 * KEY_DEPTH, 3 * HUB_LENGTH), center=(0.0, BORE_RADIUS, HUB_LENGTH / 2))
    return (body | hub) - bore - key


solid = gear()


def main():
    print(solid.tree())
    return solid


if __name__ == "__main__":
    main()
