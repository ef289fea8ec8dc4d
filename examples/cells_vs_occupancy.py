"""Cell decomposition next to spatial occupancy: the same part at z = 0.

Left: the octree's leaves cut by the plane z = 0 (FULL blue, BOUNDARY red,
EMPTY white): big cells inside, small ones only along the boundary.  Right:
the spatial-occupancy grid of the same finest cell: one voxel per cell
everywhere.  The counts and bytes of both are in the titles.
"""

import numpy as np
from matplotlib.patches import Rectangle

from _gallery import plt, save
from implicit import box, cylinder, sphere
from spatial.cells import BOUNDARY, FULL, OccupancyGrid, Octree


def main(out_dir=None, small=False):
    N = 32 if small else 64
    part = (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    tree = Octree.from_solid(part, resolution=N, progress=False)
    grid = OccupancyGrid.from_solid(part, resolution=N, progress=False)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 6))
    z = 1e-9
    cut = (tree.lo[:, 2] <= z) & (tree.lo[:, 2] + tree.size > z)
    colours = {FULL: "#4477aa", BOUNDARY: "#ee6677"}
    for lo, s, st in zip(tree.lo[cut], tree.size[cut], tree.state[cut]):
        a.add_patch(Rectangle(lo[:2], s, s, fc=colours.get(int(st), "white"), ec="0.3", lw=0.3))
    lo, hi = part.bounds
    leaves = {name: int(np.sum(tree.state == st)) for name, st in (("FULL", FULL), ("BOUNDARY", BOUNDARY))}
    a.set_title(f"cell decomposition (octree): {len(tree)} leaves in all\n{leaves['FULL']} FULL, "
                f"{leaves['BOUNDARY']} BOUNDARY; volume in [{tree.volume_bounds()[0]:.3f}, {tree.volume_bounds()[1]:.3f}]",
                fontsize=10)
    k = int(np.argmin(np.abs(grid.origin[2] + (np.arange(grid.distance.shape[2]) + 0.5) * grid.voxel_size)))
    occ = grid.occupancy[:, :, k]
    ext = (grid.origin[0], grid.origin[0] + occ.shape[0] * grid.voxel_size,
           grid.origin[1], grid.origin[1] + occ.shape[1] * grid.voxel_size)
    b.imshow(occ.T, origin="lower", extent=ext, cmap="Greys", vmin=0, vmax=1.6, interpolation="nearest")
    h = grid.voxel_size
    for x in np.arange(ext[0], ext[1] + h / 2, h):
        b.axvline(x, color="0.8", lw=0.2)
    for y in np.arange(ext[2], ext[3] + h / 2, h):
        b.axhline(y, color="0.8", lw=0.2)
    b.set_title(f"spatial occupancy: {grid.occupancy.size} voxels ({grid.occupancy.nbytes} B as bytes)\n"
                f"volume by count {grid.volume('count'):.4f}, exact 0.9888", fontsize=10)
    for ax in (a, b):
        ax.set_xlim(lo[0] - 0.1, hi[0] + 0.1)
        ax.set_ylim(lo[1] - 0.1, hi[1] + 0.1)
        ax.set_aspect("equal")
    fig.suptitle("The benchmark part at z = 0", fontsize=11)
    fig.tight_layout()
    return save(fig, "cells_vs_occupancy", out_dir)


if __name__ == "__main__":
    print(main())
