"""Pictures: shaded images, wireframes, hidden-line drawings, multi-view sheets
and exploded views of assemblies (the drafting functions of a modeler).

Everything renders off-screen through pyvista/VTK; on a machine without a
display VTK is pointed at EGL before the first plotter is made.

Examples
--------
>>> import pyvista as pv
>>> from spatial.drafting.render import render
>>> image = render(pv.Cube().triangulate(), style="hidden-line", window_size=(200, 150))
>>> image.shape
(150, 200, 3)
"""

from __future__ import annotations

import os
from typing import Mapping

import numpy as np

from ..files.atomic import atomic_write as _atomic_write

__all__ = ["STYLES", "VIEWS", "render", "render_views", "exploded_view", "explode_offsets"]

#: Picture styles understood by `render`.
STYLES = ("shaded", "wireframe", "mesh", "hidden-line")

#: Named camera directions (from the camera towards the part) and up vectors.
VIEWS = {
    "iso": ((1.0, 1.0, 0.8), (0.0, 0.0, 1.0)),
    "front": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "top": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "right": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
}

_PART_COLORS = ("#c8a165", "#6a9fb5", "#b5676a", "#7fb56a", "#a06ab5", "#b5a86a", "#6ab5a8", "#8c8c8c")


def _pyvista():
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    try:
        import pyvista as pv
    except ImportError as exc:  # pragma: no cover - pyvista is a dependency
        raise ImportError("pictures need pyvista: pip install pyvista") from exc
    return pv


def _check_style(style):
    if style not in STYLES:
        raise ValueError(f"style: expected one of {', '.join(STYLES)}, got {style!r}")


def _check_size(window_size):
    size = tuple(int(v) for v in window_size)
    if len(size) != 2 or min(size) < 16 or max(size) > 8192:
        raise ValueError(f"window_size: expected (width, height) between 16 and 8192 pixels, got {window_size!r}")
    return size


def _check_path(path):
    if path is None:
        return None
    path = os.fspath(path)
    if not path.lower().endswith(".png"):
        raise ValueError(f"path: pictures are written as PNG, expected a name ending in .png, got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    return path


def _write_png_atomically(image: np.ndarray, path: str) -> None:
    pv = _pyvista()
    from PIL import Image

    _atomic_write(path, lambda tmp: Image.fromarray(image).save(tmp, format="PNG"), ".png")
    del pv


def _add_part(plotter, mesh, style, color, feature_angle):
    if mesh.n_points == 0:
        return
    edges = mesh.extract_feature_edges(feature_angle=feature_angle, boundary_edges=True,
                                       non_manifold_edges=False, manifold_edges=False)
    if style == "shaded":
        plotter.add_mesh(mesh, color=color, smooth_shading=True, split_sharp_edges=True,
                         feature_angle=feature_angle)
        # Feature lines of marching-cubes meshes come out ragged along sharp
        # edges; split normals already show the edges in a shaded picture.
        if edges.n_points and mesh.n_cells < 5000:
            plotter.add_mesh(edges, color="black", line_width=1.5)
    elif style == "mesh":
        plotter.add_mesh(mesh, color=color, show_edges=True, edge_color="#303030", line_width=0.5)
    elif style == "wireframe":
        # The wire-frame model: edges only, hidden ones included, surfaces absent.
        if edges.n_points:
            plotter.add_mesh(edges, color="black", line_width=1.5)
        plotter.add_mesh(mesh, style="wireframe", color="#b0b0b0", line_width=0.3, opacity=0.25)
    elif style == "hidden-line":
        # Surfaces drawn in the background colour hide the lines behind them.
        plotter.add_mesh(mesh, color="white", lighting=False, silhouette={"color": "black", "line_width": 2.0})
        if edges.n_points:
            plotter.add_mesh(edges, color="black", line_width=1.5)


def _place_camera(plotter, meshes, view):
    direction, up = VIEWS[view]
    bounds = np.array([m.bounds for m in meshes if m.n_points]).reshape(-1, 6)
    if bounds.size == 0:
        return
    lo = bounds[:, 0::2].min(axis=0)
    hi = bounds[:, 1::2].max(axis=0)
    centre = 0.5 * (lo + hi)
    radius = 0.5 * np.linalg.norm(hi - lo) or 1.0
    d = np.asarray(direction, dtype=float)
    d /= np.linalg.norm(d)
    plotter.camera_position = [tuple(centre + 4.0 * radius * d), tuple(centre), up]
    if view != "iso":
        plotter.enable_parallel_projection()
    # Keep the direction, fit the whole part in the picture.
    plotter.reset_camera()
    plotter.camera.zoom(0.95)


def render(mesh, path=None, *, style="shaded", view="iso", window_size=(800, 600),
           color=None, feature_angle=30.0, title=None) -> np.ndarray:
    """Render one mesh, or several (a mapping name -> mesh), to an RGB image.

    Parameters
    ----------
    mesh : pyvista.PolyData or Mapping[str, pyvista.PolyData]
        What to draw; several parts get distinct colours.
    path : str or os.PathLike, optional
        A ``.png`` file to write (atomically).
    style : {"shaded", "wireframe", "mesh", "hidden-line"}
        Shaded surfaces with feature edges; the wire-frame model (all
        edges, hidden ones too); the triangles; or a hidden-line drawing.
    view : {"iso", "front", "top", "right"}
        Camera direction; the orthographic views use parallel projection.
    window_size : (width, height)
        Picture size in pixels.

    Returns
    -------
    (height, width, 3) uint8 ndarray
    """
    _check_style(style)
    if view not in VIEWS:
        raise ValueError(f"view: expected one of {', '.join(VIEWS)}, got {view!r}")
    size = _check_size(window_size)
    path = _check_path(path)
    parts = dict(mesh) if isinstance(mesh, Mapping) else {"part": mesh}
    pv = _pyvista()
    for name, m in parts.items():
        if not isinstance(m, pv.DataSet):
            raise TypeError(f"mesh: expected pyvista meshes, got {type(m).__name__} for {name!r}")
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        plotter.set_background("white")
        for i, (name, m) in enumerate(parts.items()):
            part_color = color or _PART_COLORS[i % len(_PART_COLORS)]
            _add_part(plotter, m, style, part_color, feature_angle)
        if title:
            plotter.add_text(title, font_size=10, color="black")
        _place_camera(plotter, list(parts.values()), view)
        image = np.asarray(plotter.screenshot(return_img=True))[..., :3].copy()
    finally:
        plotter.close()
    if path is not None:
        _write_png_atomically(image, path)
    return image


def render_views(mesh, path=None, *, style="hidden-line", window_size=(1000, 800)) -> np.ndarray:
    """A drawing sheet: front, top and right orthographic views and an iso view.

    Returns the (height, width, 3) image; writes it to `path` when given.
    """
    _check_style(style)
    width, height = _check_size(window_size)
    path = _check_path(path)
    tile = (max(16, width // 2), max(16, height // 2))
    tiles = {v: render(mesh, style=style, view=v, window_size=tile, title=v) for v in ("front", "top", "right", "iso")}
    # First-angle projection sheet: front top-left, iso top-right, top below front, right below iso.
    sheet = np.vstack([np.hstack([tiles["front"], tiles["iso"]]), np.hstack([tiles["top"], tiles["right"]])])
    if path is not None:
        _write_png_atomically(sheet, path)
    return sheet


def explode_offsets(centroids: np.ndarray, factor: float) -> np.ndarray:
    """Offsets (n, 3) that push parts away from the assembly centre.

    Each part moves along the direction from the mean of all `centroids` to
    its own centroid, by `factor` times the assembly's radius; a part at
    the centre stays.
    """
    c = np.asarray(centroids, dtype=float).reshape(-1, 3)
    if not np.isfinite(factor) or factor < 0:
        raise ValueError(f"factor: expected a non-negative number, got {factor!r}")
    centre = c.mean(axis=0)
    rel = c - centre
    norms = np.linalg.norm(rel, axis=1, keepdims=True)
    radius = float(norms.max()) if len(c) else 0.0
    directions = np.divide(rel, norms, out=np.zeros_like(rel), where=norms > 1e-12 * max(radius, 1.0))
    return directions * factor * max(radius, 1e-12)


def exploded_view(parts: Mapping, path=None, *, factor=0.6, style="shaded", window_size=(900, 700)) -> np.ndarray:
    """Render an assembly with its parts pulled apart along radial directions.

    Parameters
    ----------
    parts : Mapping[str, pyvista.PolyData]
        Named part meshes in assembly position.
    factor : float
        How far parts move, as a fraction of the assembly radius.
    """
    if not isinstance(parts, Mapping) or not parts:
        raise TypeError("parts: expected a non-empty mapping of part names to meshes")
    meshes = {k: v for k, v in parts.items()}
    centroids = np.array([np.asarray(m.center) for m in meshes.values()])
    offsets = explode_offsets(centroids, factor)
    moved = {k: m.translate(off, inplace=False) for (k, m), off in zip(meshes.items(), offsets)}
    return render(moved, path, style=style, window_size=window_size)
