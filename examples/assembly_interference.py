"""An assembly with interference, and its exploded view.

The example assembly (a plate, an over-size bolt in one of its holes and a
block) is checked pair by pair: the bolt and the plate share volume (in red,
the overlap), the block stands clear.  Right: the parts pulled apart.
"""

import os
import sys

import numpy as np

from _gallery import image_axes, plt, pv_picture, save
from spatial import mesh
from spatial.analysis import check_assembly
from spatial.drafting import exploded_view

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from assembly import assembly  # noqa: E402


def main(out_dir=None, small=False):
    N = 32 if small else 96
    size = (300, 240) if small else (560, 440)
    parts = assembly()
    report = check_assembly(parts, resolution=N)
    meshes = {name: mesh(p, resolution=N) for name, p in parts.items()}
    colours = {"plate": "#bbbbbb", "bolt": "#4477aa", "block": "#228833"}
    items = [(m, {"color": colours.get(k, "tan"), "opacity": 0.55}) for k, m in meshes.items()]
    lines = []
    for a, b, hit in report.interfering:
        overlap = mesh(parts[a] & parts[b], resolution=N)
        items.append((overlap, {"color": "#dd2222"}))
        lines.append(f"{a} & {b}: {hit.volume:.1f} mm^3 overlap")
    assert report.interfering, "the example assembly interferes on purpose"
    fig, (x, y) = plt.subplots(1, 2, figsize=(13, 5.2))
    image_axes(x, pv_picture(items, size, view=(1.0, -1.6, 1.2)),
               "interference (red: shared volume)\n" + "; ".join(lines), fontsize=10)
    image_axes(y, exploded_view(meshes, factor=0.8, window_size=size), "exploded view", fontsize=10)
    fig.tight_layout()
    return save(fig, "assembly_interference", out_dir)


if __name__ == "__main__":
    print(main())
