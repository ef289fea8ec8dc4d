"""Closest-point projection of many points onto curves and surfaces.

Point inversion after The NURBS Book (Piegl and Tiller, 2nd ed.), section 6.1:
each point is seeded with the nearest sample of the curve or surface
(``scipy.spatial.cKDTree``) and refined with Newton steps on
``f = C'(u) . (C(u) - P) = 0`` (curves) or ``(Su . r, Sv . r) = 0`` (surfaces),
vectorized over all points at once, clamped to the domain, with a halving step
whenever a step would move away from the point.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .curves import BSpline, Curve
from .surfaces import Surface

__all__ = ["project_to_curve", "project_to_surface", "PROJECTION_TOL"]

#: Relative parameter step below which Newton iterations stop (the step is still
#: taken; Newton's quadratic convergence leaves an error near its square).
PROJECTION_TOL = 1e-9


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


def project_to_curve(curve, points, *, samples=None, iterations=30, tol=PROJECTION_TOL):
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
    a, b = curve.domain
    if samples is None:
        nc = curve.control_points.shape[0] if isinstance(curve, BSpline) else 16
        samples = max(256, 40 * nc)
    ts = np.linspace(a, b, int(samples))
    pts = curve(ts)
    tree = cKDTree(pts)
    _, idx = tree.query(P)
    u = ts[idx]
    span = b - a
    closed = np.linalg.norm(pts[0] - pts[-1]) <= 1e-10 * max(1.0, np.ptp(pts, axis=0).max())
    u_prev = u.copy()
    d_prev = np.full(P.shape[0], np.inf)
    last = np.zeros(P.shape[0])
    noise = (1e-15 * max(1.0, float(np.ptp(pts, axis=0).max()))) ** 2
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
        last[active] = stp
        moved = np.abs(new - ua)
        if closed:
            moved = np.minimum(moved, span - moved)
        u[active] = new
        active = active[moved > tol * span]
    closest = curve(u)
    better = d_prev < np.einsum("nd,nd->n", closest - P, closest - P)
    if np.any(better):
        u[better] = u_prev[better]
        closest[better] = curve(u[better])
    dist = np.linalg.norm(closest - P, axis=1)
    if scalar:
        return u[0], closest[0], dist[0]
    return u, closest, dist


def project_to_surface(surface, points, *, samples=None, iterations=30, tol=PROJECTION_TOL):
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
    tree = cKDTree(grid.reshape(-1, surface.dim))
    _, idx = tree.query(P)
    u = su[idx // sv.size]
    v = sv[idx % sv.size]
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
        last_u[active], last_v[active] = du, dv
        nu_ = wrap(bu_ + du, au, lu, closed_u)
        nv_ = wrap(bv_ + dv, av, lv, closed_v)
        mu_ = np.abs(nu_ - ua)
        mv_ = np.abs(nv_ - va)
        if closed_u:
            mu_ = np.minimum(mu_, lu - mu_)
        if closed_v:
            mv_ = np.minimum(mv_, lv - mv_)
        u[active], v[active] = nu_, nv_
        active = active[np.maximum(mu_ / lu, mv_ / lv) > tol]
    closest = surface(u, v)
    better = d_prev < dot(closest - P, closest - P)
    if np.any(better):
        u[better], v[better] = u_prev[better], v_prev[better]
        closest[better] = surface(u[better], v[better])
    dist = np.linalg.norm(closest - P, axis=1)
    uv = np.stack([u, v], axis=1)
    if scalar:
        return uv[0], closest[0], dist[0]
    return uv, closest, dist
