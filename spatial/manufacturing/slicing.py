"""Layer slices of a solid for additive manufacturing.

`slice(solid, layer=H)` cuts the part by horizontal planes at the middle of
each layer of height `H` (``z_i = z_bottom + (i + 1/2) H``) and keeps, for
every layer, the closed contours of the section: outer loops counter-clockwise
seen from +z, holes clockwise.  Each plane is an exact section of the solid
(`analysis.section`: sampled, contoured by scikit-image's ``find_contours``,
moved onto the true zero level by Newton steps), so a layer's area carries the
section's accuracy, and ``sum(area_i) * H`` is the midpoint rule of the part's
volume: for a sphere of radius R its error is exactly ``pi R H^2 / 6``
(``-(b - a) H^2 f'' / 24`` with ``f = pi (R^2 - z^2)``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

__all__ = ["Layer", "Slices", "slice"]

#: Samples across a layer's section (the section's default).
DEFAULT_RESOLUTION = 256
#: At most this many layers (a guard against a layer height given in the wrong unit).
MAX_LAYERS = 20000


@dataclass(frozen=True)
class Layer:
    """One layer: the section at its mid-height.

    Attributes
    ----------
    z : float
        Height of the cutting plane (middle of the layer).
    area : float
        Area of material in the plane.
    loops : list of (k, 2) float
        Closed contours in (x, y), first point not repeated; outer loops
        counter-clockwise, holes clockwise.
    holes : list of bool
        True for a loop bounding a hole.
    """

    z: float
    area: float
    loops: list
    holes: list

    def to_dict(self) -> dict:
        """Plain-Python form for JSON."""
        return {"z": self.z, "area": self.area,
                "loops": [{"hole": bool(h), "orientation": "cw" if h else "ccw", "points": lp.tolist()}
                          for lp, h in zip(self.loops, self.holes)]}


@dataclass(frozen=True)
class Slices:
    """The layers of a sliced part.

    Attributes
    ----------
    layer : float
        Layer height.
    z_bottom, z_top : float
        The part's extent along z that the layers cover.
    layers : list of Layer
        Bottom to top.
    volume : float
        ``sum(area) * layer``: the part's volume by the midpoint rule.
    voxel_size : float
        Sampling step in each plane.
    """

    layer: float
    z_bottom: float
    z_top: float
    layers: list
    volume: float
    voxel_size: float

    def to_dict(self) -> dict:
        """``{"layer", "z_bottom", "z_top", "volume", "layers": [{"z", "area", "loops"}]}``."""
        return {"layer": self.layer, "z_bottom": self.z_bottom, "z_top": self.z_top, "volume": self.volume,
                "voxel_size": self.voxel_size, "layers": [ly.to_dict() for ly in self.layers]}

    def to_json(self) -> str:
        """The JSON text of `to_dict`."""
        return json.dumps(self.to_dict())

    def to_csv(self) -> str:
        """One row per contour point: ``layer,z,loop,hole,x,y``."""
        rows = ["layer,z,loop,hole,x,y"]
        for i, ly in enumerate(self.layers):
            for j, (lp, h) in enumerate(zip(ly.loops, ly.holes)):
                head = f"{i},{ly.z:.9g},{j},{int(h)},"
                rows.extend(head + f"{x:.9g},{y:.9g}" for x, y in lp)
        return "\n".join(rows) + "\n"

    def to_svg(self, *, columns: int | None = None, cell_px: float = 220.0) -> str:
        """Every layer drawn in a grid of panels (even-odd fill keeps holes empty)."""
        n = len(self.layers)
        if n == 0:
            return '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"/>\n'
        pts = [lp for ly in self.layers for lp in ly.loops]
        allp = np.concatenate(pts) if pts else np.zeros((1, 2))
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        span = float(max(hi - lo)) or 1.0
        cols = columns or int(np.ceil(np.sqrt(n)))
        rows_n = int(np.ceil(n / cols))
        scale = 0.86 * cell_px / span
        out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * cell_px:.0f}" '
               f'height="{rows_n * cell_px:.0f}" font-family="sans-serif" font-size="11">',
               f'<!-- {n} layers of height {self.layer:g}; volume {self.volume:.9g}; '
               f'1 model unit = {scale:.6g} px -->']
        for i, ly in enumerate(self.layers):
            ox, oy = (i % cols) * cell_px, (i // cols) * cell_px
            paths = []
            for lp in ly.loops:
                xy = (lp - lo) * scale + 0.07 * cell_px
                px = ox + xy[:, 0]
                py = oy + cell_px - xy[:, 1]                 # SVG's y axis points down
                paths.append("M " + " L ".join(f"{a:.2f},{b:.2f}" for a, b in zip(px, py)) + " Z")
            out.append(f'<rect x="{ox:.1f}" y="{oy:.1f}" width="{cell_px:.1f}" height="{cell_px:.1f}" '
                       f'fill="none" stroke="#ccc"/>')
            if paths:
                out.append(f'<path d="{" ".join(paths)}" fill="#9ab" fill-rule="evenodd" stroke="#123"/>')
            out.append(f'<text x="{ox + 4:.1f}" y="{oy + 13:.1f}">z={ly.z:.4g}  A={ly.area:.4g}</text>')
        out.append("</svg>")
        return "\n".join(out) + "\n"


def _extent_z(solid, resolution):
    """The solid's true z extent: its bounds shrunk to where material is.

    Columns of samples find the lowest and highest inside samples; bisection
    on the planes next to them then locates the extremes to 1e-9 of the size.
    """
    lo, hi = solid.bounds
    n = max(32, min(resolution, 128))
    xs = np.linspace(lo[0], hi[0], n)
    ys = np.linspace(lo[1], hi[1], n)
    zs = np.linspace(lo[2], hi[2], n + 1)
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    f = solid(np.stack([X, Y, Z], axis=-1).reshape(-1, 3)).reshape(X.shape)
    inside = (f < 0).any(axis=(0, 1))
    if not inside.any():
        return None
    k0, k1 = int(np.argmax(inside)), int(len(zs) - 1 - np.argmax(inside[::-1]))
    dz = zs[1] - zs[0]
    # the extremes are within one sample step of the first/last inside plane;
    # a plane's minimum (over a fine in-plane grid) changes sign there
    fine = max(64, resolution) | 1          # odd: the centre line of symmetric bounds is sampled
    gx = np.linspace(lo[0], hi[0], fine)
    gy = np.linspace(lo[1], hi[1], fine)
    GX, GY = np.meshgrid(gx, gy, indexing="ij")
    xy = np.column_stack([GX.ravel(), GY.ravel()])

    def plane_min(z):
        return float(solid(np.column_stack([xy, np.full(len(xy), z)])).min())

    def bisect(a, b):          # plane_min(a) >= 0 > plane_min(b)
        for _ in range(40):
            m = 0.5 * (a + b)
            if plane_min(m) < 0:
                b = m
            else:
                a = m
        return 0.5 * (a + b)

    bottom = bisect(zs[k0] - dz, zs[k0]) if plane_min(zs[k0] - dz) >= 0 else lo[2]
    top = bisect(zs[k1] + dz, zs[k1]) if plane_min(zs[k1] + dz) >= 0 else hi[2]
    snap = 1e-9 * float(np.max(hi - lo))
    bottom = lo[2] if abs(bottom - lo[2]) < snap else bottom        # tight bounds: keep their digits
    top = hi[2] if abs(top - hi[2]) < snap else top
    return float(bottom), float(top)


def slice(solid, layer: float, *, resolution: int = DEFAULT_RESOLUTION, z_range=None) -> Slices:  # noqa: A001
    """Cut `solid` into horizontal layers of height `layer`.

    Parameters
    ----------
    solid : Solid
        A bounded solid.
    layer : float
        Layer height (> 0).
    resolution : int
        Samples across each section (see `analysis.section`).
    z_range : (float, float), optional
        The z interval to slice (default: the part's true z extent, found
        by sampling and bisection).

    Returns
    -------
    Slices

    Examples
    --------
    >>> from implicit import box
    >>> s = slice(box(1.0), layer=0.25)
    >>> len(s.layers), round(s.volume, 6)
    (4, 1.0)
    """
    from implicit import Solid
    from implicit.solid import as_positive

    from ..analysis.section import section

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if not solid.is_bounded:
        raise ValueError("solid: expected a bounded solid, got infinite bounds")
    H = as_positive(layer, "layer")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 8:
        raise ValueError(f"resolution: expected an integer of at least 8, got {resolution!r}")
    if z_range is None:
        ext = _extent_z(solid, resolution)
        if ext is None:
            return Slices(H, 0.0, 0.0, [], 0.0, 0.0)
        z0, z1 = ext
    else:
        if not isinstance(z_range, (tuple, list)) or len(z_range) != 2:
            raise TypeError(f"z_range: expected (z_min, z_max), got {z_range!r}")
        z0, z1 = float(z_range[0]), float(z_range[1])
        if not (np.isfinite(z0) and np.isfinite(z1) and z1 > z0):
            raise ValueError(f"z_range: expected finite z_min < z_max, got {z_range!r}")
    n = int(np.ceil((z1 - z0) / H - 1e-9))
    if n > MAX_LAYERS:
        raise ValueError(f"layer: {H:g} gives {n} layers over a height of {z1 - z0:g} (at most {MAX_LAYERS})")
    lo, hi = solid.bounds
    h = float(max(hi[0] - lo[0], hi[1] - lo[1])) / resolution
    layers = []
    for i in range(max(n, 1)):
        z = z0 + (i + 0.5) * H
        # a plane exactly on a flat face samples zeros: look a hair above it
        sec = section(solid, f"z={z + 1e-9 * H!r}", voxel_size=h)
        layers.append(Layer(float(z), float(sec.area), [lp.copy() for lp in sec.loops], list(sec.holes)))
    volume = float(sum(ly.area for ly in layers) * H)
    return Slices(H, float(z0), float(z1), layers, volume, h)
