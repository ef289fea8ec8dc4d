"""Parts shared by the meshing tests (built fresh on each call: a test may not change another's)."""

from implicit import box, cylinder, sphere


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
