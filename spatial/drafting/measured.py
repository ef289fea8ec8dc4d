"""What a drawing measures where the CSG tree knows nothing: holes and arcs
from sections of the part, sizes from its mesh.

A part read from an STL (`mesh_to_solid`), or a solid whose holes come from
a sweep or a generic field, has no cylinder leaves to report.  Here the
part is cut by planes across each axis (`spatial.analysis.section`), a
circle is fitted to every loop (an algebraic fit, then Gauss-Newton steps
on the geometric distances: the exact least-squares circle), and

* hole loops that are circles, on the same axis in several cuts and open
  along that whole axis line, are through holes: `AxialFeature` cylinders
  like the tree's, so they get the same callouts (``4x ⌀8``, positions);
* runs of an outline that turn at one steady rate are arcs: their radii
  are fillets and rounds (``R5``).

Measured values carry the mesh's error; they are rounded to `step_for`
the voxel size, the drawing's precision for them.

Examples
--------
>>> import numpy as np
>>> t = np.linspace(0, 2 * np.pi, 50, endpoint=False)
>>> c, r, rms = fit_circle(np.column_stack([3 + 2 * np.cos(t), -1 + 2 * np.sin(t)]))
>>> np.round(c, 9).tolist(), round(r, 9)
([3.0, -1.0], 2.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .csg_features import AxialFeature, leaves

__all__ = ["fit_circle", "fit_arcs", "step_for", "snap", "snap_to_holes", "is_measured", "measured_holes", "Arc",
           "section_arcs", "MEASURED_KINDS"]

#: Leaves whose bounds and surfaces the tree does not state exactly: the drawing measures them.
MEASURED_KINDS = frozenset({"grid", "sweep_curve", "star_solid", "surface_solid", "volume_solid",
                            "thicken_surface"})

#: Cuts across each axis, as fractions of the part's extent along it.
CUTS = (0.13, 0.31, 0.5, 0.69, 0.87)

#: A loop is a circle when its points lie within this share of the radius of the fit (rms).
CIRCLE_RMS = 0.01

#: Rounding steps of measured values (model units, times powers of ten).
_STEPS = (1.0, 2.0, 5.0)


def is_measured(solid) -> bool:
    """True when some leaf of `solid` is a mesh, a sweep or another field the tree cannot size."""
    return any(leaf.node.kind in MEASURED_KINDS for leaf in leaves(solid))


def step_for(h: float) -> float:
    """The drawing's precision for a value measured on a mesh of voxel `h`:
    the smallest of 1, 2, 5 times a power of ten that is at least ``h / 4``."""
    target = max(float(h) / 4.0, 1e-12)
    exp = np.floor(np.log10(target))
    for k in range(2):
        for s in _STEPS:
            step = s * 10.0 ** (exp + k)
            if step >= target * (1 - 1e-9):
                return float(step)
    return float(10.0 ** (exp + 1))


def snap(values, step: float):
    """`values` rounded to multiples of `step` (arrays kept as arrays)."""
    return np.round(np.asarray(values, dtype=float) / step) * step


def fit_circle(points) -> tuple[np.ndarray, float, float]:
    """The least-squares circle through 2-D `points`: ``(centre, radius, rms distance)``.

    Kasa's algebraic fit (linear least squares on ``x^2 + y^2 + D x + E y + F = 0``)
    starts Gauss-Newton iterations on the geometric residuals ``|p - c| - r``,
    which converge to the circle minimising the sum of squared distances.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3:
        raise ValueError(f"points: expected (n, 2) with n >= 3, got shape {p.shape}")
    mean = p.mean(axis=0)
    q = p - mean
    a = np.column_stack([q, np.ones(len(q))])
    sol, *_ = np.linalg.lstsq(a, (q ** 2).sum(axis=1), rcond=None)
    c = 0.5 * sol[:2]
    r = float(np.sqrt(max(sol[2] + c @ c, 0.0)))
    for _ in range(20):
        d = q - c
        dist = np.linalg.norm(d, axis=1)
        dist = np.where(dist > 0, dist, 1e-300)
        res = dist - r
        jac = np.column_stack([-d / dist[:, None], -np.ones(len(q))])
        step, *_ = np.linalg.lstsq(jac, -res, rcond=None)
        c = c + step[:2]
        r = r + float(step[2])
        if np.abs(step).max() < 1e-13 * max(r, 1.0):
            break
    dist = np.linalg.norm(q - c, axis=1)
    return c + mean, abs(r), float(np.sqrt(np.mean((dist - abs(r)) ** 2)))


@dataclass(frozen=True)
class Arc:
    """An arc of a section outline: centre and a mid point in space, its radius,
    the angle it turns (radians) and whether it is concave (a fillet in a corner)."""

    centre: np.ndarray
    mid: np.ndarray
    radius: float
    turn: float
    concave: bool


def fit_arcs(loop, h: float, *, min_turn: float = np.radians(30.0)):
    """Arcs of a closed 2-D `loop` (counter-clockwise around material):
    ``[(centre (2,), mid point (2,), radius, turn, concave)]``.

    The turning angle per unit length is the curvature; runs of points where
    it keeps one sign and stays within a factor two of its median, turning
    at least `min_turn` in all, are arcs, and a circle is fitted to each.
    Straight runs (curvature below a tenth of ``1 / h``'s scale of noise)
    end them.
    """
    p = np.asarray(loop, dtype=float)
    n = len(p)
    if n < 8:
        return []
    seg = np.roll(p, -1, axis=0) - p
    length = np.linalg.norm(seg, axis=1)
    ang = np.arctan2(seg[:, 1], seg[:, 0])
    turn = (ang - np.roll(ang, 1) + np.pi) % (2 * np.pi) - np.pi   # at each point
    ds = 0.5 * (length + np.roll(length, 1))
    kappa = turn / np.maximum(ds, 1e-300)
    # Smooth over a voxel or so: the contour's steps wiggle point by point.
    w = max(1, int(round(1.5 * h / max(float(np.median(length)), 1e-300))))
    kernel = np.ones(2 * w + 1) / (2 * w + 1)
    k_s = np.convolve(np.concatenate([kappa[-w:], kappa, kappa[:w]]), kernel, mode="valid")
    curved = np.abs(k_s) > 0.02 / h
    sign = np.sign(k_s) * curved
    if sign.all() or not sign.any():
        return []
    # Runs of one sign, starting after a change so that no run wraps round the end.
    start = int(np.flatnonzero(sign != np.roll(sign, 1))[0])
    order = np.roll(np.arange(n), -start)
    s = sign[order]
    cut = np.flatnonzero(np.diff(s) != 0) + 1
    out = []
    for run in np.split(order, cut):  # one step per run of the outline, not per point
        if sign[run[0]] == 0 or len(run) < 5:
            continue
        total = float(np.abs(turn[run]).sum())
        if total < min_turn:
            continue
        # Leave the run's ends, where the outline bends into the neighbouring flats.
        trim = max(1, len(run) // 8)
        core = run[trim:-trim] if len(run) > 2 * trim + 3 else run
        c, r, rms = fit_circle(p[core])
        if rms > 0.05 * r + 0.05 * h or r > 50 * h * 10:
            continue
        mid = p[run[len(run) // 2]]
        out.append((c, mid, float(r), total, bool(sign[run[0]] < 0)))
    return out


def _cut_levels(lo, hi, axis, mesh, h):
    """Where to cut across `axis`: fixed fractions of the extent, and half way between the
    levels of the mesh's faces square to the axis (a thin leg of a bracket is cut through its middle)."""
    levels = list(lo[axis] + np.asarray(CUTS) * (hi[axis] - lo[axis]))
    if mesh is not None and mesh.n_cells:
        tri = mesh.compute_normals(cell_normals=True, point_normals=False)
        n = np.asarray(tri.cell_data["Normals"])
        centres = np.asarray(tri.cell_centers().points)
        flat = np.abs(n[:, axis]) > 0.999
        z = np.unique(np.round(centres[flat, axis] / h))
        z = z[np.concatenate([[True], np.diff(z) > 2])] * h
        mids = 0.5 * (z[1:] + z[:-1])
        levels += [m for m in mids if m - (z[z < m].max()) > 1.5 * h]
    return sorted(levels)


def _sections(solid, lo, hi, axis, resolution, mesh=None, h=1.0):
    from ..analysis.section import section

    normal = np.eye(3)[axis]
    out = []
    for level in _cut_levels(lo, hi, axis, mesh, h):
        point = 0.5 * (lo + hi)
        point[axis] = level
        try:
            s = section(solid, (point, normal), resolution=resolution)
        except Exception:  # noqa: BLE001 - a plane the sampler cannot handle gives nothing
            continue
        if not s.is_empty:
            out.append(s)
    return out


def measured_holes(solid, bounds, h: float, *, known=(), resolution: int = 256, mesh=None) -> list[AxialFeature]:
    """Through holes along x, y and z found in sections of `solid`, as cylinders.

    Parameters
    ----------
    solid : implicit.Solid
    bounds : ((3,), (3,))
        The part's extent (the drawing mesh's).
    h : float
        The drawing mesh's voxel: values are rounded to `step_for(h)`.
    known : list of AxialFeature
        The tree's features: holes they already give are not repeated.
    resolution : int
        Samples across each section.
    mesh : pyvista.PolyData, optional
        The part's mesh: its faces square to an axis add cuts between them.

    Returns
    -------
    list of AxialFeature
        ``negative=True`` cylinders spanning the part along their axis.
    """
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    step = step_for(h)
    out = []
    for axis in range(3):
        circles = []   # (centre3, radius)
        for sec in _sections(solid, lo, hi, axis, resolution, mesh, h):
            for loop, loop3, hole in zip(sec.loops, sec.loops3d, sec.holes):
                if not hole or len(loop) < 8:
                    continue
                c, r, rms = fit_circle(loop)
                if rms > CIRCLE_RMS * r + 0.05 * sec.voxel_size:
                    continue
                centre3 = sec.point + c[0] * sec.frame[0] + c[1] * sec.frame[1]
                circles.append((None, centre3, r))
        if not circles:
            continue
        centres = np.array([c[1] for c in circles])
        radii = np.array([c[2] for c in circles])
        # Circles of the cuts that share an axis line and a radius are one hole.
        flat = centres.copy()
        flat[:, axis] = 0.0
        taken = np.zeros(len(circles), dtype=bool)
        for j in range(len(circles)):  # one step per circle found, a handful
            if taken[j]:
                continue
            same = (~taken) & (np.linalg.norm(flat - flat[j], axis=1) < 2 * h) & (np.abs(radii - radii[j]) < 2 * h)
            taken |= same
            centre = flat[same].mean(axis=0)
            centre[axis] = 0.5 * (lo[axis] + hi[axis])
            blind = None
            if not _open_along(solid, centre, axis, lo, hi, h):
                blind = _blind_depth(solid, centre, axis, lo, hi, h)
                if blind is None:
                    continue
            diameter = float(snap(2 * np.median(radii[same]), step))
            centre = snap(centre, step)
            centre[axis] = 0.5 * (lo[axis] + hi[axis])
            direction = np.eye(3)[axis]
            if any(_same_hole(f, centre, direction, diameter, h) for f in known):
                continue
            start, stop = _wall_span(solid, centre, axis, diameter / 2, lo, hi, h)
            depth = None
            if blind is not None:
                depth, bottom, sign = blind
                # The hole runs from its face to its bottom only.
                start, stop = (start, bottom - centre[axis]) if sign < 0 else (bottom - centre[axis], stop)
                depth = float(snap(depth, step))
            out.append(AxialFeature("cylinder", centre, direction, diameter, stop - start, start, stop, True,
                                    depth=depth))
    return out


def _wall_span(solid, centre, axis, r, lo, hi, h):
    """From `centre` along `axis`, the stretch where material rings the hole (its wall)."""
    t = np.linspace(lo[axis], hi[axis], 97)
    e = np.eye(3)[[(axis + 1) % 3, (axis + 2) % 3]]
    ang = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = (r + 1.5 * h) * (np.cos(ang)[:, None] * e[0] + np.sin(ang)[:, None] * e[1])
    pts = np.repeat(centre[None], len(t), axis=0)
    pts[:, axis] = t
    probe = (pts[:, None, :] + ring[None]).reshape(-1, 3)
    wall = (np.asarray(solid(probe)) < 0).reshape(len(t), len(ang)).any(axis=1)
    if not wall.any():
        return -0.5 * (hi[axis] - lo[axis]), 0.5 * (hi[axis] - lo[axis])
    k = np.flatnonzero(wall)
    mid = centre[axis]
    return float(t[k[0]] - mid), float(t[k[-1]] - mid)


def _blind_depth(solid, centre, axis, lo, hi, h):
    """A hole open at one end of the line through `centre` along `axis` and stopped inside:
    ``(depth from the face, bottom level, +1 / -1 for the end it opens at)``, or None.

    The face is the part's extent at that end (a plate's face); the bottom is where
    the line itself meets material."""
    n = max(64, int(np.ceil((hi[axis] - lo[axis] + 2 * h) / (0.1 * h))))
    t = np.linspace(lo[axis] - h, hi[axis] + h, n)
    pts = np.repeat(centre[None], len(t), axis=0)
    pts[:, axis] = t
    inside = np.asarray(solid(pts)) < 0
    if not inside.any():
        return None
    first, last = int(np.argmax(inside)), len(t) - 1 - int(np.argmax(inside[::-1]))
    # Depth from the end with the longer open run: that is where the drill went in.
    runs = ((t[first] - lo[axis], t[first], -1), (hi[axis] - t[last], t[last], +1))
    depth_lo, depth_hi = runs[0][0], runs[1][0]
    if max(depth_lo, depth_hi) < 2 * h:
        return None
    depth, bottom, sign = runs[0] if depth_lo >= depth_hi else runs[1]
    return float(depth), float(bottom), sign


def _open_along(solid, centre, axis, lo, hi, h) -> bool:
    """True when the line through `centre` along `axis` stays outside the part: a through hole."""
    t = np.linspace(lo[axis] - h, hi[axis] + h, 64)
    pts = np.repeat(centre[None], len(t), axis=0)
    pts[:, axis] = t
    return bool((np.asarray(solid(pts)) > 0).all())


def _same_hole(f: AxialFeature, centre, direction, diameter, h) -> bool:
    if abs(abs(float(f.axis @ direction)) - 1.0) > 1e-6 or abs(f.diameter - diameter) > 2 * h:
        return False
    off = centre - f.centre
    off = off - (off @ direction) * direction
    return float(np.linalg.norm(off)) < 2 * h


def section_arcs(solid, bounds, h: float, *, axis: int, resolution: int = 256) -> list[Arc]:
    """Arcs of the outlines of the middle section across `axis` (fillets, rounds, bends)."""
    from ..analysis.section import section

    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    point = 0.5 * (lo + hi)
    sec = section(solid, (point, np.eye(3)[axis]), resolution=resolution)
    out = []
    for loop, hole in zip(sec.loops, sec.holes):
        if hole:
            continue
        for c, mid, r, turn, concave in fit_arcs(loop, sec.voxel_size):
            if r < 4 * h:
                continue  # a corner the mesh rounded, not an arc of the part
            c3 = sec.point + c[0] * sec.frame[0] + c[1] * sec.frame[1]
            m3 = sec.point + mid[0] * sec.frame[0] + mid[1] * sec.frame[1]
            out.append(Arc(c3, m3, r, turn, concave))
    return out


def snap_to_holes(points, holes, reach: float) -> np.ndarray:
    """`points` ``(k, 3)`` within `reach` of a hole's wall moved radially onto it."""
    p = np.array(points, dtype=float)
    for f in holes:  # one step per hole
        rel = p - f.centre
        t = rel @ f.axis
        radial = rel - t[:, None] * f.axis
        dist = np.linalg.norm(radial, axis=1)
        r = f.diameter / 2
        near = (np.abs(dist - r) < reach) & (t >= f.start - reach) & (t <= f.stop + reach) & (dist > 0)
        p[near] = f.centre + t[near, None] * f.axis + radial[near] * (r / dist[near])[:, None]
    return p
