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
