"""Placing views on a sheet: a grid of columns and rows, views aligned with
their neighbours (front and top share x, front and side share the height),
room around each view for its dimensions, and the largest standard scale
at which it all fits.

Examples
--------
>>> cells = {"front": ((0, 0), (-20, -5, 20, 5), (10, 10, 10, 10)),
...          "top": ((0, 1), (-20, -10, 20, 10), (10, 10, 10, 10))}
>>> scale, places = place_grid(cells, (0, 0, 200, 200))
>>> scale, places["front"][0] == places["top"][0]
(2.0, True)
"""

from __future__ import annotations

import numpy as np

from .views import choose_scale

__all__ = ["place_grid", "ViewPlace"]


class ViewPlace:
    """Where a view sits: sheet ``X = x + s (u - umin)``, ``Y = y + s (vmax - v)``."""

    __slots__ = ("x", "y", "scale", "extent")

    def __init__(self, x, y, scale, extent):
        self.x, self.y, self.scale, self.extent = float(x), float(y), float(scale), tuple(float(e) for e in extent)

    def __getitem__(self, i):
        return (self.x, self.y)[i]

    def to_sheet(self, uv):
        uv = np.asarray(uv, dtype=float)
        out = np.empty(uv.shape)
        out[..., 0] = self.x + self.scale * (uv[..., 0] - self.extent[0])
        out[..., 1] = self.y + self.scale * (self.extent[3] - uv[..., 1])
        return out

    def box(self):
        """(x0, y0, x1, y1) of the view's extent on the sheet."""
        umin, vmin, umax, vmax = self.extent
        return (self.x, self.y, self.x + self.scale * (umax - umin), self.y + self.scale * (vmax - vmin))


def _sizes(cells, scale):
    """Per column and row: aligned size, margins and the total an unaligned (iso) view needs."""
    cols = max(c[0][0] for c in cells.values()) + 1
    rows = max(c[0][1] for c in cells.values()) + 1
    width, height = np.zeros(cols), np.zeros(rows)
    left, right, top, bottom = np.zeros(cols), np.zeros(cols), np.zeros(rows), np.zeros(rows)
    free_w, free_h = np.zeros(cols), np.zeros(rows)
    for name, ((col, row), ext, (ml, mr, mt, mb)) in cells.items():
        w, h = scale * (ext[2] - ext[0]), scale * (ext[3] - ext[1])
        if name == "iso":
            free_w[col] = max(free_w[col], w + ml + mr)
            free_h[row] = max(free_h[row], h + mt + mb)
            continue
        width[col], height[row] = max(width[col], w), max(height[row], h)
        left[col], right[col] = max(left[col], ml), max(right[col], mr)
        top[row], bottom[row] = max(top[row], mt), max(bottom[row], mb)
    total_w = np.maximum(width + left + right, free_w)
    total_h = np.maximum(height + top + bottom, free_h)
    return total_w, total_h, left, top


def place_grid(cells: dict, area, *, scale=None, unit_mm: float = 1.0):
    """Scale and places of views in a grid.

    Parameters
    ----------
    cells : dict
        view -> ((column, row), (umin, vmin, umax, vmax), (left, right, top, bottom) margins in mm).
    area : (x0, y0, x1, y1)
        Free sheet area (mm).
    scale : float, optional
        A fixed scale (paper mm per model unit); by default the largest that fits
        among the ISO 5455 ratios.
    unit_mm : float
        Millimetres in one model unit: the standard ratios are true sizes.

    Returns
    -------
    (scale, {view: ViewPlace})
    """
    x0, y0, x1, y1 = area
    aw, ah = x1 - x0, y1 - y0

    def fits(s):
        tw, th, _, _ = _sizes(cells, s)
        return tw.sum() <= aw and th.sum() <= ah

    s = choose_scale(lambda r: fits(r * unit_mm)) * unit_mm if scale is None else float(scale)
    tw, th, left, top = _sizes(cells, s)
    # The spare room is shared out evenly around and between columns and rows.
    gap_x = max(0.0, aw - tw.sum()) / (len(tw) + 1)
    gap_y = max(0.0, ah - th.sum()) / (len(th) + 1)
    cell_x = x0 + gap_x + np.concatenate([[0], np.cumsum(tw + gap_x)[:-1]])
    cell_y = y0 + gap_y + np.concatenate([[0], np.cumsum(th + gap_y)[:-1]])
    places = {}
    for name, ((col, row), ext, _) in cells.items():
        vw, vh = s * (ext[2] - ext[0]), s * (ext[3] - ext[1])
        if name == "iso":
            # The pictorial view needs no alignment: centred in its cell.
            x, y = cell_x[col] + 0.5 * (tw[col] - vw), cell_y[row] + 0.5 * (th[row] - vh)
        else:
            x, y = cell_x[col] + left[col], cell_y[row] + top[row]
        places[name] = ViewPlace(x, y, s, ext)
    return s, places
