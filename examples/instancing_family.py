"""Primitive instancing: a family of parts made from a name and a few numbers.

`instancing_family.png`: ISO 4014 bolts M6 .. M24 from the standard's table
(head height and width across flats looked up by size), each with its
closed-form volume.  `part_library.png`: one instance of every family of
the library (`implicit.library`).
"""

import math

import numpy as np

from _gallery import image_axes, plt, save, shaded
from implicit.families import instance
from implicit.library import LIBRARY_FAMILIES, iso_bolt
from implicit.library.fasteners import hexagon_area
from spatial import mass_properties, mesh

SHOW = {"i_beam": {"length": 300.0}, "angle_section": {"length": 120.0},
        "tee_section": {"length": 120.0}, "channel_section": {"length": 200.0}}
#: Turns (degrees about z) that face each part's feature to the camera.
TURN = {"pipe_bend": 180.0, "keyed_shaft": 90.0}


def main(out_dir=None, small=False):
    N = 24 if small else 72
    size = (220, 200) if small else (320, 300)
    sizes = ("M6", "M10", "M16", "M24") if not small else ("M6", "M16")
    fig, axes = plt.subplots(1, len(sizes), figsize=(3.4 * len(sizes), 4.2))
    for ax, s in zip(np.atleast_1d(axes), sizes):
        bolt = iso_bolt(s, length=40)
        p = bolt.params["params"]
        exact = hexagon_area(p["across_flats"]) * p["head_height"] + math.pi * p["diameter"] ** 2 / 4 * p["length"]
        vol = mass_properties(bolt, resolution=N).volume
        assert abs(vol - exact) < 0.02 * exact
        image_axes(ax, shaded(mesh(bolt, resolution=N), size=size),
                   f"ISO 4014 {s} x 40\nk = {p['head_height']:g}, s = {p['across_flats']:g}\n"
                   f"V = {vol:.0f} mm^3 (exact {exact:.0f})")
    fig.suptitle("One family, four instances: iso4014_bolt(size, length)", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.9))
    path = save(fig, "instancing_family", out_dir)
    names = LIBRARY_FAMILIES if not small else LIBRARY_FAMILIES[:4]
    cols = 5
    rows = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.1 * rows))
    axes = np.atleast_1d(axes).ravel()
    for ax, name in zip(axes, names):
        part = instance(name, **SHOW.get(name, {})).rotate(TURN.get(name, 0.0))
        image_axes(ax, shaded(mesh(part, resolution=N), size=size), name)
    for ax in axes[len(names):]:
        ax.set_axis_off()
    fig.suptitle(f"The part library: {len(LIBRARY_FAMILIES)} families with named faces and standard sizes",
                 fontsize=11)
    fig.tight_layout()
    save(fig, "part_library", out_dir)
    return path


if __name__ == "__main__":
    print(main())
