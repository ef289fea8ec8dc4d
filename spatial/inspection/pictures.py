"""Pictures of an inspection: the colour map on the part and the histogram.

`deviation_picture` renders the aligned scan (its mesh, or its points as
spheres) coloured by deviation with a diverging map centred on zero and a
legend in model units, the tolerance band marked on the legend's range, and
the worst points labelled with their deviation.  `histogram_picture` plots
the distribution of the deviations with the tolerance limits.
"""

from __future__ import annotations

import os

import numpy as np

from ..files.atomic import atomic_write, check_output_path

__all__ = ["deviation_picture", "histogram_picture"]


def _check_png(path):
    return check_output_path(path, ".png")


def deviation_picture(result, path, *, solid=None, worst=5, window_size=(1400, 700), title=None, resolution=96):
    """The scan coloured by deviation, worst points labelled; returns the path.

    A scanned mesh is drawn itself.  A point cloud is drawn over the design's
    surface (when `solid` is given), each surface point coloured like its
    nearest scan point, so the map reads as a surface, not as a see-through
    cloud.
    """
    path = _check_png(path)
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    dev = result.deviation
    # the colours span twice the tolerance: a defect beyond it saturates and stands out
    span = float(min(max(np.abs(dev).max(), result.tolerance), 2 * result.tolerance))
    if result.mesh is not None:
        shown = result.mesh.copy()
        shown.point_data["deviation"] = dev
        style = {}
    elif solid is not None:
        from scipy.spatial import cKDTree

        from ..meshing import mesh as mesh_solid

        shown = mesh_solid(solid, resolution=resolution)
        shown.point_data["deviation"] = dev[cKDTree(result.points).query(np.asarray(shown.points))[1]]
        style = {}
    else:
        shown = pv.PolyData(result.points)
        shown.point_data["deviation"] = dev
        style = {"render_points_as_spheres": True, "point_size": max(2.0, min(6.0, 600.0 / np.sqrt(len(dev))))}
    plotter = pv.Plotter(off_screen=True, window_size=window_size, shape=(1, 2), border=False)
    try:
        w = result.worst(worst)
        for col, (azimuth, name) in enumerate(((25, "seen from +x +y"), (160, "seen from -x"))):
            plotter.subplot(0, col)
            plotter.set_background("white")
            bar = {"title": f"deviation from design (+ outside material), colours saturate at +/-{span:.3g}",
                   "color": "black", "fmt": "%.3g", "n_labels": 5, "vertical": False, "position_x": 0.1,
                   "position_y": 0.03, "width": 0.8, "height": 0.07, "title_font_size": 14,
                   "label_font_size": 12}
            plotter.add_mesh(shown.copy(), scalars="deviation", cmap="coolwarm", clim=(-span, span), ambient=0.4,
                             diffuse=0.6, specular=0.0, show_scalar_bar=(col == 0),
                             scalar_bar_args=bar if col == 0 else None, **style)
            if w:
                pts = np.array([p["point"] for p in w])
                labels = [f"{k + 1}: {p['deviation']:+.4g}" for k, p in enumerate(w)]
                plotter.add_point_labels(pts, labels, font_size=13, point_size=10, point_color="black",
                                         text_color="black", shape_color="#ffffe0", shape_opacity=0.85,
                                         always_visible=True)
            plotter.add_text(name, position="upper_right", font_size=8, color="black")
            plotter.camera_position = "iso"
            plotter.camera.azimuth = azimuth
            plotter.camera.elevation = 10
            plotter.reset_camera()
            plotter.camera.zoom(0.8)
        plotter.subplot(0, 0)
        verdict = "PASS" if result.passed else "FAIL"
        text = title or (f"{verdict}: tolerance +/-{result.tolerance:.4g}, {100 * result.within_tolerance:.1f} % within\n"
                         f"max {result.max_deviation:+.4g}, min {result.min_deviation:+.4g}, "
                         f"RMS {result.rms_deviation:.4g}\n{len(dev)} points, {result.alignment} alignment")
        plotter.add_text(text, position="upper_left", font_size=9, color="black")
        image = plotter.screenshot(None, return_img=True)
    finally:
        plotter.close()
    from PIL import Image

    atomic_write(path, lambda tmp: Image.fromarray(image).save(tmp, format="PNG"))
    return path


def histogram_picture(result, path, *, bins=60, title=None):
    """Histogram of the deviations with the tolerance limits; returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = _check_png(path)
    dev = result.deviation
    tol = result.tolerance
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=130)
    try:
        lo = min(float(dev.min()), -tol) * 1.1
        hi = max(float(dev.max()), tol) * 1.1
        edges = np.linspace(lo, hi, bins + 1)
        counts, _, patches = ax.hist(dev, bins=edges, color="#6a9fb5", edgecolor="#234", lw=0.4)
        centres = 0.5 * (edges[:-1] + edges[1:])
        for c, patch in zip(centres, patches):
            if abs(c) > tol:
                patch.set_facecolor("#d62728")
        for x in (-tol, tol):
            ax.axvline(x, color="#d62728", ls="--", lw=1.2)
        ax.axvline(0.0, color="black", lw=0.8)
        ax.axvline(result.mean_deviation, color="#2ca02c", lw=1.2, label=f"mean {result.mean_deviation:+.4g}")
        ax.plot([], [], color="#d62728", ls="--", label=f"tolerance +/-{tol:.4g}")
        ax.set_xlabel("signed deviation from the design surface (model units; + outside the material)")
        ax.set_yscale("log")                 # the tails (a defect's few points) stay visible
        ax.set_ylabel("points (log scale)")
        ax.legend(fontsize=8, loc="upper left")
        verdict = "PASS" if result.passed else "FAIL"
        ax.set_title(title or f"{verdict}: {100 * result.within_tolerance:.1f} % of {len(dev)} points within "
                              f"tolerance; RMS {result.rms_deviation:.4g}", fontsize=10)
        ax.grid(True, lw=0.3)
        fig.tight_layout()
        atomic_write(path, lambda tmp: fig.savefig(tmp, format="png"))
    finally:
        plt.close(fig)
    return path
