"""Pictures of tool paths and of their verification.

`toolpath_picture` draws the program from above (matplotlib): cutting moves
coloured by depth, rapids dashed, the stock outline.  `removal_picture`
renders the part's mesh coloured by the machined stock's deviation from it
(pyvista off screen): red where material is left (excess), blue where the
tool went into the part (gouge), with a legend in model units.
"""

from __future__ import annotations

import os

import numpy as np

from ..files.atomic import atomic_write, check_output_path
from .gcode import path_points, read_gcode

__all__ = ["toolpath_picture", "removal_picture"]


def _check_png(path):
    return check_output_path(path, ".png")


def toolpath_picture(toolpath, path, *, title=None):
    """Top view of a `ToolPath`'s G-code: feeds by depth, rapids dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = _check_png(path)
    ops, start, _ = read_gcode(toolpath.to_gcode())
    lo, hi = (np.asarray(b, dtype=float) for b in toolpath.stock)
    fig, ax = plt.subplots(figsize=(7.5, 6.5), dpi=130)
    try:
        cmap = plt.get_cmap("viridis")
        cur = start
        for _name, moves in ops:
            pts, feed = path_points(moves, cur, step=None)
            cur = pts[-1]
            cut = feed > 0
            seg = np.stack([pts[:-1], pts[1:]], axis=1)
            c = cut[1:]
            z = seg[:, 1, 2]
            zn = (z - lo[2]) / max(hi[2] - lo[2], 1e-300)
            from matplotlib.collections import LineCollection

            ax.add_collection(LineCollection(seg[c][:, :, :2], colors=cmap(zn[c]), linewidths=0.8))
            ax.add_collection(LineCollection(seg[~c][:, :, :2], colors="#d62728", linewidths=0.4,
                                             linestyles="dashed", alpha=0.35))
        ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[1], lo[1], hi[1], hi[1], lo[1]], "k-", lw=1.2,
                label="stock")
        ax.plot([], [], color="#d62728", ls="--", lw=0.6, label="rapid (G0)")
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(lo[2], hi[2]))
        fig.colorbar(sm, ax=ax, label="tool bottom z of cutting moves")
        r = toolpath.tool_radius
        ax.set_xlim(lo[0] - 2 * r, hi[0] + 2 * r)
        ax.set_ylim(lo[1] - 2 * r, hi[1] + 2 * r)
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.legend(loc="upper right", fontsize=8)
        ax.set_title(title or f"{toolpath.title}: tool radius {r:g}, {toolpath.direction} milling, "
                              f"{len(toolpath.depths)} depths, {toolpath.move_count} moves", fontsize=9)
        ax.grid(True, lw=0.3)
        atomic_write(path, lambda tmp: fig.savefig(tmp, format="png"))
    finally:
        plt.close(fig)
    return path


def removal_picture(result, solid, path, *, resolution=128, window_size=(1000, 800), title=None):
    """The part's mesh coloured by the machined deviation (see `removal_deviation`)."""
    from ..meshing import mesh as mesh_solid
    from .verify import removal_deviation

    path = _check_png(path)
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    m = mesh_solid(solid, resolution=resolution)
    dev = removal_deviation(result, m, solid)
    m.point_data["deviation"] = dev
    span = float(max(np.abs(dev).max(), 3 * result.column))
    plotter = pv.Plotter(off_screen=True, window_size=window_size)
    try:
        plotter.set_background("white")
        plotter.add_mesh(m, scalars="deviation", cmap="coolwarm", clim=(-span, span), ambient=0.45,
                         diffuse=0.55, specular=0.0,
                         scalar_bar_args={"title": "deviation: + material left (excess), - gouge",
                                          "color": "black", "fmt": "%.3g", "n_labels": 5,
                                          "vertical": False, "position_x": 0.2, "position_y": 0.04,
                                          "height": 0.06, "width": 0.6, "title_font_size": 16,
                                          "label_font_size": 14})
        text = title or (f"gouge {result.gouge_volume:.4g}, excess {result.excess_volume:.4g} "
                         f"(beyond {result.tolerance:.3g}); removed {result.removed_volume:.4g}; "
                         f"rapid cuts {result.rapid_volume:.3g}")
        plotter.add_text(text, position="upper_left", font_size=10, color="black")
        plotter.camera_position = "iso"
        plotter.camera.azimuth = 20
        plotter.camera.elevation = 10
        plotter.reset_camera()
        plotter.camera.zoom(0.9)
        plotter.add_axes(color="black")
        image = plotter.screenshot(None, return_img=True)
    finally:
        plotter.close()
    from PIL import Image

    atomic_write(path, lambda tmp: Image.fromarray(image).save(tmp, format="PNG"))
    return path
