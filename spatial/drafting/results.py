"""Pictures of finite-element results: the deformed part coloured by von Mises stress.

`draw_results` takes the grid `spatial.fea.read_frd` returns, warps it by
the displacements (scaled so the largest one shows as 8 % of the part's
size, the factor printed in the title), colours it by the von Mises
stress, and draws the undeformed part as a grey outline, off screen.
"""

from __future__ import annotations

import numpy as np

from .render import _check_path, _check_size, _pyvista, _write_png_atomically

__all__ = ["draw_results"]

#: The largest displacement is drawn as this fraction of the part's diagonal.
SHOWN_DISPLACEMENT = 0.08


def draw_results(grid, path=None, *, field="von_mises", window_size=(1000, 700), view=(1.0, -1.6, 0.9)) -> np.ndarray:
    """Draw results (deformed shape coloured by `field`) as a PNG.

    Parameters
    ----------
    grid : pyvista.UnstructuredGrid
        From `spatial.fea.read_frd`: point data ``DISP`` and `field`.
    path : str, optional
        PNG file written (atomically).
    field : str
        Point data to colour by (default ``von_mises``).
    window_size : (int, int)
    view : (3,) float
        Direction from the part's centre to the camera.

    Returns
    -------
    (h, w, 3) uint8
        The picture.

    Examples
    --------
    >>> from spatial.fea import read_frd
    >>> draw_results(read_frd("beam.frd"), "beam.png")   # doctest: +SKIP
    """
    path = _check_path(path)
    size = _check_size(window_size)
    if field not in grid.point_data:
        raise ValueError(f"field: the results hold {', '.join(grid.point_data.keys())}, not {field!r}")
    pv = _pyvista()
    disp = np.asarray(grid.point_data["DISP"]) if "DISP" in grid.point_data else np.zeros((grid.n_points, 3))
    diag = float(np.linalg.norm(np.subtract(grid.bounds[1::2], grid.bounds[::2])))
    umax = float(np.linalg.norm(disp, axis=1).max(initial=0.0))
    scale = SHOWN_DISPLACEMENT * diag / umax if umax > 0 else 0.0
    warped = grid.copy()
    warped.points = np.asarray(grid.points) + scale * disp
    plotter = pv.Plotter(off_screen=True, window_size=size)
    plotter.set_background("white")
    plotter.add_mesh(grid.extract_surface(algorithm="dataset_surface").extract_feature_edges(30.0), color="#888888", line_width=1)
    plotter.add_mesh(warped.extract_surface(algorithm="dataset_surface"), scalars=field, cmap="jet", show_edges=False,
                     scalar_bar_args={"title": f"{field.replace('_', ' ')}\n(max {float(np.max(grid.point_data[field])):.4g})",
                                      "color": "black", "vertical": True, "position_x": 0.86,
                                      "position_y": 0.15, "height": 0.7})
    plotter.add_text(f"displacement x {scale:.3g} (max {umax:.4g})", font_size=10, color="black")
    centre = np.asarray(grid.center)
    d = np.asarray(view, dtype=np.float64)
    plotter.camera_position = [tuple(centre + 2.2 * diag * d / np.linalg.norm(d)), tuple(centre), (0.0, 0.0, 1.0)]
    plotter.reset_camera()
    image = plotter.screenshot(return_img=True)
    plotter.close()
    if path is not None:
        _write_png_atomically(image, path)
    return image
