"""Parts shared by the meshing tests (built fresh on each call: a test may not change another's)."""

import numpy as np

from implicit import box, capsule, cylinder, sphere, union


def benchmark_part():
    """The benchmark part of examples/benchmark_part.py: a drilled sphere-box, volume 0.988789504774."""
    return ((sphere(1.0) & box(1.5)) - cylinder(0.5, 4.0, axis=(1, 0, 0)) - cylinder(0.5, 4.0, axis=(0, 1, 0))
            - cylinder(0.5, 4.0, axis=(0, 0, 1)))


def holed_plate():
    """A 10 x 6 x 0.5 plate with 3 x 2 through holes of radius 0.6."""
    plate = box((10.0, 6.0, 0.5))
    for i in range(3):
        for j in range(2):
            plate = plate - cylinder(0.6, 2.0, center=(-3.0 + 3.0 * i, -1.5 + 3.0 * j, 0.0))
    return plate


def capsule_lattice(cells=4, radius=0.12):
    """Capsules along the edges of ``cells^3`` unit cells cut by the cells' box, and their count
    (3 cells: 144 capsules; 4: 300)."""
    caps = []
    ticks = np.arange(cells + 1, dtype=float)
    for axis in range(3):
        for i in ticks[:cells]:
            for j in ticks:
                for k in ticks:
                    a = np.roll(np.array([i, j, k]), axis)
                    caps.append(capsule(tuple(a), tuple(a + np.roll([1.0, 0.0, 0.0], axis)), radius))
    return union(*caps) & box((cells,) * 3, center=(cells / 2,) * 3), len(caps)
