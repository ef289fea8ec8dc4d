"""The seven representation schemes of the seed, side by side, for one part.

The part is a UPN 80 channel, 120 long: a block minus a block (CSG), a
U profile extruded (sweep), an instance of the `channel_section` family
(primitive instancing), three convex pieces of planes (half-spaces), three
trilinear volumes (analytical solid modelling), its faces, edges and
vertices (B-rep), and octree cells and voxels (spatial partitioning: cell
decomposition and spatial occupancy).  Every form is built by
`spatial.compare` and measured: the storage under each picture.
"""

import numpy as np

from _gallery import cubes, image_axes, plt, pv_picture, save, shaded
from implicit import box
from implicit.library import channel_section
from spatial import mesh
from spatial.cells import BOUNDARY, FULL, OccupancyGrid, Octree
from spatial.compare import compare, half_space_form


def _hull(vertices):
    import pyvista as pv
    return pv.PolyData(vertices).delaunay_3d().extract_surface(algorithm="dataset_surface")


def main(out_dir=None, small=False):
    N = 16 if small else 40
    size = (300, 250) if small else (420, 340)
    part = channel_section("UPN80", length=120)
    p = part.params["params"]
    h, b, tw, tf, L = p["height"], p["width"], p["web"], p["flange"], p["length"]
    csg = box((b, h, L), center=(b / 2, h / 2, 0)) - box((b, h - 2 * tf, L + 2), center=(tw + b / 2, h / 2, 0))
    table = compare(part, resolution=N, n_queries=2000, claims=False, progress=False)
    rows = {r.name: r for r in table.rows}
    form = half_space_form(part)
    pieces = form.piece_vertices()
    m = mesh(part, resolution=2 * N)
    from spatial.compare import brep
    rep = brep(part, m)
    m.cell_data["face"] = rep.face_of_triangle

    fig, axes = plt.subplots(2, 4, figsize=(17, 8.4))
    axes = axes.ravel()

    def caption(name):
        r = rows[name]
        return f"{r.bytes} B in memory, {r.file_bytes} B in its file"

    A = mesh(box((b, h, L), center=(b / 2, h / 2, 0)), resolution=N)
    B = mesh(box((b, h - 2 * tf, L + 2), center=(tw + b / 2, h / 2, 0)), resolution=N)
    image_axes(axes[0], pv_picture([(A, {"color": "#c8a165"}), (B, {"color": "#cc3333", "opacity": 0.45})], size),
               f"CSG: block − block\n{caption('CSG tree')}")
    import pyvista as pv
    solids = [(_hull(v), {"color": c}) for v, c in zip(pieces, ("#4477aa", "#66ccee", "#228833", "#ccbb44"))]
    image_axes(axes[1], pv_picture(solids, size),
               f"half-spaces: {len(pieces)} convex pieces, {form.n_planes} planes\n{caption('half-space form')}")
    ax = axes[2]
    from implicit.library.sections import section_outline
    outline = section_outline("channel_section", **{k: p[k] for k in ("height", "width", "web", "flange")})
    ax.fill(*np.vstack([outline, outline[:1]]).T, color="#c8a165", ec="k")
    ax.annotate("extrude 120 along z", xy=(b * 0.8, h * 0.5), fontsize=9, ha="center")
    ax.set_aspect("equal")
    ax.set_title(f"sweep: a U profile extruded\n{caption('sweep')}", fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
    ax = axes[3]
    image = shaded(m, size=size)
    ax.imshow(image)
    ax.set_axis_off()
    text = "\n".join(f"{k} = {v:g}" for k, v in p.items())
    ax.text(0.02, 0.98, f"channel_section\n(UPN 80)\n{text}", transform=ax.transAxes, va="top", fontsize=8,
            family="monospace", bbox=dict(fc="white", ec="0.6"))
    ax.set_title(f"primitive instancing: family + parameters\n{caption('primitive instancing')}", fontsize=9)
    ax = fig.add_subplot(2, 4, 5, projection="3d")
    axes[4].set_axis_off()
    from parametric import BezierVolume
    for verts in pieces:
        lo, hi = verts.min(axis=0), verts.max(axis=0)
        u = np.array([0.0, 1.0])
        grid = lo + np.stack(np.meshgrid(u, u, u, indexing="ij"), -1) * (hi - lo)
        vol = BezierVolume(grid)
        for surf in vol.boundary_surfaces().values():
            ul, vl = surf.isoparametric_lines(step=0.25, samples=8)
            for line in list(ul) + list(vl):
                ax.plot(*line.T, color="C0", lw=0.6)
    ax.set_box_aspect((b, h, L))
    ax.set_axis_off()
    ax.set_title(f"analytical: 3 trilinear volumes\n{caption('analytical (trivariate)')}", fontsize=9)
    image_axes(axes[5], pv_picture([(m, {"scalars": "face", "cmap": "tab20", "show_scalar_bar": False})], size),
               f"B-rep: V={rep.V} E={rep.E} F={rep.F}, F-E+V-L = {rep.euler_poincare[0]}\n"
               f"{caption('B-rep (faces by CSG leaf)')}")
    tree = Octree.from_solid(part, resolution=N, progress=False)
    keep = (tree.state == FULL) | (tree.state == BOUNDARY)
    cells = cubes(tree.lo[keep] + 0.04 * tree.size[keep, None], 0.92 * tree.size[keep], tree.state[keep])
    image_axes(axes[6], pv_picture([(cells, {"scalars": "state", "cmap": ["#4477aa", "#ee6677"],
                                             "show_scalar_bar": False})], size),
               f"cell decomposition: {int(np.sum(tree.state == FULL))} FULL, {int(np.sum(tree.state == BOUNDARY))} "
               f"BOUNDARY\n{caption('octree cells')}")
    grid = OccupancyGrid.from_solid(part, resolution=N, progress=False)
    idx = np.argwhere(grid.occupancy)
    h_ = grid.voxel_size
    vox = cubes(grid.origin + idx * h_ + 0.05 * h_, np.full(len(idx), 0.9 * h_))
    image_axes(axes[7], pv_picture([(vox, {"color": "#999933"})], size),
               f"spatial occupancy: {len(idx)} of {grid.occupancy.size} voxels\n"
               f"{caption('occupancy grid (bool voxels)')}")
    fig.suptitle("Seven representation schemes of one part (a UPN 80 channel, 120 long)", fontsize=12)
    fig.tight_layout()
    return save(fig, "seven_schemes", out_dir)


if __name__ == "__main__":
    print(main())
