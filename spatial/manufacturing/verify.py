"""Verification of a milling program by material removal on a dexel grid.

The stock is a grid of vertical columns (dexels, Van Hook 1986), each one a
height: a flat end mill from +z only ever lowers a column's top, so one
height per column is exact for 3-axis flat-end milling.  Every move of the
G-code is cut into points at most half a column apart; at each point the
tool's disk stamps ``top = min(top, z)`` on every column whose centre lies
within the tool radius (``numpy.minimum.at``, in chunks).  The design is the
fractional occupancy ``clamp(1/2 - f / h, 0, 1)`` of voxel layers in each
column, integrated upwards, so the part's volume below any height of a
column is read off by interpolation.

Gouge is material removed more than `tolerance` inside the part (the part
shrunk by the tolerance); excess is material left more than `tolerance`
outside it (the part grown by the tolerance); the tolerance (default one
column width) absorbs the columns' own discretisation at the walls.  Both are
also reported per operation, with the volume removed by rapid moves
(collisions: it should be zero).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .gcode import ToolPath, path_points, read_gcode

__all__ = ["Verification", "verify", "removal_deviation"]

#: Columns across the stock's larger side.
DEFAULT_RESOLUTION = 128
#: Stamp points processed at once (times the disk's columns).
CHUNK = 2_000_000


@dataclass(frozen=True)
class Verification:
    """The result of `verify`.

    Attributes
    ----------
    gouge_volume, excess_volume : float
        Material removed inside the part / left outside it (beyond `tolerance`).
    removed_volume, stock_volume, part_volume : float
    rapid_volume : float
        Material removed by rapid moves (G0): a collision when positive.
    operations : list of dict
        ``name, removed, gouge, rapid`` per operation of the program.
    tolerance, column : float
        The band and the column width.
    xs, ys : (nx,), (ny,) float
        Column centres; `top` (nx, ny) their final heights.
    """

    gouge_volume: float
    excess_volume: float
    removed_volume: float
    stock_volume: float
    part_volume: float
    rapid_volume: float
    operations: list
    tolerance: float
    column: float
    xs: np.ndarray
    ys: np.ndarray
    top: np.ndarray
    z_bottom: float

    def to_dict(self) -> dict:
        return {"gouge_volume": self.gouge_volume, "excess_volume": self.excess_volume,
                "removed_volume": self.removed_volume, "stock_volume": self.stock_volume,
                "part_volume": self.part_volume, "rapid_volume": self.rapid_volume,
                "tolerance": self.tolerance, "column": self.column, "operations": self.operations}

    def table(self) -> str:
        """The per-operation table as text."""
        w = max([len("operation")] + [len(o["name"]) for o in self.operations])
        lines = [f"{'operation':<{w}}  {'removed':>12}  {'gouge':>12}  {'rapid cut':>12}"]
        for o in self.operations:
            lines.append(f"{o['name']:<{w}}  {o['removed']:12.6g}  {o['gouge']:12.6g}  {o['rapid']:12.6g}")
        lines.append(f"{'total':<{w}}  {self.removed_volume:12.6g}  {self.gouge_volume:12.6g}  "
                     f"{self.rapid_volume:12.6g}")
        lines.append(f"excess left outside the part (beyond {self.tolerance:.3g}): {self.excess_volume:.6g}")
        return "\n".join(lines)

    def stock_height(self, xy):
        """Final stock top at points (n, 2) (nearest column; -inf off the stock)."""
        xy = np.asarray(xy, dtype=float)
        h = self.column
        i = np.rint((xy[:, 0] - self.xs[0]) / h).astype(int)
        j = np.rint((xy[:, 1] - self.ys[0]) / h).astype(int)
        ok = (i >= 0) & (i < len(self.xs)) & (j >= 0) & (j < len(self.ys))
        out = np.full(len(xy), -np.inf)
        out[ok] = self.top[i[ok], j[ok]]
        return out


def _stamp(top, pts, xs, ys, h, r, offs):
    """Lower `top` under the tool's disk at every point (vectorized, chunked)."""
    nx, ny = top.shape
    flat = top.ravel()
    step = max(1, CHUNK // max(len(offs), 1))
    for s in range(0, len(pts), step):
        p = pts[s:s + step]
        i0 = np.rint((p[:, 0] - xs[0]) / h).astype(np.int64)
        j0 = np.rint((p[:, 1] - ys[0]) / h).astype(np.int64)
        I = i0[:, None] + offs[None, :, 0]
        J = j0[:, None] + offs[None, :, 1]
        ok = (I >= 0) & (I < nx) & (J >= 0) & (J < ny)
        dx = xs[np.clip(I, 0, nx - 1)] - p[:, 0:1]
        dy = ys[np.clip(J, 0, ny - 1)] - p[:, 1:2]
        ok &= dx * dx + dy * dy <= r * r
        z = np.broadcast_to(p[:, 2:3], I.shape)
        np.minimum.at(flat, (I * ny + J)[ok], z[ok])


def _column_integral(C, zb, hz, z):
    """Part volume per unit area below heights `z` (nx, ny) from cumulative layers C."""
    k = np.clip((z - zb) / hz, 0, C.shape[-1] - 1)
    k0 = np.minimum(np.floor(k).astype(int), C.shape[-1] - 2)
    t = k - k0
    c0 = np.take_along_axis(C, k0[..., None], axis=-1)[..., 0]
    c1 = np.take_along_axis(C, (k0 + 1)[..., None], axis=-1)[..., 0]
    return c0 + t * (c1 - c0)


def verify(solid, program, *, tool_radius=None, stock=None, resolution=DEFAULT_RESOLUTION,
           tolerance=None) -> Verification:
    """Simulate `program` on the stock and compare the result with `solid`.

    Parameters
    ----------
    solid : Solid
        The design.
    program : ToolPath or str
        A planned tool path (its G-code is what is simulated) or G-code text.
    tool_radius : float, optional
        The flat end mill's radius (default: the ToolPath's).
    stock : (lo, hi), optional
        The stock box (default: the ToolPath's).
    resolution : int
        Columns across the stock's larger side.
    tolerance : float, optional
        Gouge and excess count beyond this distance from the surface
        (default: one column width).

    Returns
    -------
    Verification

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.manufacturing import toolpath
    >>> part = box((3.0, 3.0, 1.0)) - box((1.0, 1.0, 2.0))
    >>> v = verify(part, toolpath(part, 0.2, resolution=48), resolution=48)
    >>> v.gouge_volume < 1e-3
    True
    """
    from implicit import Solid
    from implicit.solid import as_positive

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if isinstance(program, ToolPath):
        text = program.to_gcode()
        r = program.tool_radius if tool_radius is None else as_positive(tool_radius, "tool_radius")
        stock = program.stock if stock is None else stock
    elif isinstance(program, str):
        text = program
        if tool_radius is None:
            raise ValueError("tool_radius: give the tool's radius with G-code text")
        r = as_positive(tool_radius, "tool_radius")
        if stock is None:
            raise ValueError("stock: give the stock box (lo, hi) with G-code text")
    else:
        raise TypeError(f"program: expected a ToolPath or G-code text, got {type(program).__name__}")
    if not isinstance(stock, (tuple, list)) or len(stock) != 2:
        raise TypeError(f"stock: expected (lo, hi) corners, got {stock!r}")
    slo, shi = (np.asarray(c, dtype=float).reshape(3) for c in stock)
    if not np.all(shi > slo):
        raise ValueError(f"stock: expected lo < hi, got {stock!r}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 8 <= resolution <= 4096:
        raise ValueError(f"resolution: expected an integer in [8, 4096], got {resolution!r}")
    ops, start, _units = read_gcode(text)

    h = float(max(shi[0] - slo[0], shi[1] - slo[1])) / resolution
    xs = np.arange(slo[0] + h / 2, shi[0], h)
    ys = np.arange(slo[1] + h / 2, shi[1], h)
    nz = max(2, int(np.ceil((shi[2] - slo[2]) / h)))
    hz = (shi[2] - slo[2]) / nz
    tol = h if tolerance is None else as_positive(tolerance, "tolerance", allow_zero=True)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    zc = slo[2] + (np.arange(nz) + 0.5) * hz
    pts = np.stack(np.broadcast_arrays(X[..., None], Y[..., None], zc[None, None, :]), axis=-1)
    f = solid(pts.reshape(-1, 3)).reshape(pts.shape[:-1])
    area = h * h

    def cumulative(shift):
        phi = np.clip(0.5 - (f + shift) / hz, 0.0, 1.0) * hz
        return np.concatenate([np.zeros(X.shape + (1,)), np.cumsum(phi, axis=-1)], axis=-1)

    C = cumulative(0.0)
    C_in = cumulative(tol)          # the part shrunk by the tolerance
    C_out = cumulative(-tol)        # grown by it

    R = int(np.ceil(r / h)) + 1
    gi, gj = np.meshgrid(np.arange(-R, R + 1), np.arange(-R, R + 1), indexing="ij")
    offs = np.column_stack([gi.ravel(), gj.ravel()])
    offs = offs[(np.hypot(offs[:, 0], offs[:, 1]) - 1.5) * h <= r]
    top = np.full(X.shape, shi[2])
    table = []
    cur = start
    for name, moves in ops:
        pts_, feed = path_points(moves, cur, h / 2)
        cur = pts_[-1]
        before = top.copy()
        # in program order: runs of rapids and runs of cutting moves
        is_rapid = feed == 0
        cuts = np.flatnonzero(np.diff(is_rapid.astype(np.int8))) + 1
        rapid_cut = 0.0
        for run in np.split(np.arange(len(pts_)), cuts):
            run = run[pts_[run, 2] < shi[2]]
            if run.size == 0:
                continue
            if is_rapid[run[0]]:
                was = top.copy()
                _stamp(top, pts_[run], xs, ys, h, r, offs)
                rapid_cut += float((was - top).sum() * area)
            else:
                _stamp(top, pts_[run], xs, ys, h, r, offs)
        gouge = float((_column_integral(C_in, slo[2], hz, before)
                       - _column_integral(C_in, slo[2], hz, top)).sum() * area)
        table.append({"name": name, "removed": float((before - top).sum() * area), "gouge": gouge,
                      "rapid": rapid_cut})
    top = np.maximum(top, slo[2])
    full = _column_integral(C_in, slo[2], hz, np.full(X.shape, shi[2]))
    gouge = float((full - _column_integral(C_in, slo[2], hz, top)).sum() * area)
    excess = float(((top - slo[2]) - _column_integral(C_out, slo[2], hz, top)).sum() * area)
    stock_volume = float((shi[2] - slo[2]) * X.size * area)
    return Verification(gouge, max(excess, 0.0), float((shi[2] - top).sum() * area), stock_volume,
                        float(C[..., -1].sum() * area), float(sum(o["rapid"] for o in table)), table,
                        float(tol), h, xs, ys, top, float(slo[2]))


def removal_deviation(result: Verification, mesh, solid, *, reach=None, samples=24):
    """Per-vertex deviation of the machined stock from the design surface.

    Positive: thickness of material left outside the surface along the
    outward normal (excess); negative: depth of material removed inside it
    along the inward normal (gouge); both measured up to `reach`
    (default 6 columns) and zero within the result's tolerance.
    """
    pts = np.asarray(mesh.points, dtype=float)
    # the field's gradient picks one face at a sharp edge (a mesh normal would average them)
    g = solid.gradient(pts)
    n = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    reach = 6 * result.column if reach is None else float(reach)
    t = np.linspace(0.0, reach, samples)[1:]

    def material(q):
        top = result.stock_height(q[:, :2])
        return (q[:, 2] < top) & (q[:, 2] >= result.z_bottom)

    out = (pts[:, None, :] + t[None, :, None] * n[:, None, :]).reshape(-1, 3)
    inn = (pts[:, None, :] - t[None, :, None] * n[:, None, :]).reshape(-1, 3)
    # material left outside the design / removed inside it, along the normal
    left = (material(out) & (solid(out) > 0)).reshape(len(pts), -1)
    gone = (~material(inn) & (solid(inn) < 0)).reshape(len(pts), -1)
    # contiguous runs from the surface: the first False ends the run
    run_left = np.where(left.all(axis=1), len(t), np.argmin(left, axis=1))
    run_gone = np.where(gone.all(axis=1), len(t), np.argmin(gone, axis=1))
    ex = np.where(run_left > 0, t[np.maximum(run_left - 1, 0)], 0.0)
    go = np.where(run_gone > 0, t[np.maximum(run_gone - 1, 0)], 0.0)
    dev = np.where(go > ex, -go, ex)
    # within the tolerance band the columns' own staircase speaks, not the program
    return np.where(np.abs(dev) <= result.tolerance, 0.0, dev)
