"""Shared set-up of the gallery scripts: where pictures go, matplotlib Agg, off-screen pyvista."""

from __future__ import annotations

import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402,F401

HERE = os.path.dirname(os.path.abspath(__file__))
PICTURES = os.path.join(HERE, "pictures")


def picture_path(name: str, out_dir=None) -> str:
    """``out_dir/name.png`` (default `examples/pictures/`), the folder made when missing."""
    folder = PICTURES if out_dir is None else os.fspath(out_dir)
    os.makedirs(folder, exist_ok=True)
    return os.path.join(folder, f"{name}.png")


def save(fig, name: str, out_dir=None, dpi=100) -> str:
    """Write `fig` as a PNG (atomically) and close it; returns the path."""
    from spatial.files import atomic_write

    path = picture_path(name, out_dir)
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"), ".png")
    plt.close(fig)
    return path


def shaded(mesh, size=(360, 300), view="iso", style="shaded", **kw):
    """An off-screen picture (RGB array) of a mesh or a mapping of meshes."""
    from spatial.drafting import render

    return render(mesh, style=style, view=view, window_size=size, **kw)


def image_axes(ax, image, title=None, fontsize=9):
    ax.imshow(image)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=fontsize)


def pv_picture(items, size=(360, 300), view=(1.0, -1.3, 0.9), edges=False):
    """Render ``[(mesh, add_mesh keyword dict), ...]`` off-screen; returns the RGB image."""
    import numpy as np
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background("white")
    for mesh, kw in items:
        kw = dict(kw)
        kw.setdefault("show_edges", edges)
        plotter.add_mesh(mesh, **kw)
    plotter.camera_position = "iso"
    plotter.camera.azimuth = 0
    bounds = np.array(plotter.bounds).reshape(3, 2)
    centre = bounds.mean(axis=1)
    radius = float(np.linalg.norm(bounds[:, 1] - bounds[:, 0])) or 1.0
    d = np.asarray(view, dtype=float)
    plotter.camera.position = tuple(centre + 2.2 * radius * d / np.linalg.norm(d))
    plotter.camera.focal_point = tuple(centre)
    plotter.camera.up = (0.0, 0.0, 1.0)
    plotter.reset_camera_clipping_range()
    plotter.camera.zoom(1.1)
    image = plotter.screenshot(return_img=True)
    plotter.close()
    return image


def cubes(lo, size, state=None):
    """A PolyData of axis-aligned cubes (lower corners `lo`, edges `size`), with a `state` array."""
    import numpy as np
    import pyvista as pv

    centres = np.asarray(lo) + 0.5 * np.asarray(size)[:, None]
    cloud = pv.PolyData(centres)
    cloud["size"] = np.asarray(size, dtype=float)
    if state is not None:
        cloud["state"] = np.asarray(state)
    return cloud.glyph(geom=pv.Cube(), scale="size", orient=False)
