"""2.5D milling tool paths for a flat end mill approaching from +z.

The planner works on the solid's own field, never on a polygon outline:

1. The part's top surface over a grid of (x, y) columns (sampling, then
   bisection to the true height) gives the *floors*: upward-facing flat faces,
   the heights the tool must reach exactly.  The cutting depths are the floors
   and the part's bottom, with intermediate step-downs no deeper than
   `step_down`.
2. At a depth ``z``, the tool may not touch anything of the part above ``z``:
   the *shadow* is the union of the part's sections by planes ``z' > z``
   (samples, every flat face and every depth, just above it).  Each section's
   boundary is the solid's exact zero level (`analysis.section`: contoured,
   then Newton steps onto the surface); its points, resampled densely, go into
   a KD-tree, so ``F(x, y)`` is the in-plane distance to the shadow (negative
   inside it).  A 3D distance would not do: just above a flat face it is the
   height above the face, not the distance to the wall.  The tool centre may
   go where ``G = min(F - r, E) >= 0``, ``E`` being the stock box grown by 0.9 r.
3. The passes are the level sets ``G = k s`` (step-over ``s <= r``): ``k = 0``
   is the finishing contour at exactly ``r`` from the part (the level ``+r`` of
   its distance field, each point moved onto it by Newton steps), ``k >= 1`` the
   pocketing offsets.  Every point of the region is within ``s`` of a pass, so
   the tool (radius ``r >= s``) sweeps it all.
4. Loops run with the uncut material on the cutter's right (climb milling with
   a clockwise spindle, M3) or on its left (conventional); each pass starts
   with a quarter-arc lead-in on the cleared side and ends with a lead-out;
   rapids cross the part at the safe height; plunges descend at the plunge feed
   from just above the previous depth.

Where the grid's samples miss a region the tool just fits (a hole barely
wider than the tool, seen at a coarse resolution), the tool plunges at its
middle instead.  Material the tool cannot reach - a hole, slot or pocket
narrower than the tool's diameter - is refused with its coordinates: where the region to clear
lies deeper than `leftover` x r from the part and out of the tool's reach.
(An inner corner of angle theta keeps a fillet of the tool radius whose
deepest point lies ``r (1 / sin(theta / 2) - 1)`` from the corner: 0.41 r at
90 degrees, under the default 0.5 r.)
"""

from __future__ import annotations

import numpy as np

from .contours import level_loops, newton_to_level
from .gcode import Operation, ToolPath

__all__ = ["toolpath", "part_floors"]

#: Grid samples across the larger side of the stock (plus the tool).
DEFAULT_RESOLUTION = 128
#: A column's top is on a flat face when its normal's z component exceeds this (0.8 degrees).
FLAT_NORMAL = 0.9999
#: Bisection steps for the top surface of each column.
BISECTIONS = 40


def _check_choice(value, name, choices):
    if value not in choices:
        raise ValueError(f"{name}: expected one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def _top_heights(solid, X, Y, zs):
    """Height of the part's top surface over each column (NaN: no material)."""
    pts = np.stack(np.broadcast_arrays(X[..., None], Y[..., None], zs[None, None, :]), axis=-1)
    f = solid(pts.reshape(-1, 3)).reshape(pts.shape[:-1])
    inside = f < 0
    has = inside.any(axis=-1)
    # highest inside sample, then bisection between it and the sample above
    k = len(zs) - 1 - np.argmax(inside[..., ::-1], axis=-1)
    lo = zs[k]
    hi = np.where(k + 1 < len(zs), zs[np.minimum(k + 1, len(zs) - 1)], zs[-1])
    top_inside = (k == len(zs) - 1)
    x, y = X[has], Y[has]
    a, b = lo[has], hi[has]
    for _ in range(BISECTIONS):
        m = 0.5 * (a + b)
        inn = solid(np.column_stack([x, y, m])) < 0
        a = np.where(inn, m, a)
        b = np.where(inn, b, m)
    H = np.full(X.shape, np.nan)
    H[has] = np.where(top_inside[has], zs[-1], 0.5 * (a + b))
    return H


def part_floors(heights, *, tol, min_columns=4):
    """Heights shared by at least `min_columns` columns (within `tol`): flat
    upward faces, highest first."""
    h = np.sort(heights[np.isfinite(heights)])[::-1]
    if h.size == 0:
        return []
    breaks = np.flatnonzero(np.abs(np.diff(h)) > tol) + 1
    groups = np.split(h, breaks)
    return [float(np.median(g)) for g in groups if g.size >= min_columns]


def _depths(top, floors, bottom, step_down, tol):
    targets = sorted({round(z, 12) for z in floors if bottom + tol < z < top - tol} | {bottom}, reverse=True)
    out, prev = [], top
    for t in targets:
        n = max(1, int(np.ceil((prev - t) / step_down - 1e-9)))
        out += [prev - (prev - t) * k / n for k in range(1, n)] + [t]
        prev = t
    return out


def _stock_field(sx0, sx1, sy0, sy1, e):
    def E(q):
        return np.minimum(np.minimum(q[..., 0] - (sx0 - e), (sx1 + e) - q[..., 0]),
                          np.minimum(q[..., 1] - (sy0 - e), (sy1 + e) - q[..., 1]))
    return E


def _narrow_features(F, G, inside_stock, h, r, leftover, z):
    """Regions to clear that no tool position reaches: their descriptions."""
    from scipy import ndimage

    allowed = G >= 0
    if allowed.any():
        reach = ndimage.distance_transform_edt(~allowed) * h <= r + 1.5 * h
    else:
        reach = np.zeros_like(allowed)
    lost = (F > leftover * r) & inside_stock & ~reach
    labels, n = ndimage.label(lost)
    return labels, n


def toolpath(solid, tool_radius, *, stepover=0.4, step_down=None, direction="climb", stock=None,
             safe_height=None, feed=600.0, plunge_feed=None, spindle=10000.0, units="mm",
             resolution=DEFAULT_RESOLUTION, leftover=0.5, title="part") -> ToolPath:
    """Plan 2.5D pocketing and profile passes around `solid` seen from +z.

    Parameters
    ----------
    solid : Solid
        The part (bounded); undercuts are left (a flat end mill from +z
        cannot reach them).
    tool_radius : float
        Radius r of the flat end mill.
    stepover : float
        Distance between successive offsets as a fraction of the tool
        diameter, in (0, 0.5] (so that no material is left between passes).
    step_down : float, optional
        Largest depth of one cut (default: r).
    direction : {"climb", "conventional"}
    stock : (lo, hi), optional
        The stock box (default: the solid's bounds in x, y and its true
        extent in z).
    safe_height : float, optional
        Height of rapids (default: stock top + max(2 r, 5 % of the stock size)).
    feed, plunge_feed : float
        Feeds per minute (plunge default: feed / 3).
    spindle : float
        Spindle speed, rev/min.
    units : {"mm", "inch"}
        Units of the model: G21 or G20.
    resolution : int
        Grid samples across the stock's larger side.
    leftover : float
        Material deeper than ``leftover * r`` from the part that the tool
        cannot reach is refused (see the module notes).

    Returns
    -------
    ToolPath

    Raises
    ------
    ValueError
        Bad arguments, or a feature narrower than the tool: the message gives
        its depth, centre and extent.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> part = box((4.0, 3.0, 1.0)) - cylinder(0.8, 4)
    >>> tp = toolpath(part, 0.25, resolution=64)
    >>> [op.kind for op in tp.operations][:2]
    ['pocket', 'profile']
    """
    from implicit import Solid
    from implicit.solid import as_positive

    from .slicing import _extent_z

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    if not solid.is_bounded:
        raise ValueError("solid: expected a bounded solid, got infinite bounds")
    r = as_positive(tool_radius, "tool_radius")
    so = as_positive(stepover, "stepover")
    if so > 0.5:
        raise ValueError(f"stepover: expected a fraction of the tool diameter in (0, 0.5], got {stepover!r}")
    s = so * 2 * r
    dz_max = r if step_down is None else as_positive(step_down, "step_down")
    _check_choice(direction, "direction", ("climb", "conventional"))
    _check_choice(units, "units", ("mm", "inch"))
    feed = as_positive(feed, "feed")
    plunge = feed / 3 if plunge_feed is None else as_positive(plunge_feed, "plunge_feed")
    spindle = as_positive(spindle, "spindle")
    leftover = as_positive(leftover, "leftover")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 16 <= resolution <= 2048:
        raise ValueError(f"resolution: expected an integer in [16, 2048], got {resolution!r}")
    blo, bhi = (np.asarray(b, dtype=float) for b in solid.bounds)
    if stock is None:
        ext = _extent_z(solid, 64)
        if ext is None:
            raise ValueError("solid: no material found inside its bounds")
        slo = np.array([blo[0], blo[1], ext[0]])
        shi = np.array([bhi[0], bhi[1], ext[1]])
    else:
        if not isinstance(stock, (tuple, list)) or len(stock) != 2:
            raise TypeError(f"stock: expected (lo, hi) corners, got {stock!r}")
        slo, shi = (np.asarray(c, dtype=float).reshape(3) for c in stock)
        if not (np.all(np.isfinite(slo)) and np.all(np.isfinite(shi)) and np.all(shi > slo)):
            raise ValueError(f"stock: expected finite corners with lo < hi, got {stock!r}")
    size = float(np.max(shi - slo))
    safe_z = shi[2] + max(2 * r, 0.05 * size) if safe_height is None else float(safe_height)
    if not safe_z > shi[2]:
        raise ValueError(f"safe_height: expected a height above the stock top {shi[2]:g}, got {safe_height!r}")

    # the (x, y) grid: the stock, the tool around it, and a margin for closed contours
    span = float(max(shi[0] - slo[0], shi[1] - slo[1])) + 3 * r
    h = span / resolution
    pad = 1.5 * r + 4 * h
    xs = np.arange(slo[0] - pad, shi[0] + pad + h, h)
    ys = np.arange(slo[1] - pad, shi[1] + pad + h, h)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    nz = max(16, resolution // 2)
    zs = np.linspace(slo[2], shi[2], nz + 1)
    tol = 1e-6 * size
    eps = 1e-7 * size
    inside_xy = (X >= slo[0]) & (X <= shi[0]) & (Y >= slo[1]) & (Y <= shi[1])
    heights = _top_heights(solid, X, Y, zs)
    heights[~inside_xy] = np.nan
    # a floor is flat: the surface normal at the column's top points straight up
    has = np.isfinite(heights)
    g = solid.gradient(np.column_stack([X[has], Y[has], heights[has]]))
    nzc = g[:, 2] / np.maximum(np.linalg.norm(g, axis=1), 1e-300)
    flat = heights[has]
    flat[nzc < FLAT_NORMAL] = np.nan
    heights[has] = flat
    floors = part_floors(heights, tol=1e-9 * size, min_columns=max(16, int(0.002 * inside_xy.sum())))
    depths = _depths(float(shi[2]), floors, float(slo[2]), dz_max, tol)

    # every plane the shadows need, top to bottom: samples, faces and depths (+eps)
    planes = np.unique(np.concatenate([zs[1:], np.asarray(depths) + eps, np.asarray(floors) + eps]))[::-1]
    planes = planes[planes <= shi[2] + eps]
    xy = np.column_stack([X.ravel(), Y.ravel()])
    inside = np.logical_or.accumulate(
        np.stack([solid(np.column_stack([xy, np.full(len(xy), z)])).reshape(X.shape) < 0 for z in planes]), axis=0)
    boundary = [_section_points(solid, z, h) for z in planes]
    E = _stock_field(slo[0], shi[0], slo[1], shi[1], 0.9 * r)
    Estock = _stock_field(slo[0], shi[0], slo[1], shi[1], 0.0)
    Egrid = E(np.stack([X, Y], axis=-1))

    from scipy.interpolate import RegularGridInterpolator
    from scipy.spatial import cKDTree

    ops = []
    prev = float(shi[2])
    problems = []
    for zc in depths:
        n_above = int(np.searchsorted(-planes, -(zc + eps), side="right"))
        pts_above = np.concatenate(boundary[:n_above])
        if len(pts_above) == 0:
            F = np.full(X.shape, np.inf)
            tree = None
        else:
            tree = cKDTree(pts_above)
            F = tree.query(xy)[0].reshape(X.shape)
            F[inside[n_above - 1]] *= -1.0
        G = np.minimum(F - r, Egrid)
        labels, n_bad = _narrow_features(F, G, inside_xy, h, r, leftover, zc)
        plunges = []
        for lab in range(1, n_bad + 1):
            m = labels == lab
            # the grid's samples miss the largest inscribed circle by up to h / sqrt(2): a
            # feature that may be wide enough gets a plunge at its middle if the tool fits there
            fmax = float(F[m].max())
            if fmax + h / np.sqrt(2) >= r and tree is not None:
                core = m & (F >= fmax - 0.5 * h)
                c = np.array([X[core].mean(), Y[core].mean()])
                if tree.query(c[None, :])[0][0] >= r * (1 - 1e-9) and E(c[None, :])[0] >= 0:
                    plunges.append(c)
                    continue
            if any(abs(p[1] - X[m].mean()) < 2 * h and abs(p[2] - Y[m].mean()) < 2 * h for p in problems):
                continue                                  # the same feature, one depth further down
            problems.append((zc, X[m].mean(), Y[m].mean(), X[m].min(), X[m].max(), Y[m].min(), Y[m].max(),
                             2 * fmax))
        if problems:
            continue
        interp = RegularGridInterpolator((xs, ys), G, bounds_error=False, fill_value=-r)

        def orient(q, interp=interp):
            return interp(q)

        def exact(q, tree=tree):
            d = tree.query(q)[0] if tree is not None else np.full(len(q), np.inf)
            return np.minimum(d - r, E(q))

        def refine(q, tree=tree):
            if tree is None:
                return q

            def field(p):
                n, k = p.shape[:2]
                d = tree.query(p.reshape(-1, 2))[0].reshape(n, k)
                return np.minimum(d - r, E(p))

            return newton_to_level(field, q, level, h)

        gmax = float(G.max())
        levels = np.arange(0, int(np.floor(gmax / s)) + 1) * s if gmax > 0 else np.array([])
        pocket, profile = [], []
        for level in levels[::-1]:
            for lp in level_loops(G, xs, ys, float(level), refine=refine, orient=orient):
                if level == 0 and np.all(Estock(lp) < -0.5 * r):
                    continue                  # runs outside the stock, around material the tool never meets
                if direction == "conventional":
                    lp = lp[::-1].copy()
                faces_part = level == 0 and np.any(F[_nearest(lp, xs, ys)] - r < Egrid[_nearest(lp, xs, ys)])
                moves = _loop_moves(lp, zc, prev, safe_z, r, s, level, exact, direction, feed, plunge)
                (profile if faces_part else pocket).append((level, moves))
        for c in plunges:
            z_clear = min(prev + 0.25 * r, safe_z)
            pocket.append((0.0, [(0, c[0], c[1], safe_z, 0, 0, None), (0, c[0], c[1], z_clear, 0, 0, None),
                                 (1, c[0], c[1], zc, 0, 0, plunge), (0, c[0], c[1], safe_z, 0, 0, None)]))
        if pocket:
            ops.append(Operation(f"pocket, depth z={zc:.6g}, {len(pocket)} loops, step-over {s:.6g}", "pocket", zc,
                                 _joined(pocket)))
        if profile:
            ops.append(Operation(f"profile, depth z={zc:.6g}, {len(profile)} loops at {r:.6g} from the part",
                                 "profile", zc, _joined(profile)))
        prev = zc
    if problems:
        first = problems[:3]
        where = "; ".join(f"at z={p[0]:.6g} near ({p[1]:.6g}, {p[2]:.6g}), x {p[3]:.6g}..{p[4]:.6g}, "
                          f"y {p[5]:.6g}..{p[6]:.6g}, width about {p[7]:.3g}" for p in first)
        more = f" (and {len(problems) - 3} more)" if len(problems) > 3 else ""
        raise ValueError(f"tool_radius: {len(problems)} feature(s) narrower than the tool diameter "
                         f"{2 * r:g}: {where}{more}")
    return ToolPath(r, (slo, shi), float(safe_z), depths, ops, units, spindle, direction, title)


def _sharp_corners(solid, z, lp, h):
    """The loop with the sharp corners that the contour cut restored.

    Sampled contours cut a sharp corner by a chord; the two neighbouring
    chords' lines meet at the corner.  A meeting point is kept where the
    lines turn by more than 30 degrees, it lies near the chord, and the
    solid's field vanishes there (a true corner, not a tight curve).
    """
    a, b = np.roll(lp, 1, axis=0), lp                       # chord j - 1 ends at p_j
    c, d = np.roll(lp, -1, axis=0), np.roll(lp, -2, axis=0)  # chord j + 1 starts at p_{j+1}
    u, v = b - a, d - c
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    nu, nv = np.linalg.norm(u, axis=1), np.linalg.norm(v, axis=1)
    sin = np.abs(cross) / np.maximum(nu * nv, 1e-300)
    w = c - b
    t = (w[:, 0] * v[:, 1] - w[:, 1] * v[:, 0]) / np.where(cross == 0, 1.0, cross)
    q = b + t[:, None] * u
    mid = 0.5 * (b + c)
    ok = (sin > 0.5) & (np.linalg.norm(q - mid, axis=1) < 2 * h) & (cross != 0)
    if not ok.any():
        return lp
    fq = np.full(len(lp), np.inf)
    fq[ok] = np.abs(solid(np.column_stack([q[ok], np.full(ok.sum(), z)])))
    ok &= fq < 1e-3 * h
    out = []
    for j in range(len(lp)):                                 # a loop's few corners: cheap
        out.append(lp[j])
        if ok[j]:
            out.append(q[j])
    return np.array(out)


def _section_points(solid, z, h):
    """Boundary points of the section at height z (sharp corners restored), at most h / 32 apart
    (the distance to them is the distance to the curve within (h / 64)^2 / (2 r))."""
    from ..analysis.section import section

    sec = section(solid, f"z={float(z)!r}", voxel_size=h)
    out = [np.zeros((0, 2))]
    for lp in sec.loops:
        lp = _sharp_corners(solid, z, lp, h)
        b = np.roll(lp, -1, axis=0)
        n = np.maximum(1, np.ceil(np.linalg.norm(b - lp, axis=1) / (h / 32)).astype(int))
        t = np.concatenate([np.arange(k) / k for k in n])
        i = np.repeat(np.arange(len(lp)), n)
        out.append(lp[i] + t[:, None] * (b[i] - lp[i]))
    return np.concatenate(out)


def _nearest(lp, xs, ys):
    i = np.clip(np.rint((lp[:, 0] - xs[0]) / (xs[1] - xs[0])).astype(int), 0, len(xs) - 1)
    j = np.clip(np.rint((lp[:, 1] - ys[0]) / (ys[1] - ys[0])).astype(int), 0, len(ys) - 1)
    return i, j


def _joined(loops):
    out = []
    for k, (level, moves) in enumerate(loops, 1):
        out.append((f"loop {k} of {len(loops)}, offset {level:.6g} beyond the finishing contour", 0, 0, 0, 0, 0, None))
        out.extend(moves)
    return out


def _loop_moves(lp, zc, prev, safe_z, r, s, level, exact, direction, feed, plunge):
    """Rapid above the start, plunge, lead-in arc, the loop, lead-out, retract."""
    p0 = lp[0]
    t = lp[1] - lp[0]
    t = t / max(np.linalg.norm(t), 1e-300)
    side = 1.0 if direction == "climb" else -1.0       # the cleared side: left for climb
    nrm = side * np.array([-t[1], t[0]])
    g_arc = 3 if side > 0 else 2
    rho = min(0.5 * s, 0.5 * r)
    for _ in range(4):
        c = p0 + rho * nrm
        ang = np.linspace(0, np.pi, 17)[:, None]
        ring = c - rho * (np.cos(ang) * t + np.sin(ang) * nrm)     # a -> p0 -> b
        if np.all(exact(ring) >= level - 1e-6 * r):      # the arc runs where the tool may go
            break
        rho *= 0.5
    else:
        rho = 0.0
    z_clear = min(prev + 0.25 * r, safe_z)
    moves = []
    if rho > 0:
        c = p0 + rho * nrm
        a = c - rho * t
        b = c + rho * t
        moves += [(0, a[0], a[1], safe_z, 0, 0, None), (0, a[0], a[1], z_clear, 0, 0, None),
                  (1, a[0], a[1], zc, 0, 0, plunge),
                  (g_arc, p0[0], p0[1], zc, c[0] - a[0], c[1] - a[1], feed)]
    else:
        moves += [(0, p0[0], p0[1], safe_z, 0, 0, None), (0, p0[0], p0[1], z_clear, 0, 0, None),
                  (1, p0[0], p0[1], zc, 0, 0, plunge)]
    moves += [(1, x, y, zc, 0, 0, feed) for x, y in lp[1:]]
    moves.append((1, p0[0], p0[1], zc, 0, 0, feed))
    if rho > 0:
        moves.append((g_arc, b[0], b[1], zc, c[0] - p0[0], c[1] - p0[1], feed))
        moves.append((0, b[0], b[1], safe_z, 0, 0, None))
    else:
        moves.append((0, p0[0], p0[1], safe_z, 0, 0, None))
    return moves
