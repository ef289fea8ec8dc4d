"""Interpolating and least-squares fits of curves and surfaces to point data.

References: The NURBS Book (Piegl and Tiller, 2nd ed.): eq. 9.4-9.6 (chord-length
and centripetal parameters), eq. 9.8 (knot averaging), A9.1 (curve interpolation),
A9.4 (surface interpolation), A9.7 and eq. 9.68-9.69 (least-squares curves),
section 10.3 (skinning / lofting through compatible sections).
"""

from __future__ import annotations

import numpy as np

from . import _ops
from .basis import _check_degree, basis_matrix, clamped_knots, periodic_knots
from .curves import NURBS, Bezier, BSpline, Curve
from .tensor import BSplineSurface, NURBSSurface

__all__ = ["parametrize", "averaged_knots", "approximation_knots", "interpolate_curve", "make_compatible",
           "approximate_curve", "fit_periodic_curve", "fit_curve", "interpolate_surface",
           "approximate_surface", "loft", "fit_periodic_surface"]

_METHODS = ("chord", "centripetal", "uniform")


def _pts(points, name="points", min_rows=2):
    try:
        Q = np.array(points, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of shape (n, dim)") from None
    if Q.ndim != 2:
        raise ValueError(f"{name} must have shape (n, dim), got {Q.shape}")
    if Q.shape[0] < min_rows:
        raise ValueError(f"{name} needs at least {min_rows} points, got {Q.shape[0]}")
    if not np.all(np.isfinite(Q)):
        raise ValueError(f"{name} must be finite")
    return Q


def parametrize(points, method="chord", closed=False):
    """Parameters in [0, 1] for data points (eq. 9.4-9.6).

    Parameters
    ----------
    points : (m, dim) float
    method : {"chord", "centripetal", "uniform"}
    closed : bool
        Include the closing leg from the last point back to the first; the
        parameters then lie in [0, 1) and 1 stands for the first point again.

    Returns
    -------
    (m,) float array, non-decreasing.
    """
    Q = _pts(points)
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    P = np.concatenate([Q, Q[:1]]) if closed else Q
    d = np.linalg.norm(np.diff(P, axis=0), axis=1)
    if method == "centripetal":
        d = np.sqrt(d)
    elif method == "uniform":
        d = np.ones_like(d)
    total = d.sum()
    if not total > 0:
        raise ValueError("points must not all coincide")
    t = np.concatenate([[0.0], np.cumsum(d)]) / total
    if closed:
        return t[:-1]
    t[-1] = 1.0
    return t


def averaged_knots(params, degree):
    """Clamped knot vector by averaging ``degree`` consecutive parameters (eq. 9.8)."""
    t = np.asarray(params, dtype=float)
    p = degree
    n = t.size - 1
    c = np.concatenate([[0.0], np.cumsum(t)])
    j = np.arange(1, n - p + 1)
    inner = (c[j + p] - c[j]) / p
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


def approximation_knots(params, degree, n_control):
    """Clamped knots for least squares with ``n_control`` points (eq. 9.68-9.69)."""
    t = np.asarray(params, dtype=float)
    p = degree
    m = t.size - 1
    n = n_control - 1
    d = (m + 1) / (n - p + 1)
    j = np.arange(1, n - p + 1)
    i = np.floor(j * d).astype(int)
    alpha = j * d - i
    inner = (1.0 - alpha) * t[i - 1] + alpha * t[i]
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


def interpolate_curve(points, degree=3, *, method="chord", params=None):
    """B-spline through all points (A9.1).

    Parameters
    ----------
    points : (m, dim) float, m >= degree + 1
    degree : int
    method : {"chord", "centripetal", "uniform"}
    params : (m,) float, optional
        Parameters to use instead of ``method``.

    Returns
    -------
    BSpline with ``m`` control points and ``curve(params) == points``.

    Examples
    --------
    >>> q = np.array([[0, 0], [1, 2], [3, 2], [4, 0]], dtype=float)
    >>> c = interpolate_curve(q, 3)
    >>> np.allclose(c(parametrize(q)), q)
    True
    """
    Q = _pts(points)
    p = _check_degree(degree)
    if Q.shape[0] < p + 1:
        raise ValueError(f"points: degree {p} needs at least {p + 1} points, got {Q.shape[0]}")
    same = np.flatnonzero(np.all(Q[1:] == Q[:-1], axis=1))
    if same.size:
        i = int(same[0])
        raise ValueError(f"points: consecutive points {i} and {i + 1} coincide ({Q[i].tolist()}); an "
                         "interpolating curve cannot pass one point twice in a row (drop the repeats)")
    t = parametrize(Q, method) if params is None else _params(params, Q.shape[0])
    if np.any(np.diff(t) <= 0):
        i = int(np.flatnonzero(np.diff(t) <= 0)[0])
        raise ValueError(f"params: expected strictly increasing parameters, got {t[i]} then {t[i + 1]} "
                         f"at points {i} and {i + 1}")
    U = averaged_knots(t, p)
    A = basis_matrix(U, p, Q.shape[0], t)
    return BSpline(np.linalg.solve(A, Q), p, U)


def _params(params, m):
    t = np.asarray(params, dtype=float).ravel()
    if t.size != m:
        raise ValueError(f"params must have one value per point ({m}), got {t.size}")
    if np.any(np.diff(t) < 0) or t[0] < 0 or t[-1] > 1:
        raise ValueError("params must be non-decreasing in [0, 1]")
    return t


def approximate_curve(points, n_control, degree=3, *, method="chord", params=None):
    """Least-squares B-spline with ``n_control`` points (A9.7).

    The end points are interpolated; the interior control points minimise the sum of
    squared distances ``|C(t_k) - Q_k|²`` at the data parameters.

    Returns
    -------
    BSpline

    Examples
    --------
    >>> t = np.linspace(0, 1, 50)
    >>> c = approximate_curve(np.stack([t, np.sin(3 * t)], 1), 8, 3)
    >>> c.control_points.shape
    (8, 2)
    """
    Q = _pts(points)
    p = _check_degree(degree)
    m1 = Q.shape[0]
    if isinstance(n_control, (bool, np.bool_)) or not isinstance(n_control, (int, np.integer)):
        raise TypeError(f"n_control must be an int, got {type(n_control).__name__}")
    if not p + 1 <= n_control <= m1:
        raise ValueError(f"n_control must lie in [degree + 1, len(points)] = [{p + 1}, {m1}], "
                         f"got {n_control}")
    t = parametrize(Q, method) if params is None else _params(params, m1)
    if n_control == m1:
        return interpolate_curve(Q, p, params=t)
    U = approximation_knots(t, p, n_control)
    A = basis_matrix(U, p, n_control, t)
    P = np.empty((n_control, Q.shape[1]))
    P[0], P[-1] = Q[0], Q[-1]
    if n_control > 2:
        R = Q[1:-1] - np.outer(A[1:-1, 0], Q[0]) - np.outer(A[1:-1, -1], Q[-1])
        P[1:-1] = np.linalg.lstsq(A[1:-1, 1:-1], R, rcond=None)[0]
    return BSpline(P, p, U)


def _periodic_basis(t, n_unique, p):
    U = periodic_knots(n_unique, p)
    A = basis_matrix(U, p, n_unique + p, np.clip(t, 0.0, 1.0))
    A[:, :p] += A[:, n_unique:]
    return A[:, :n_unique], U


def fit_periodic_curve(points, n_control, degree=3, *, method="chord"):
    """Closed C^(p-1) least-squares B-spline through a closed contour.

    Parameters
    ----------
    points : (m, dim) float
        The contour, without repeating the first point at the end.
    n_control : int
        Distinct control points, ``degree + 1 <= n_control <= m``.

    Returns
    -------
    BSpline built by :meth:`BSpline.periodic` (domain [0, 1], ``C(0) == C(1)``).

    Examples
    --------
    >>> th = np.linspace(0, 2 * np.pi, 100, endpoint=False)
    >>> c = fit_periodic_curve(np.stack([np.cos(th), np.sin(th)], 1), 12)
    >>> bool(np.allclose(c(0.0), c(1.0)))
    True
    """
    Q = _pts(points, min_rows=3)
    p = _check_degree(degree)
    m = Q.shape[0]
    if not p + 1 <= n_control <= m:
        raise ValueError(f"n_control must lie in [degree + 1, len(points)] = [{p + 1}, {m}], "
                         f"got {n_control}")
    t = parametrize(Q, method, closed=True)
    A, _ = _periodic_basis(t, n_control, p)
    P = np.linalg.lstsq(A, Q, rcond=None)[0]
    return BSpline.periodic(P, p)


def _deviation(curve, Q, t):
    return float(np.max(np.linalg.norm(curve(t) - Q, axis=1)))


def fit_curve(points, degree=3, n_control=None, tolerance=None, closed=False, *,
              method="chord"):
    """Fit a B-spline to points, adding control points until within ``tolerance``.

    Parameters
    ----------
    points : (m, dim) float
    degree : int
    n_control : int, optional
        Fixed number of (distinct) control points.
    tolerance : float, optional
        Target maximum deviation. The control count starts at ``degree + 1`` and
        grows by a third each round until the deviation is below ``tolerance``
        (an open curve reaches interpolation at worst).
    closed : bool
        Fit a closed periodic curve; a last point equal to the first is dropped.
    method : {"chord", "centripetal", "uniform"}

    With neither ``n_control`` nor ``tolerance`` an open curve interpolates
    every point and a closed curve uses ``max(degree + 1, m // 2)`` control points.

    Returns
    -------
    curve : BSpline
    max_deviation : float
        ``max_k |C(t_k) - Q_k|`` at the data parameters (an upper bound of the
        distance from each point to the curve).

    Examples
    --------
    >>> th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    >>> ring = np.stack([np.cos(th), np.sin(th)], 1)
    >>> c, dev = fit_curve(ring, tolerance=1e-4, closed=True)
    >>> dev < 1e-4
    True
    """
    Q = _pts(points)
    p = _check_degree(degree)
    if closed and Q.shape[0] > 2 and np.allclose(Q[0], Q[-1], rtol=0, atol=1e-12):
        Q = Q[:-1]
    m = Q.shape[0]
    if tolerance is not None:
        tolerance = float(tolerance)
        if not tolerance > 0:
            raise ValueError(f"tolerance must be > 0, got {tolerance}")
    if n_control is not None:
        if isinstance(n_control, (bool, np.bool_)) or not isinstance(n_control, (int, np.integer)):
            raise TypeError(f"n_control must be an int, got {type(n_control).__name__}")
        if not p + 1 <= n_control <= m:
            raise ValueError(f"n_control must lie in [{p + 1}, {m}], got {n_control}")
    if m < p + 1:
        raise ValueError(f"points: degree {p} needs at least {p + 1} points, got {m}")
    t = parametrize(Q, method, closed=closed)

    def fit(n):
        if closed:
            return fit_periodic_curve(Q, n, p, method=method)
        return approximate_curve(Q, n, p, params=t)

    if n_control is not None or tolerance is None:
        n = n_control if n_control is not None else (max(p + 1, m // 2) if closed else m)
        c = fit(n)
        return c, _deviation(c, Q, t)
    n = p + 1
    while True:
        c = fit(n)
        dev = _deviation(c, Q, t)
        if dev <= tolerance or n >= m:
            return c, dev
        n = min(m, n + max(1, n // 3))


# --------------------------------------------------------------------------- surfaces

def _grid_pts(points, name="points"):
    try:
        Q = np.array(points, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of shape (r, s, dim)") from None
    if Q.ndim != 3 or Q.shape[0] < 2 or Q.shape[1] < 2:
        raise ValueError(f"{name} must have shape (r >= 2, s >= 2, dim), got {Q.shape}")
    if not np.all(np.isfinite(Q)):
        raise ValueError(f"{name} must be finite")
    return Q


def _grid_params(Q, method):
    """Averaged parameters along axis 0 of a grid (A9.3)."""
    rows = [parametrize(Q[:, j], method) for j in range(Q.shape[1])]
    return np.mean(rows, axis=0)


def interpolate_surface(points, degree_u=3, degree_v=3, *, method="chord"):
    """B-spline surface through a grid of points (A9.4).

    Parameters
    ----------
    points : (r, s, dim) float
        ``points[k, l]`` is interpolated at ``(u_k, v_l)``.

    Returns
    -------
    BSplineSurface with an ``(r, s)`` control net.

    Examples
    --------
    >>> u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 4), indexing="ij")
    >>> s = interpolate_surface(np.stack([u, v, u * v], -1), 3, 3)
    >>> s.control_points.shape
    (5, 4, 3)
    """
    Q = _grid_pts(points)
    p = _check_degree(degree_u, "degree_u")
    q = _check_degree(degree_v, "degree_v")
    r, s = Q.shape[:2]
    if r < p + 1 or s < q + 1:
        raise ValueError(f"points grid {Q.shape[:2]} too small for degrees ({p}, {q})")
    tu = _grid_params(Q, method)
    tv = _grid_params(np.transpose(Q, (1, 0, 2)), method)
    Uu, Uv = averaged_knots(tu, p), averaged_knots(tv, q)
    Au = basis_matrix(Uu, p, r, tu)
    Av = basis_matrix(Uv, q, s, tv)
    R = np.linalg.solve(Au, Q.reshape(r, -1)).reshape(Q.shape)
    P = np.linalg.solve(Av, np.transpose(R, (1, 0, 2)).reshape(s, -1)).reshape(s, r, -1)
    return BSplineSurface(np.transpose(P, (1, 0, 2)), p, q, Uu, Uv)


def approximate_surface(points, n_control, degree_u=3, degree_v=3, *, method="chord"):
    """Least-squares B-spline surface on a grid of points.

    The tensor problem ``min |Au P Avᵀ - Q|`` separates: ``P = Au⁺ Q (Avᵀ)⁺``.

    Parameters
    ----------
    points : (r, s, dim) float
    n_control : (2,) int
        Control net size ``(n_u, n_v)``, at most ``(r, s)``.

    Returns
    -------
    BSplineSurface
    """
    Q = _grid_pts(points)
    p = _check_degree(degree_u, "degree_u")
    q = _check_degree(degree_v, "degree_v")
    r, s = Q.shape[:2]
    nu, nv = (int(x) for x in n_control)
    if not (p + 1 <= nu <= r and q + 1 <= nv <= s):
        raise ValueError(f"n_control must lie in [{p + 1}, {r}] x [{q + 1}, {s}], got {n_control}")
    tu = _grid_params(Q, method)
    tv = _grid_params(np.transpose(Q, (1, 0, 2)), method)
    Uu = approximation_knots(tu, p, nu) if nu < r else averaged_knots(tu, p)
    Uv = approximation_knots(tv, q, nv) if nv < s else averaged_knots(tv, q)
    Au = basis_matrix(Uu, p, nu, tu)
    Av = basis_matrix(Uv, q, nv, tv)
    P = np.einsum("ia,abd,jb->ijd", np.linalg.pinv(Au), Q, np.linalg.pinv(Av))
    return BSplineSurface(P, p, q, Uu, Uv)


# --------------------------------------------------------------------------- lofting

def _as_spline(c, i):
    if isinstance(c, Bezier):
        c = c.to_bspline()
    if not isinstance(c, BSpline):
        raise TypeError(f"sections[{i}] must be a Bezier, BSpline or NURBS curve, "
                        f"got {type(c).__name__}")
    return c


def _normalized(c):
    """Clamped copy of ``c`` with its domain mapped onto [0, 1]."""
    c = c.clamped()
    a, b = c.domain
    U = (np.asarray(c.knots) - a) / (b - a)
    U[:c.degree + 1] = 0.0
    U[-c.degree - 1:] = 1.0
    return c._from_ctrl(c._ctrl(), c.degree, U)


def make_compatible(curves):
    """Bring curves to one degree and one knot vector (section 10.3).

    Each curve is clamped and mapped onto [0, 1], elevated to the highest degree,
    then refined with the union of all interior knots (largest multiplicity wins).

    Returns
    -------
    list of curves (BSpline, or NURBS if any input is rational), same shape as input.
    """
    cs = [_normalized(_as_spline(c, i)) for i, c in enumerate(curves)]
    rational = any(isinstance(c, NURBS) for c in cs)
    if rational:
        cs = [c.to_nurbs() for c in cs]
    p = max(c.degree for c in cs)
    cs = [c.elevate_degree(p - c.degree) if c.degree < p else c for c in cs]
    mult, value = {}, {}
    for c in cs:
        vals, counts = _ops.distinct_interior(np.asarray(c.knots), p)
        for v, k in zip(vals.tolist(), counts.tolist()):
            key = round(v, 12)
            value.setdefault(key, v)
            mult[key] = max(mult.get(key, 0), k)
    out = []
    for c in cs:
        vals, counts = _ops.distinct_interior(np.asarray(c.knots), p)
        have = {round(v, 12): k for v, k in zip(vals.tolist(), counts.tolist())}
        X = [value[k] for k in mult for _ in range(mult[k] - have.get(k, 0))]
        c = c.refine_knots(np.asarray(X, dtype=float)) if X else c
        # snap knots that agree to 1e-12 onto one shared value
        U = np.array(c.knots)
        inner = slice(p + 1, U.size - p - 1)
        U[inner] = [value.get(round(x, 12), x) for x in U[inner]]
        out.append(c._from_ctrl(c._ctrl(), p, U))
    return out


def loft(curves_or_sections, degree_v=3, *, method="chord"):
    """Skinned surface through a sequence of section curves (section 10.3).

    Parameters
    ----------
    curves_or_sections : list of curves, or (k, n, dim) float array
        Curves are made compatible (:func:`make_compatible`); point sections are
        interpolated with common (averaged) parameters and knots first.
    degree_v : int
        Degree across the sections (lowered to ``k - 1`` if fewer sections).

    Returns
    -------
    BSplineSurface (NURBSSurface for rational sections) with ``u`` along the
    sections and ``v`` across them; ``S(u, v_k)`` is section ``k``.

    Examples
    --------
    >>> from parametric.conics import circle
    >>> rings = [circle(r, center=(0, 0, z)) for r, z in ((1.0, 0.0), (2.0, 1.0), (1.0, 2.0))]
    >>> vase = loft(rings, degree_v=2)
    >>> round(float(np.linalg.norm(vase(0.3, 1.0) - [0, 0, 2])), 12)
    1.0
    """
    q0 = _check_degree(degree_v, "degree_v")
    if isinstance(curves_or_sections, np.ndarray) or (
            len(curves_or_sections) and not isinstance(curves_or_sections[0], Curve)):
        S = np.asarray(curves_or_sections, dtype=float)
        if S.ndim != 3 or S.shape[0] < 2 or S.shape[1] < 2:
            raise ValueError(f"sections must have shape (k >= 2, n >= 2, dim), got {S.shape}")
        p = min(3, S.shape[1] - 1)
        t = _grid_params(np.transpose(S, (1, 0, 2)), method)
        curves = [interpolate_curve(sec, p, params=t) for sec in S]
    else:
        curves = list(curves_or_sections)
        if len(curves) < 2:
            raise ValueError(f"loft needs at least 2 sections, got {len(curves)}")
        curves = make_compatible(curves)
    dims = {c.dim for c in curves}
    if len(dims) != 1:
        raise ValueError(f"sections must share one dimension, got {sorted(dims)}")
    k = len(curves)
    q = min(q0, k - 1)
    rational = isinstance(curves[0], NURBS)
    C = np.stack([c._ctrl() for c in curves], axis=1)  # (n, k, D)
    pts = C[..., :-1] / C[..., -1:] if rational else C
    # v parameters: averaged chord (or centripetal) lengths across the control points
    tv = _grid_params(np.transpose(pts, (1, 0, 2)), method)
    Uv = averaged_knots(tv, q)
    Av = basis_matrix(Uv, q, k, tv)
    n, _, D = C.shape
    P = np.linalg.solve(Av, np.transpose(C, (1, 0, 2)).reshape(k, -1)).reshape(k, n, D)
    P = np.transpose(P, (1, 0, 2))
    p, Uu = curves[0].degree, np.asarray(curves[0].knots)
    if rational:
        return NURBSSurface.from_homogeneous(P, p, q, Uu, Uv)
    return BSplineSurface(P, p, q, Uu, Uv)


# --------------------------------------------------------------------------- star-shaped

def fit_periodic_surface(radii, *, center=(0.0, 0.0, 0.0), n_control=(16, 8), degree=(3, 3),
                         samples=(64, 33)):
    """Least-squares closed B-spline surface of a star-shaped boundary ``r(theta, phi)``.

    Data points ``c + r (sin phi cos theta, sin phi sin theta, cos phi)`` on a
    ``(theta, phi)`` grid are fitted by a tensor B-spline that is periodic in
    ``u = theta / 2 pi`` and clamped in ``v = 1 - phi / pi`` (south pole at
    ``v = 0``, so ``Su x Sv`` points outward). The first and last control rows
    in ``v`` are pinned to the two pole points (the mean of the data there), so
    the surface closes at the poles; the remaining rows solve the separable
    least-squares problem.

    Parameters
    ----------
    radii : (n_theta, n_phi) float, or callable ``r(theta, phi)``
        Samples at ``theta_i = 2 pi i / n_theta`` and ``phi_j = pi j / (n_phi - 1)``
        (both poles included), or a function sampled on ``samples``.
    center : (3,) float
    n_control : (2,) int
        Distinct control points around (``u``) and from pole to pole (``v``).
    degree : (2,) int
    samples : (2,) int
        Grid used when ``radii`` is callable.

    Returns
    -------
    surface : BSplineSurface
        Domain [0, 1]²; ``S(0, v) == S(1, v)``.
    max_deviation : float
        Largest distance between a data point and the surface at its parameters.

    Examples
    --------
    >>> s, dev = fit_periodic_surface(lambda th, ph: 1.0 + 0 * th, n_control=(12, 8),
    ...                               samples=(48, 25))
    >>> bool(dev < 1e-2), s(0.0, 1.0).round(12).tolist()
    (True, [0.0, 0.0, 1.0])
    """
    if callable(radii):
        nt, nph = (int(x) for x in samples)
        th = 2 * np.pi * np.arange(nt) / nt
        ph = np.linspace(0.0, np.pi, nph)
        T, PH = np.meshgrid(th, ph, indexing="ij")
        R = np.asarray(radii(T, PH), dtype=float) * np.ones_like(T)
    else:
        try:
            R = np.array(radii, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("radii must be a (n_theta, n_phi) array or a callable") from None
        if R.ndim != 2:
            raise ValueError(f"radii must have shape (n_theta, n_phi), got {R.shape}")
    if not np.all(np.isfinite(R)) or np.any(R < 0):
        raise ValueError("radii must be finite and >= 0")
    nt, nph = R.shape
    p, q = (_check_degree(d, "degree") for d in degree)
    nu, nv = (int(x) for x in n_control)
    if not p + 1 <= nu <= nt:
        raise ValueError(f"n_control[0] must lie in [{p + 1}, n_theta = {nt}], got {nu}")
    if not max(q + 1, 3) <= nv <= nph:
        raise ValueError(f"n_control[1] must lie in [{max(q + 1, 3)}, n_phi = {nph}], got {nv}")
    c = np.asarray(center, dtype=float).ravel()
    th = 2 * np.pi * np.arange(nt) / nt
    ph = np.linspace(0.0, np.pi, nph)
    T, PH = np.meshgrid(th, ph, indexing="ij")
    X = c + R[..., None] * np.stack([np.sin(PH) * np.cos(T), np.sin(PH) * np.sin(T),
                                     np.cos(PH)], axis=-1)
    tu = th / (2 * np.pi)
    tv = 1.0 - ph / np.pi
    Au, Uu = _periodic_basis(tu, nu, p)
    Uv = clamped_knots(nv, q)
    Av = basis_matrix(Uv, q, nv, tv)
    north = X[:, 0].mean(axis=0)   # phi = 0 -> v = 1
    south = X[:, -1].mean(axis=0)  # phi = pi -> v = 0
    Rhs = X - Av[None, :, 0, None] * south - Av[None, :, -1, None] * north
    inner = np.einsum("ia,abd,jb->ijd", np.linalg.pinv(Au), Rhs, np.linalg.pinv(Av[:, 1:-1]))
    P = np.empty((nu, nv, 3))
    P[:, 0] = south
    P[:, -1] = north
    P[:, 1:-1] = inner
    P = np.concatenate([P, P[:p]], axis=0)
    surf = BSplineSurface(P, p, q, Uu, Uv)
    fit = surf.grid(np.clip(tu, 0, 1), tv)
    return surf, float(np.max(np.linalg.norm(fit - X, axis=-1)))
