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

from ..files.atomic import atomic_write

__all__ = ["deviation_picture", "histogram_picture"]


def _check_png(path):
    p = os.fspath(path)
    if not p.lower().endswith(".png"):
        raise ValueError(f"path: expected a .png file name, got {p!r}")
    folder = os.path.dirname(os.path.abspath(p))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    return p


def deviation_picture(result, path, *, worst=5, window_size=(1100, 850), title=None):
    """The scan coloured by deviation, worst points labelled; returns the path."""
    path = _check_png(path)
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    dev = result.deviation
    span = float(max(np.abs(dev).max(), result.tolerance))
    plotter = pv.Plotter(off_screen=True, window_size=window_size)
    try:
        plotter.set_background("white")
        bar = {"title": "deviation from design (+ outside material)", "color": "black", "fmt": "%.3g",
               "n_labels": 7, "vertical": False, "position_x": 0.18, "position_y": 0.03, "width": 0.64,
               "height": 0.07, "title_font_size": 16, "label_font_size": 14}
        if result.mesh is not None:
            m = result.mesh.copy()
            m.point_data["deviation"] = dev
            plotter.add_mesh(m, scalars="deviation", cmap="coolwarm", clim=(-span, span), ambient=0.4,
                             diffuse=0.6, specular=0.0, scalar_bar_args=bar)
        else:
            cloud = pv.PolyData(result.points)
            cloud.point_data["deviation"] = dev
            size = max(3.0, min(10.0, 2000.0 / np.sqrt(len(dev))))
            plotter.add_mesh(cloud, scalars="deviation", cmap="coolwarm", clim=(-span, span),
                             render_points_as_spheres=True, point_size=size, scalar_bar_args=bar)
        w = result.worst(worst)
        if w:
            pts = np.array([p["point"] for p in w])
            labels = [f"{k + 1}: {p['deviation']:+.4g}" for k, p in enumerate(w)]
            plotter.add_point_labels(pts, labels, font_size=14, point_size=12, point_color="black",
                                     text_color="black", shape_color="#ffffe0", shape_opacity=0.85,
                                     always_visible=True)
        verdict = "PASS" if result.passed else "FAIL"
        text = title or (f"{verdict}: tolerance +/-{result.tolerance:.4g}; {100 * result.within_tolerance:.1f} % "
                         f"within; max {result.max_deviation:+.4g}, min {result.min_deviation:+.4g}, "
                         f"RMS {result.rms_deviation:.4g} ({len(dev)} points, {result.alignment} alignment)")
        plotter.add_text(text, position="upper_left", font_size=10, color="black")
        plotter.camera_position = "iso"
        plotter.camera.azimuth = 25
        plotter.camera.elevation = 10
        plotter.reset_camera()
        plotter.camera.zoom(0.85)
        plotter.add_axes(color="black")
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
