"""An object and its CSG tree, drawn as a tree: operators at the nodes, primitives at the leaves.

The object is the benchmark part: (sphere & box) minus three cylinders.
Each leaf's picture sits under its node; the root's picture is the object.
"""

import numpy as np

from _gallery import plt, save, shaded
from implicit import box, cylinder, sphere
from spatial import mesh

SYMBOL = {"union": "∪", "intersection": "∩", "difference": "−", "complement": "¬"}


def _layout(node, depth=0, x=[0]):
    """(node, x, depth) for every node, leaves spaced evenly, parents centred over children."""
    if not node.children or node.kind not in SYMBOL:
        out = [(node, float(x[0]), depth)]
        x[0] += 1
        return out
    rows = []
    for child in node.children:
        rows += _layout(child, depth + 1, x)
    kids = [r for r in rows if r[2] == depth + 1]
    rows.insert(0, (node, float(np.mean([k[1] for k in kids])), depth))
    return rows


def main(out_dir=None, small=False):
    N = 24 if small else 64
    size = (160, 140) if small else (260, 230)
    part = (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    rows = _layout(part, 0, [0])
    parent = {}
    for node, _, _ in rows:
        for child in node.children:
            parent[id(child)] = node
    pos = {id(n): (x, -d) for n, x, d in rows}
    fig, ax = plt.subplots(figsize=(12, 6.5))
    for node, x, d in rows:
        if id(node) in parent:
            px, py = pos[id(parent[id(node)])]
            ax.plot([px, x], [py, -d], color="0.4", lw=1, zorder=1)
    for node, x, d in rows:
        if node.kind in SYMBOL:
            ax.text(x, -d, SYMBOL[node.kind], fontsize=20, ha="center", va="center", zorder=3,
                    bbox=dict(boxstyle="circle", fc="#fde0c5", ec="k"))
        else:
            img = shaded(mesh(node, resolution=N), size=size)
            ax.imshow(img, extent=(x - 0.45, x + 0.45, -d - 0.85, -d + 0.05), zorder=2)
            ax.text(x, -d + 0.1, node.kind, ha="center", fontsize=9)
    root_img = shaded(mesh(part, resolution=2 * N), size=(2 * size[0], 2 * size[1]))
    xs = [x for _, x, _ in rows]
    ax.imshow(root_img, extent=(max(xs) + 0.7, max(xs) + 2.7, -1.6, 0.2), zorder=2)
    ax.text(max(xs) + 1.7, 0.3, "the object", ha="center", fontsize=10)
    ax.set_xlim(min(xs) - 0.6, max(xs) + 2.8)
    ax.set_ylim(-max(d for _, _, d in rows) - 1.0, 0.6)
    ax.set_axis_off()
    ax.set_title(f"CSG tree: {part.count_nodes()} nodes, {part.count_primitives()} primitives", fontsize=11)
    fig.tight_layout()
    return save(fig, "csg_tree", out_dir)


if __name__ == "__main__":
    print(main())
