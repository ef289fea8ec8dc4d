"""Boolean operations of a block A and a cylinder B: A | B, A & B, A - B and B - A.

Each result is meshed and its volume checked against inclusion-exclusion:
V(A | B) = V(A) + V(B) - V(A & B), V(A - B) = V(A) - V(A & B).
"""

import math

import numpy as np

from _gallery import image_axes, plt, save, shaded
from implicit import box, cylinder
from spatial import mass_properties, mesh


def main(out_dir=None, small=False):
    N = 32 if small else 96
    size = (260, 220) if small else (420, 360)
    A = box((2.0, 1.4, 1.0))
    B = cylinder(0.55, 2.0, center=(0.6, 0.0, 0.0), axis=(0.0, 1.0, 1.0))
    cases = [("A | B  (union)", A | B), ("A & B  (intersection)", A & B), ("A - B  (difference)", A - B),
             ("B - A  (difference)", B - A)]
    fig, axes = plt.subplots(1, 5, figsize=(17, 3.8))
    image_axes(axes[0], shaded({"A": mesh(A, resolution=N), "B": mesh(B, resolution=N)}, size=size),
               "block A and cylinder B")
    vols = {}
    for ax, (title, solid) in zip(axes[1:], cases):
        m = mesh(solid, resolution=N)
        vols[title[:5]] = mass_properties(m).volume
        image_axes(ax, shaded(m, size=size), f"{title}\nvolume {vols[title[:5]]:.4f}")
    # inclusion-exclusion holds to the meshing error
    va, vab = 2.0 * 1.4 * 1.0, vols["A & B"]
    assert math.isclose(vols["A | B"], va + mass_properties(mesh(B, resolution=N)).volume - vab, rel_tol=0.05)
    assert math.isclose(vols["A - B"], va - vab, rel_tol=0.05)
    fig.tight_layout()
    return save(fig, "block_cylinder_booleans", out_dir)


if __name__ == "__main__":
    print(main())
