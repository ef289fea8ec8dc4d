"""A 3D wireframe next to its solid, and the wireframe's ambiguity.

`wireframe_vs_solid.png`: the wireframe of a bracket (the edges where its CSG
faces meet, from its B-rep) beside the shaded solid.  A wireframe holds only
edges: no faces, no inside.  `wireframe_ambiguity.png`: one wireframe and
three different solids (straight, barrel and waisted bores) that each have
exactly that wireframe (`spatial.compare.ambiguity`; a test checks the edges).
"""

import numpy as np

from _gallery import image_axes, picture_path, plt, save, shaded
from implicit import box, cylinder
from spatial import mesh
from spatial.compare import brep
from spatial.compare.ambiguity import picture as ambiguity_picture


def main(out_dir=None, small=False):
    N = 32 if small else 96
    part = (box((4, 2, 0.5), center=(0, 0, 0.25)) | box((0.5, 2, 2.5), center=(-1.75, 0, 1.25))) \
        - cylinder(0.4, 1, center=(0.8, 0, 0.25)) - cylinder(0.35, 1, center=(-1.75, 0, 1.5), axis=(1, 0, 0))
    m = mesh(part, resolution=N)
    rep = brep(part, m)
    fig = plt.figure(figsize=(12, 5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    for a, b in rep.edge_segments:
        ax.plot(*zip(a, b), color="k", lw=0.9)
    lo, hi = part.bounds
    ax.set_box_aspect(tuple(hi - lo))
    ax.view_init(elev=24, azim=-62)
    ax.set_axis_off()
    ax.set_title(f"3D wireframe: {len(rep.edge_segments)} edge segments, {rep.E} edges, {rep.V} vertices\n"
                 "no faces, no inside/outside", fontsize=10)
    image_axes(fig.add_subplot(1, 2, 2), shaded(m, size=(480, 400) if not small else (240, 200)),
               f"the solid: {rep.F} faces, genus {rep.G}")
    fig.tight_layout()
    path = save(fig, "wireframe_vs_solid", out_dir)
    facts = ambiguity_picture(picture_path("wireframe_ambiguity", out_dir), resolution=24 if small else 64)
    volumes = [v for v, _, _ in facts.values()]
    assert np.ptp(volumes) > 1.0  # the three readings are different solids
    return path


if __name__ == "__main__":
    print(main())
