"""Exact conics as NURBS curves.

A rational quadratic Bezier with weights ``(1, w, 1)`` is an ellipse arc for
``w < 1``, a parabola arc for ``w = 1`` and a hyperbola arc for ``w > 1``; a
circular arc of sweep ``theta`` has ``w = cos(theta / 2)`` (The NURBS Book,
chapter 7; A7.1 for arcs of any sweep).
"""

from __future__ import annotations

import numpy as np

from .curves import NURBS

__all__ = ["conic_arc", "arc", "circle", "ellipse", "parabola", "hyperbola"]


def _frame(center, normal, x_axis, dim):
    c = np.asarray(center, dtype=float).ravel()
    if c.size not in (2, 3):
        raise ValueError(f"center must have 2 or 3 coordinates, got {c.size}")
    if dim == 2 and c.size == 2 and normal is None:
        return c, np.array([1.0, 0.0]), np.array([0.0, 1.0])
    if c.size == 2:
        c = np.append(c, 0.0)
    n = np.array([0.0, 0.0, 1.0]) if normal is None else np.asarray(normal, dtype=float).ravel()
    if n.size != 3 or not np.linalg.norm(n) > 0:
        raise ValueError(f"normal must be a non-zero 3-vector, got {normal!r}")
    n = n / np.linalg.norm(n)
    if x_axis is None:
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        X = helper - n * (helper @ n)
    else:
        X = np.asarray(x_axis, dtype=float).ravel()
        X = X - n * (X @ n)
        if not np.linalg.norm(X) > 1e-12:
            raise ValueError("x_axis must not be parallel to normal")
    X = X / np.linalg.norm(X)
    Y = np.cross(n, X)
    return c, X, Y


def conic_arc(p0, p1, p2, w):
    """Rational quadratic Bezier arc with weights ``(1, w, 1)``.

    Parameters
    ----------
    p0, p2 : (dim,) float
        End points.
    p1 : (dim,) float
        Intersection of the end tangents.
    w : float > 0
        Middle weight: ``< 1`` ellipse, ``== 1`` parabola, ``> 1`` hyperbola.

    Returns
    -------
    NURBS of degree 2 on [0, 1].
    """
    w = float(w)
    if not w > 0:
        raise ValueError(f"w must be > 0, got {w}")
    P = np.array([p0, p1, p2], dtype=float)
    return NURBS(P, [1.0, w, 1.0], 2)


def arc(radius, start_angle, sweep_angle, center=(0.0, 0.0, 0.0), normal=None, x_axis=None):
    """Exact circular arc of any sweep (A7.1), split into segments of at most 90 degrees.

    Parameters
    ----------
    radius : float > 0
    start_angle, sweep_angle : float, radians; ``0 < |sweep_angle| <= 2 pi``
    center : (2,) or (3,) float
        A 2-D center without ``normal`` gives a planar 2-D curve.
    normal : (3,) float, optional
        Plane normal (default +z); the arc turns counter-clockwise about it.
    x_axis : (3,) float, optional
        Direction of angle 0 in the plane.

    Returns
    -------
    NURBS of degree 2 on [0, 1] with ``ceil(|sweep| / 90 deg)`` segments.

    Examples
    --------
    >>> a = arc(2.0, 0.0, np.pi)
    >>> np.allclose(a(0.5), [0.0, 2.0, 0.0])
    True
    """
    r = float(radius)
    if not (r > 0 and np.isfinite(r)):
        raise ValueError(f"radius must be > 0 and finite, got {radius}")
    if not np.isfinite(float(start_angle)):
        raise ValueError(f"start_angle must be a finite angle in radians, got {start_angle}")
    sweep = float(sweep_angle)
    if not 0 < abs(sweep) <= 2 * np.pi + 1e-12:
        raise ValueError(f"sweep_angle must satisfy 0 < |sweep| <= 2 pi, got {sweep}")
    c = np.asarray(center, dtype=float).ravel()
    dim = 2 if (c.size == 2 and normal is None) else 3
    O, X, Y = _frame(center, normal, x_axis, dim)
    nseg = int(np.ceil(abs(sweep) / (np.pi / 2) - 1e-12))
    d = sweep / nseg
    ang_ends = float(start_angle) + d * np.arange(nseg + 1)
    ang_mid = ang_ends[:-1] + d / 2
    w_mid = np.cos(d / 2)
    ends = O + r * (np.cos(ang_ends)[:, None] * X + np.sin(ang_ends)[:, None] * Y)
    mids = O + (r / w_mid) * (np.cos(ang_mid)[:, None] * X + np.sin(ang_mid)[:, None] * Y)
    P = np.empty((2 * nseg + 1, O.size))
    P[0::2] = ends
    P[1::2] = mids
    if abs(abs(sweep) - 2 * np.pi) < 1e-12:
        P[-1] = P[0]
    W = np.ones(2 * nseg + 1)
    W[1::2] = w_mid
    inner = np.repeat(np.arange(1, nseg) / nseg, 2)
    U = np.concatenate([[0.0] * 3, inner, [1.0] * 3])
    return NURBS(P, W, 2, U)


def circle(radius=1.0, center=(0.0, 0.0, 0.0), normal=None, x_axis=None):
    """Exact full circle: four 90-degree rational quadratic segments (9 control points).

    Examples
    --------
    >>> c = circle(3.0, center=(0, 0))
    >>> round(float(np.linalg.norm(c(0.37))), 12)
    3.0
    """
    return arc(radius, 0.0, 2 * np.pi, center=center, normal=normal, x_axis=x_axis)


def ellipse(a, b, center=(0.0, 0.0, 0.0), normal=None, x_axis=None):
    """Exact ellipse ``x²/a² + y²/b² = 1`` (in its plane): the circle scaled per axis.

    Affine maps act on NURBS control points exactly, so scaling the circle's
    control points by ``(a, b)`` keeps the weights ``(1, sqrt(2)/2, 1)``.

    Examples
    --------
    >>> x, y = ellipse(3.0, 2.0, center=(0, 0))(0.1)
    >>> round(float(x * x / 9 + y * y / 4), 12)
    1.0
    """
    a, b = float(a), float(b)
    if not (a > 0 and b > 0 and np.isfinite(a) and np.isfinite(b)):
        raise ValueError(f"a and b must be > 0 and finite, got a={a}, b={b}")
    unit = arc(1.0, 0.0, 2 * np.pi, center=(0.0, 0.0))
    local = unit.control_points * np.array([a, b])
    c = np.asarray(center, dtype=float).ravel()
    dim = 2 if (c.size == 2 and normal is None) else 3
    O, X, Y = _frame(center, normal, x_axis, dim)
    P = O + local[:, :1] * X + local[:, 1:] * Y
    return NURBS(P, unit.weights, 2, unit.knots)


def parabola(a=1.0, x_range=(-1.0, 1.0)):
    """Arc of the parabola ``y = a x²`` for ``x`` in ``x_range`` (weights 1, 1, 1).

    The middle control point is the intersection of the end tangents,
    ``((x0 + x1) / 2, a x0 x1)``.

    Examples
    --------
    >>> x, y = parabola(2.0, (-1.0, 3.0))(0.3)
    >>> abs(float(y - 2.0 * x * x)) < 1e-14
    True
    """
    a = float(a)
    x0, x1 = (float(x) for x in x_range)
    if not (a != 0 and np.isfinite(a)):
        raise ValueError(f"a must be a finite nonzero number, got a={a}")
    if not (np.isfinite(x0) and np.isfinite(x1) and x0 < x1):
        raise ValueError(f"x_range must be finite with x_range[0] < x_range[1], got {x_range}")
    P = [[x0, a * x0 * x0], [(x0 + x1) / 2.0, a * x0 * x1], [x1, a * x1 * x1]]
    return conic_arc(P[0], P[1], P[2], 1.0)


def hyperbola(a=1.0, b=1.0, t_range=(-1.0, 1.0)):
    """Arc of the hyperbola ``x²/a² - y²/b² = 1`` (right branch), ``(a cosh t, b sinh t)``.

    For ``t`` in ``[t0, t1]`` the middle weight is ``cosh((t1 - t0) / 2) > 1`` and the
    middle control point is ``(a cosh m, b sinh m) / cosh((t1 - t0) / 2)`` with
    ``m = (t0 + t1) / 2``.

    Examples
    --------
    >>> x, y = hyperbola(2.0, 3.0, (-1.0, 2.0))(0.6)
    >>> round(float(x * x / 4 - y * y / 9), 12)
    1.0
    """
    a, b = float(a), float(b)
    t0, t1 = (float(t) for t in t_range)
    if not (a > 0 and b > 0 and t0 < t1 and np.all(np.isfinite([a, b, t0, t1]))):
        raise ValueError(f"need a, b > 0 and t_range[0] < t_range[1], got a={a}, b={b}, {t_range}")
    s = (t1 - t0) / 2.0
    m = (t0 + t1) / 2.0
    w = np.cosh(s)
    P0 = [a * np.cosh(t0), b * np.sinh(t0)]
    P2 = [a * np.cosh(t1), b * np.sinh(t1)]
    P1 = [a * np.cosh(m) / w, b * np.sinh(m) / w]
    return conic_arc(P0, P1, P2, w)
