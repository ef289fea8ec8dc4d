"""Closest-point projection of many points onto curves and surfaces.

Point inversion after The NURBS Book (Piegl and Tiller, 2nd ed.), section 6.1:
each point is seeded with the nearest sample of the curve or surface
(``scipy.spatial.cKDTree``) and refined with Newton steps on
``f = C'(u) . (C(u) - P) = 0`` (curves) or ``(Su . r, Sv . r) = 0`` (surfaces),
vectorized over all points at once, clamped to the domain, with a halving step
whenever a step would move away from the point. Distance has local minima
(a point above a wavy patch sees several valleys): other nearest samples that
are discrete local minima of the sampled distance, apart from the first seed and
its result and within half the sampling reach of the distance found, seed
further Newton runs, and the best result is kept; a result is never farther
than the nearest sample.
"""

from __future__ import annotations

import numpy as np

from .curves import BSpline, Curve
from .surfaces import Surface

__all__ = ["project_to_curve", "project_to_surface", "PROJECTION_TOL", "CURVE_SEEDS",
           "SURFACE_SEEDS"]

#: Relative parameter step below which Newton iterations stop (the step is still
#: taken; Newton's quadratic convergence leaves an error near its square).
PROJECTION_TOL = 1e-9

#: Nearest samples tried as Newton seeds (see :func:`project_to_curve`).
CURVE_SEEDS = 6
#: Nearest grid samples tried as Newton seeds (see :func:`project_to_surface`).
SURFACE_SEEDS = 8


def _query_points(points, dim):
    try:
        P = np.array(points, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"points must be a numeric array of shape (n, {dim})") from None
    scalar = P.ndim == 1
    P = np.atleast_2d(P)
    if P.ndim != 2 or P.shape[1] != dim:
        raise ValueError(f"points must have shape (n, {dim}), got {np.shape(points)}")
    if not np.all(np.isfinite(P)):
        raise ValueError("points must be finite")
    return P, scalar


def _check_seeds(seeds):
    if isinstance(seeds, (bool, np.bool_)) or not isinstance(seeds, (int, np.integer)):
        raise TypeError(f"seeds must be an int, got {type(seeds).__name__}")
    if seeds < 1:
        raise ValueError(f"seeds must be >= 1, got {seeds}")
    return int(seeds)


def project_to_curve(curve, points, *, samples=None, iterations=30, tol=PROJECTION_TOL,
                     seeds=CURVE_SEEDS):
    """Closest points on ``curve`` to many points.

    Parameters
    ----------
    curve : Curve
    points : (n, dim) float
    samples : int, optional
        Seed samples along the curve (default: 40 per control point of a
        B-spline, at least 256).
    iterations : int
        Maximum Newton iterations.
    tol : float
        Stop when the parameter step is below ``tol`` times the domain length.
    seeds : int
        Nearest samples considered as Newton seeds. Newton runs from the nearest;
        the others run too where they are not next to it nor to its result and
        lie within the sampling reach of the distance found (a nearer foot
        point may hide there); the best result is kept, and it is never farther
        than the nearest sample.

    Returns
    -------
    params : (n,) float
    closest : (n, dim) float
    distances : (n,) float

    Examples
    --------
    >>> from parametric.conics import circle
    >>> u, x, d = project_to_curve(circle(1.0, center=(0, 0)), [[2.0, 0.0], [0.0, 0.5]])
    >>> np.round(d, 12)
    array([1. , 0.5])
    """
    if not isinstance(curve, Curve):
        raise TypeError(f"curve must be a Curve, got {type(curve).__name__}")
    P, scalar = _query_points(points, curve.dim)
    seeds = _check_seeds(seeds)
    a, b = curve.domain
    if samples is None:
        nc = curve.control_points.shape[0] if isinstance(curve, BSpline) else 16
        samples = max(256, 40 * nc)
    ts = np.linspace(a, b, int(samples))
    pts = curve(ts)
    scale = max(1.0, float(np.ptp(pts, axis=0).max()))
    closed = np.linalg.norm(pts[0] - pts[-1]) <= 1e-10 * scale
    k = min(int(seeds), ts.size)
    from scipy.spatial import cKDTree  # local: scipy.spatial costs 0.25 s to import

    dist, idx = cKDTree(pts).query(P, k=k)
    dist, idx = dist.reshape(P.shape[0], k), idx.reshape(P.shape[0], k)
    u, d2 = _curve_newton(curve, P, ts[idx[:, 0]], a, b, closed, iterations, tol, scale)
    if k > 1:
        # other seeds whose sample could lie near a better foot point: not next to
        # the first seed nor to the result, and closer than the result plus the
        # sampling reach (the largest gap between neighbouring samples)
        gap = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        reach = np.maximum(np.concatenate([gap, [0.0]]), np.concatenate([[0.0], gap]))
        n = ts.size
        cell = np.clip(np.rint((u - a) / (b - a) * (n - 1)), 0, n - 1).astype(np.intp)

        def apart(x, y):
            dx = np.abs(x - y)
            return (np.minimum(dx, n - 1 - dx) if closed else dx) > 1

        cand = (apart(idx, idx[:, :1]) & apart(idx, cell[:, None])
                & (dist - 0.5 * reach[idx] < np.sqrt(d2)[:, None]))
        cand[:, 0] = False
        # a separate basin shows as a discrete local minimum of the sampled distance
        rows, cols = np.nonzero(cand)
        if rows.size:
            ci = idx[rows, cols]
            local = np.ones(rows.size, bool)
            for step in (-1, 1):
                ni = (ci + step) % (n - 1) if closed else np.clip(ci + step, 0, n - 1)
                local &= dist[rows, cols] <= np.linalg.norm(pts[ni] - P[rows], axis=1) * (1 + 1e-12)
            cand[rows[~local], cols[~local]] = False
        pi, cj = np.nonzero(cand)
        if pi.size:
            uc, dc = _curve_newton(curve, P[pi], ts[idx[pi, cj]], a, b, closed, iterations,
                                   tol, scale)
            pick, sel = _best_per_point(pi, dc, d2)
            u[pick], d2[pick] = uc[sel], dc[sel]
    # never worse than the nearest sample
    worse = d2 > dist[:, 0] ** 2
    u[worse] = ts[idx[worse, 0]]
    closest = curve(u)
    dist_out = np.linalg.norm(closest - P, axis=1)
    if scalar:
        return u[0], closest[0], dist_out[0]
    return u, closest, dist_out


def _best_per_point(pi, dc, d2):
    """Among extra results (point index ``pi``, squared distance ``dc``), the best
    per point where it beats ``d2``: (points, indices into the extra results)."""
    order = np.lexsort((dc, pi))
    first = np.ones(order.size, bool)
    first[1:] = pi[order[1:]] != pi[order[:-1]]
    sel = order[first]
    sel = sel[dc[sel] < d2[pi[sel]]]
    return pi[sel], sel


def _curve_newton(curve, P, u, a, b, closed, iterations, tol, scale):
    """Newton point inversion from seeds ``u``: (params, squared distances)."""
    u = u.astype(float).copy()
    span = b - a
    u_prev = u.copy()
    d_prev = np.full(P.shape[0], np.inf)
    last = np.zeros(P.shape[0])
    noise = (1e-15 * scale) ** 2
    active = np.arange(P.shape[0])
    for _ in range(int(iterations)):
        if active.size == 0:
            break
        ua = u[active]
        D = curve.derivatives(ua, 2)
        r = D[:, 0] - P[active]
        d = np.einsum("nd,nd->n", r, r)
        dp = d_prev[active]
        worse = d > dp * (1.0 + 1e-9) + noise
        f = np.einsum("nd,nd->n", D[:, 1], r)
        g2 = np.einsum("nd,nd->n", D[:, 1], D[:, 1])
        fp = g2 + np.einsum("nd,nd->n", D[:, 2], r)
        fp = np.where(fp > 1e-12 * g2, fp, g2)
        fp = np.where(fp > 0, fp, 1.0)
        # a step that moved away from the point is halved from the last good one
        stp = np.where(worse, 0.5 * last[active], -f / fp)
        base = np.where(worse, u_prev[active], ua)
        new = base + stp
        new = (a + np.mod(new - a, span)) if closed else np.clip(new, a, b)
        keep = ~worse
        u_prev[active[keep]] = ua[keep]
        d_prev[active[keep]] = d[keep]
        # remember the step actually taken (a clipped step is halved from its clipped length)
        last[active] = stp if closed else new - base
        moved = np.abs(new - ua)
        if closed:
            moved = np.minimum(moved, span - moved)
        u[active] = new
        active = active[moved > tol * span]
    closest = curve(u)
    d2 = np.einsum("nd,nd->n", closest - P, closest - P)
    better = d_prev < d2
    u[better] = u_prev[better]
    d2[better] = d_prev[better]
    return u, d2


def project_to_surface(surface, points, *, samples=None, iterations=30, tol=PROJECTION_TOL,
                       seeds=SURFACE_SEEDS):
    """Closest points on ``surface`` to many points.

    Parameters
    ----------
    surface : Surface
    points : (n, 3) float
    samples : (2,) int, optional
        Seed grid (default: 8 per control point of a tensor surface, 32 to 256
        each way).
    iterations : int
        Maximum Newton iterations.
    tol : float
        Stop when both parameter steps are below ``tol`` times their domain length.
    seeds : int
        Nearest grid samples considered as Newton seeds. Newton runs from the
        nearest; the others run too where they are not next to it nor to its
        result and lie within the sampling reach of the distance found (a
        nearer foot point may hide there); the best result is kept, and it is
        never farther than the nearest sample.

    Returns
    -------
    params : (n, 2) float
        ``(u, v)`` of each closest point.
    closest : (n, 3) float
    distances : (n,) float

    Examples
    --------
    >>> from parametric.tensor import sphere
    >>> uv, x, d = project_to_surface(sphere(1.0), [[0.0, 0.0, 3.0], [0.5, 0.0, 0.0]])
    >>> np.round(d, 10)
    array([2. , 0.5])
    """
    if not isinstance(surface, Surface):
        raise TypeError(f"surface must be a Surface, got {type(surface).__name__}")
    P, scalar = _query_points(points, surface.dim)
    seeds = _check_seeds(seeds)
    (au, bu), (av, bv) = surface.domain_u, surface.domain_v
    if samples is None:
        ctrl = getattr(surface, "control_points", None)
        if ctrl is not None and np.ndim(ctrl) == 3:
            samples = tuple(int(np.clip(8 * n, 32, 256)) for n in ctrl.shape[:2])
        else:
            samples = (64, 64)
    su = np.linspace(au, bu, int(samples[0]))
    sv = np.linspace(av, bv, int(samples[1]))
    grid = surface.grid(su, sv)
    scale = max(1.0, float(np.ptp(grid.reshape(-1, surface.dim), axis=0).max()))
    closed_u = np.max(np.linalg.norm(grid[0] - grid[-1], axis=-1)) <= 1e-10 * scale
    closed_v = np.max(np.linalg.norm(grid[:, 0] - grid[:, -1], axis=-1)) <= 1e-10 * scale
    ns_u, ns_v = su.size, sv.size
    k = min(int(seeds), ns_u * ns_v)
    flat = grid.reshape(-1, surface.dim)
    from scipy.spatial import cKDTree  # local: scipy.spatial costs 0.25 s to import

    dist, idx = cKDTree(flat).query(P, k=k)
    dist, idx = dist.reshape(P.shape[0], k), idx.reshape(P.shape[0], k)
    dom = (au, bu, av, bv, closed_u, closed_v)
    u, v, d2 = _surface_newton(surface, P, su[idx[:, 0] // ns_v], sv[idx[:, 0] % ns_v], dom,
                               iterations, tol, scale)
    if k > 1:
        # other seeds whose sample could lie near a better foot point: not next to
        # the first seed nor to the result, and closer than the result plus the
        # sampling reach (the largest distance to a neighbouring sample)
        pad = np.pad(grid, ((1, 1), (1, 1), (0, 0)), mode="edge")
        reach = np.zeros((ns_u, ns_v))
        for di in (0, 1, 2):
            for dj in (0, 1, 2):
                nb = pad[di:di + ns_u, dj:dj + ns_v]
                reach = np.maximum(reach, np.linalg.norm(nb - grid, axis=-1))
        reach = reach.ravel()
        iu, iv = idx // ns_v, idx % ns_v
        cu = np.clip(np.rint((u - au) / (bu - au) * (ns_u - 1)), 0, ns_u - 1).astype(np.intp)
        cv = np.clip(np.rint((v - av) / (bv - av) * (ns_v - 1)), 0, ns_v - 1).astype(np.intp)

        def gap(x, y, n, closed):
            dx = np.abs(x - y)
            return np.minimum(dx, n - 1 - dx) if closed else dx

        def apart(i1, j1, i2, j2):
            return np.maximum(gap(i1, i2, ns_u, closed_u), gap(j1, j2, ns_v, closed_v)) > 1

        cand = (apart(iu, iv, iu[:, :1], iv[:, :1]) & apart(iu, iv, cu[:, None], cv[:, None])
                & (dist - 0.5 * reach[idx] < np.sqrt(d2)[:, None]))
        cand[:, 0] = False
        # a separate basin shows as a discrete local minimum of the sampled distance
        rows, cols = np.nonzero(cand)
        cand[:] = False
        ci, cj_ = iu[rows, cols], iv[rows, cols]
        d0 = dist[rows, cols] ** 2
        for di, dj in ((-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)):
            if not rows.size:
                break
            ni, nj = ci + di, cj_ + dj
            ni = ni % (ns_u - 1) if closed_u else np.clip(ni, 0, ns_u - 1)
            nj = nj % (ns_v - 1) if closed_v else np.clip(nj, 0, ns_v - 1)
            r_ = flat[ni * ns_v + nj] - P[rows]
            ok = d0 <= np.einsum("nd,nd->n", r_, r_) * (1.0 + 1e-12)  # ties (clipped) pass
            rows, cols, ci, cj_, d0 = rows[ok], cols[ok], ci[ok], cj_[ok], d0[ok]
        cand[rows, cols] = True
        pi, cj = np.nonzero(cand)
        if pi.size:
            sel_idx = idx[pi, cj]
            uc, vc, dc = _surface_newton(surface, P[pi], su[sel_idx // ns_v], sv[sel_idx % ns_v],
                                         dom, iterations, tol, scale)
            pick, sel = _best_per_point(pi, dc, d2)
            u[pick], v[pick], d2[pick] = uc[sel], vc[sel], dc[sel]
    # never worse than the nearest sample
    worse = d2 > dist[:, 0] ** 2
    u[worse], v[worse] = su[idx[worse, 0] // ns_v], sv[idx[worse, 0] % ns_v]
    closest = surface(u, v)
    dist_out = np.linalg.norm(closest - P, axis=1)
    uv = np.stack([u, v], axis=1)
    if scalar:
        return uv[0], closest[0], dist_out[0]
    return uv, closest, dist_out


def _surface_newton(surface, P, u, v, dom, iterations, tol, scale):
    """Newton point inversion from seeds ``(u, v)``: (u, v, squared distances)."""
    au, bu, av, bv, closed_u, closed_v = dom
    u, v = u.astype(float).copy(), v.astype(float).copy()
    lu, lv = bu - au, bv - av
    u_prev, v_prev = u.copy(), v.copy()
    d_prev = np.full(P.shape[0], np.inf)
    last_u = np.zeros(P.shape[0])
    last_v = np.zeros(P.shape[0])
    noise = (1e-15 * scale) ** 2
    active = np.arange(P.shape[0])

    def dot(x, y):
        return np.einsum("nd,nd->n", x, y)

    def wrap(x, lo, length, closed):
        return lo + np.mod(x - lo, length) if closed else np.clip(x, lo, lo + length)

    for _ in range(int(iterations)):
        if active.size == 0:
            break
        ua, va = u[active], v[active]
        D = surface.derivatives(ua, va, 2)
        r = D[:, 0, 0] - P[active]
        d = dot(r, r)
        worse = d > d_prev[active] * (1.0 + 1e-9) + noise
        Su, Sv = D[:, 1, 0], D[:, 0, 1]
        f, g = dot(Su, r), dot(Sv, r)
        g11, g12, g22 = dot(Su, Su), dot(Su, Sv), dot(Sv, Sv)
        a11 = g11 + dot(D[:, 2, 0], r)
        a12 = g12 + dot(D[:, 1, 1], r)
        a22 = g22 + dot(D[:, 0, 2], r)
        det = a11 * a22 - a12 * a12
        h11 = np.where(a11 > 1e-12 * g11, a11, g11 + 1e-300)  # 1-D Newton along u
        h22 = np.where(a22 > 1e-12 * g22, a22, g22 + 1e-300)  # 1-D Newton along v
        bad = (det <= 1e-12 * (a11 + a22) ** 2) | (a11 <= 0) | (a22 <= 0)
        # Gauss-Newton (first fundamental form, positive semi-definite) where the
        # Hessian is not positive definite, damped where it is singular (poles)
        mu = 1e-10 * (g11 + g22) + 1e-300
        a11 = np.where(bad, g11 + mu, a11)
        a12 = np.where(bad, g12, a12)
        a22 = np.where(bad, g22 + mu, a22)
        det = a11 * a22 - a12 * a12
        du = -(a22 * f - a12 * g) / det
        dv = -(a11 * g - a12 * f) / det
        # on a boundary the step pushing outward is dropped and the other
        # parameter takes a one-dimensional Newton step along the boundary curve
        out_v = np.zeros(du.shape, bool) if closed_v else (
            ((va <= av) & (dv < 0)) | ((va >= bv) & (dv > 0)))
        out_u = np.zeros(du.shape, bool) if closed_u else (
            ((ua <= au) & (du < 0)) | ((ua >= bu) & (du > 0)))
        du1, dv1 = -f / h11, -g / h22
        in_u = ~(((ua <= au) & (du1 < 0)) | ((ua >= bu) & (du1 > 0))) | closed_u
        in_v = ~(((va <= av) & (dv1 < 0)) | ((va >= bv) & (dv1 > 0))) | closed_v
        only_v = out_v & ~out_u
        only_u = out_u & ~out_v
        both = out_u & out_v  # a corner: slide along whichever edge leads inside
        du = np.where(only_v | (both & in_u), du1, np.where(out_u, 0.0, du))
        dv = np.where(only_u | (both & ~in_u & in_v), dv1, np.where(out_v, 0.0, dv))
        # a step that moved away from the point is halved from the last good one
        du = np.where(worse, 0.5 * last_u[active], du)
        dv = np.where(worse, 0.5 * last_v[active], dv)
        bu_ = np.where(worse, u_prev[active], ua)
        bv_ = np.where(worse, v_prev[active], va)
        keep = ~worse
        u_prev[active[keep]], v_prev[active[keep]] = ua[keep], va[keep]
        d_prev[active[keep]] = d[keep]
        nu_ = wrap(bu_ + du, au, lu, closed_u)
        nv_ = wrap(bv_ + dv, av, lv, closed_v)
        # remember the step actually taken (a clipped step is halved from its clipped length)
        last_u[active] = du if closed_u else nu_ - bu_
        last_v[active] = dv if closed_v else nv_ - bv_
        mu_ = np.abs(nu_ - ua)
        mv_ = np.abs(nv_ - va)
        if closed_u:
            mu_ = np.minimum(mu_, lu - mu_)
        if closed_v:
            mv_ = np.minimum(mv_, lv - mv_)
        u[active], v[active] = nu_, nv_
        active = active[np.maximum(mu_ / lu, mv_ / lv) > tol]
    closest = surface(u, v)
    d2 = dot(closest - P, closest - P)
    better = d_prev < d2
    u[better], v[better] = u_prev[better], v_prev[better]
    d2[better] = d_prev[better]
    return u, v, d2
