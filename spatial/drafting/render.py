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

__all__ = ["STYLES", "VIEWS", "render", "render_views", "render_cells", "feature_lines", "exploded_view",
           "explode_offsets"]

#: Picture styles understood by `render`.
STYLES = ("shaded", "wireframe", "mesh", "hidden-line")

#: Named camera directions (from the camera towards the part) and up vectors: the front
#: view looks along +y with z up, as the drawings of `spatial.drafting` do.
VIEWS = {
    "iso": ((-1.0, 1.0, -1.0), (0.0, 0.0, 1.0)),
    "front": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "top": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "left": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
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


def feature_lines(mesh, solid=None, feature_angle=30.0):
    """The sharp edges of `mesh` as a pyvista line set: exact and single when
    the `solid` it came from is given (`spatial.drafting.edges`), from the
    mesh normals otherwise."""
    pv = _pyvista()
    from .edges import surface_edges

    lines = surface_edges(mesh, solid, feature_angle=feature_angle).polylines
    if not lines:
        return pv.PolyData()
    points = np.concatenate(lines)
    sizes = np.array([len(p) for p in lines])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    cells = np.concatenate([np.concatenate([[n], np.arange(s0, s0 + n)]) for s0, n in zip(starts, sizes)])
    return pv.PolyData(points, lines=cells)


def _add_part(plotter, mesh, style, color, feature_angle, solid=None):
    if mesh.n_points == 0:
        return
    edges = feature_lines(mesh, solid, feature_angle) if style in ("wireframe", "hidden-line") or \
        solid is not None else mesh.extract_feature_edges(feature_angle=feature_angle, boundary_edges=True,
                                                          non_manifold_edges=False, manifold_edges=False)
    if style == "shaded":
        plotter.add_mesh(mesh, color=color, smooth_shading=True, split_sharp_edges=True,
                         feature_angle=feature_angle)
        # Feature lines from mesh normals alone come out ragged along sharp edges;
        # the exact ones (with the solid) are drawn at every size.
        if edges.n_points and (solid is not None or mesh.n_cells < 5000):
            plotter.add_mesh(edges, color="black", line_width=1.5)
    elif style == "mesh":
        plotter.add_mesh(mesh, color=color, show_edges=True, edge_color="#303030", line_width=0.5)
    elif style == "wireframe":
        # The wire-frame model: the feature edges only, hidden ones included, no surfaces
        # and no triangles.
        if edges.n_points:
            plotter.add_mesh(edges, color="black", line_width=1.5)
    elif style == "hidden-line":
        # Surfaces drawn in the background colour hide the lines behind them.
        actor = plotter.add_mesh(mesh, color="white", lighting=False,
                                 silhouette={"color": "black", "line_width": 1.5})
        # Push the white faces back a little so the edges lying on them are not lost to
        # depth fighting.
        actor.mapper.SetResolveCoincidentTopologyToPolygonOffset()
        actor.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(2.0, 4.0)
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
    # `direction` points from the camera towards the part.
    plotter.camera_position = [tuple(centre - 4.0 * radius * d), tuple(centre), up]
    if view != "iso":
        plotter.enable_parallel_projection()
    # Keep the direction, fit the whole part in the picture.
    plotter.reset_camera()
    plotter.camera.zoom(0.95)


def render(mesh, path=None, *, style="shaded", view="iso", window_size=(800, 600),
           color=None, feature_angle=30.0, title=None, solid=None) -> np.ndarray:
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
    view : {"iso", "front", "top", "left", "right"}
        Camera direction; the orthographic views use parallel projection.
    window_size : (width, height)
        Picture size in pixels.
    solid : implicit.Solid or Mapping[str, Solid], optional
        The solid(s) the mesh(es) came from: feature edges are then exact
        single lines instead of the mesh's chamfered double lines.

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
    solids = dict(solid) if isinstance(solid, Mapping) else {k: solid for k in parts}
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        plotter.set_background("white")
        for i, (name, m) in enumerate(parts.items()):
            part_color = color or _PART_COLORS[i % len(_PART_COLORS)]
            _add_part(plotter, m, style, part_color, feature_angle, solids.get(name))
        if title:
            plotter.add_text(title, font_size=10, color="black")
        _place_camera(plotter, list(parts.values()), view)
        image = np.asarray(plotter.screenshot(return_img=True))[..., :3].copy()
    finally:
        plotter.close()
    if path is not None:
        _write_png_atomically(image, path)
    return image


def render_views(mesh, path=None, *, style="hidden-line", window_size=(1000, 800), projection="first",
                 solid=None) -> np.ndarray:
    """Four pictures: front, top and side views placed by the projection
    method, and the iso view in the free corner.

    First angle (ISO 5456-2): the top view below the front view, the view
    from the left on its right.  Third angle (ASME Y14.3): the top view
    above the front view, the view from the right on its right.  (For a
    drawing with dimensions and a title block see `spatial.drafting.part_drawing`.)

    Returns the (height, width, 3) image; writes it to `path` when given.
    """
    _check_style(style)
    if projection not in ("first", "third"):
        raise ValueError(f"projection: expected 'first' or 'third', got {projection!r}")
    width, height = _check_size(window_size)
    path = _check_path(path)
    tile = (max(16, width // 2), max(16, height // 2))
    side = "left" if projection == "first" else "right"
    tiles = {v: render(mesh, style=style, view=v, window_size=tile, title=v, solid=solid)
             for v in ("front", "top", side, "iso")}
    if projection == "first":
        rows = [[tiles["front"], tiles[side]], [tiles["top"], tiles["iso"]]]
    else:
        rows = [[tiles["top"], tiles["iso"]], [tiles["front"], tiles[side]]]
    sheet = np.vstack([np.hstack(r) for r in rows])
    if path is not None:
        _write_png_atomically(sheet, path)
    return sheet


def render_cells(octree, path=None, *, window_size=(800, 600), cutaway=True) -> np.ndarray:
    """The octree's leaves as boxes coloured by class: FULL blue, BOUNDARY orange
    (EMPTY leaves are left out); with `cutaway` the front half (y below the
    middle) is removed to show the inside.

    Examples
    --------
    >>> from implicit import sphere
    >>> from spatial.cells import Octree
    >>> image = render_cells(Octree.from_solid(sphere(1.0), resolution=8), window_size=(120, 90))
    >>> image.shape
    (90, 120, 3)
    """
    from ..cells import BOUNDARY, FULL

    size = _check_size(window_size)
    path = _check_path(path)
    for name in ("lo", "size", "state"):
        if not hasattr(octree, name):
            raise TypeError(f"octree: expected a spatial.cells.Octree, got {type(octree).__name__}")
    pv = _pyvista()
    lo, edge, state = np.asarray(octree.lo), np.asarray(octree.size), np.asarray(octree.state)
    keep = (state == FULL) | (state == BOUNDARY)
    if cutaway and keep.any():
        centre = lo + 0.5 * edge[:, None]
        mid = 0.5 * (centre[keep, 1].min() + centre[keep, 1].max())
        keep &= centre[:, 1] >= mid
    lo, edge, state = lo[keep], edge[keep], state[keep]
    # Eight corners per leaf in VTK's hexahedron order, all leaves at once.
    unit = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    pts = (lo[:, None, :] + edge[:, None, None] * unit[None]).reshape(-1, 3)
    cells = np.column_stack([np.full(len(lo), 8), np.arange(8 * len(lo)).reshape(-1, 8)]).ravel()
    grid = pv.UnstructuredGrid(cells, np.full(len(lo), pv.CellType.HEXAHEDRON, dtype=np.uint8), pts)
    colours = np.where(state == FULL, 0, 1)
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        plotter.set_background("white")
        if len(lo):
            grid.cell_data["class"] = colours
            plotter.add_mesh(grid, scalars="class", cmap=["#4f7fbf", "#e8933a"], clim=(0, 1), show_edges=True,
                             edge_color="#303030", line_width=0.5, show_scalar_bar=False)
        plotter.add_text("FULL (blue) / BOUNDARY (orange)", font_size=9, color="black")
        direction, up = VIEWS["iso"]
        if len(lo):
            c = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
            r = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0))) or 1.0
            plotter.camera_position = [tuple(c - 3.0 * r * np.asarray(direction)), tuple(c), up]
            plotter.reset_camera()
        image = np.asarray(plotter.screenshot(return_img=True))[..., :3].copy()
    finally:
        plotter.close()
    if path is not None:
        _write_png_atomically(image, path)
    return image


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
