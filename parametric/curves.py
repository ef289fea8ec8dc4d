"""Parametric curves: Hermite, Bezier, B-spline and NURBS.

Every curve is immutable (editing returns a new object) and evaluates in batches:
``curve(u)`` takes a scalar or an ``(n,)`` array and returns ``(n, dim)`` points
(``(dim,)`` for a scalar). Parameters outside :attr:`Curve.domain` raise
``ValueError`` naming ``u``.

References: L. Piegl and W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997,
doi:10.1007/978-3-642-59223-2 (algorithm numbers A2.x-A5.x are cited per method).
"""

from __future__ import annotations

import numpy as np

from . import _ops
from .basis import _check_degree, bernstein, clamped_knots, periodic_knots, validate_knots
from .curve_base import Curve, FunctionCurve, _check_order, _points, _vector  # noqa: F401

__all__ = ["Curve", "FunctionCurve", "Hermite", "Bezier", "BSpline", "NURBS"]


# --------------------------------------------------------------------------- Hermite

_HERMITE = np.array([[1.0, 0.0, -3.0, 2.0],    # 1 - 3u^2 + 2u^3
                     [0.0, 0.0, 3.0, -2.0],    # 3u^2 - 2u^3
                     [0.0, 1.0, -2.0, 1.0],    # u - 2u^2 + u^3
                     [0.0, 0.0, -1.0, 1.0]])   # -u^2 + u^3


def _power_derivs(u, order):
    """Rows ``d^k/du^k [1, u, u^2, u^3]`` for k = 0..order: (n, order+1, 4)."""
    out = np.zeros((u.shape[0], order + 1, 4))
    for k in range(order + 1):
        for i in range(k, 4):
            out[:, k, i] = (np.prod(np.arange(i - k + 1, i + 1)) if k else 1.0) * u ** (i - k)
    return out


class Hermite(Curve):
    """Cubic Hermite curve from end points and end tangents.

    ``P(u) = [1-3u²+2u³, 3u²-2u³, u-2u²+u³, -u²+u³] · [P0, P1, P0', P1']``,
    ``u in [0, 1]``.

    Parameters
    ----------
    p0, p1 : (dim,) float
        End points.
    t0, t1 : (dim,) float
        Tangent vectors ``P'(0)`` and ``P'(1)``.

    Examples
    --------
    >>> h = Hermite([0, 0], [1, 0], [1, 1], [1, -1])
    >>> h(0.5)
    array([0.5 , 0.25])
    """

    def __init__(self, p0, p1, t0, t1):
        vecs = [_vector(v, n) for v, n in ((p0, "p0"), (p1, "p1"), (t0, "t0"), (t1, "t1"))]
        dims = {v.size for v in vecs}
        if len(dims) != 1:
            raise ValueError(f"p0, p1, t0, t1 must share one dimension, got sizes {[v.size for v in vecs]}")
        self._G = np.stack(vecs)
        self._G.setflags(write=False)
        self._dim = vecs[0].size

    @property
    def geometry(self):
        """(4, dim) geometric coefficients [P0, P1, P0', P1']."""
        return self._G

    @staticmethod
    def blending_functions(u):
        """Hermite blending functions at ``u``: (n, 4) (``(4,)`` for a scalar)."""
        uu = np.asarray(u, dtype=float)
        scalar = uu.ndim == 0
        uu = np.atleast_1d(uu)
        out = _power_derivs(uu, 0)[:, 0, :] @ _HERMITE.T
        return out[0] if scalar else out

    def _eval(self, u):
        return (_power_derivs(u, 0)[:, 0, :] @ _HERMITE.T) @ self._G

    def _derivs(self, u, order):
        pw = _power_derivs(u, order)  # (n, k, 4)
        return np.einsum("nki,ji,jd->nkd", pw, _HERMITE, self._G)

    def to_bezier(self):
        """The same curve as a cubic :class:`Bezier`."""
        P0, P1, T0, T1 = self._G
        return Bezier(np.stack([P0, P0 + T0 / 3.0, P1 - T1 / 3.0, P1]))

    def to_bspline(self):
        """The same curve as a clamped cubic :class:`BSpline` (Bezier knots)."""
        return self.to_bezier().to_bspline()

    def to_nurbs(self):
        """The same curve as a cubic :class:`NURBS` with all weights 1."""
        return self.to_bezier().to_nurbs()

    def derivative_curve(self):
        """The derivative ``P'(u)`` as a quadratic :class:`Bezier` (the hodograph)."""
        return self.to_bezier().derivative_curve()

    def __repr__(self):
        return f"Hermite(dim={self._dim})"


# --------------------------------------------------------------------------- Bezier

class Bezier(Curve):
    """Bezier curve of any degree and dimension on ``u in [0, 1]``.

    Parameters
    ----------
    control_points : (n + 1, dim) float
        Control polygon; the degree is ``n``.

    Examples
    --------
    >>> b = Bezier([[0, 0], [1, 2], [2, 0]])
    >>> b(0.5)
    array([1., 1.])
    >>> left, right = b.split(0.5)
    """

    def __init__(self, control_points):
        self._P = _points(control_points, "control_points", min_rows=1)
        self._dim = self._P.shape[1]

    @property
    def control_points(self):
        """(n + 1, dim) read-only control polygon."""
        return self._P

    @property
    def degree(self):
        return self._P.shape[0] - 1

    def _eval(self, u):
        return bernstein(self.degree, u) @ self._P

    def _derivs(self, u, order):
        out = np.zeros((u.shape[0], order + 1, self._dim))
        Q = self._P
        n = self.degree
        for k in range(order + 1):
            if Q.shape[0] == 0:
                break
            out[:, k, :] = bernstein(Q.shape[0] - 1, u) @ Q
            Q = (n - k) * np.diff(Q, axis=0)
        return out

    def de_casteljau(self, u):
        """Evaluate by de Casteljau's algorithm (vectorized over ``u``).

        Returns
        -------
        (n, dim) float array (``(dim,)`` for a scalar).
        """
        uu, scalar = self._params(u)
        Q = np.broadcast_to(self._P, (uu.size,) + self._P.shape).copy()
        t = uu[:, None, None]
        for k in range(self.degree):
            Q = (1.0 - t) * Q[:, :-1] + t * Q[:, 1:]
        out = Q[:, 0, :]
        return out[0] if scalar else out

    def derivative_curve(self):
        """Hodograph: the derivative as a Bezier of degree ``n - 1``."""
        if self.degree == 0:
            return Bezier(np.zeros((1, self._dim)))
        return Bezier(self.degree * np.diff(self._P, axis=0))

    def split(self, u):
        """Subdivide at ``u`` into two Bezier curves covering [0, u] and [u, 1]."""
        uu, _ = self._params(u)
        t = float(uu[0])
        if not 0.0 < t < 1.0:
            raise ValueError(f"u must lie strictly inside (0, 1) to split, got {t}")
        Q = self._P.copy()
        left = [Q[0].copy()]
        right = [Q[-1].copy()]
        for _ in range(self.degree):
            Q = (1.0 - t) * Q[:-1] + t * Q[1:]
            left.append(Q[0].copy())
            right.append(Q[-1].copy())
        return Bezier(np.array(left)), Bezier(np.array(right[::-1]))

    def elevate_degree(self, times=1):
        """Same curve with degree raised by ``times`` (eq. 5.36)."""
        times = _check_degree(times, "times", minimum=0)
        Q = self._P
        for _ in range(times):
            n = Q.shape[0] - 1
            i = np.arange(1, n + 1)[:, None] / (n + 1.0)
            mid = i * Q[:-1] + (1.0 - i) * Q[1:]
            Q = np.concatenate([Q[:1], mid, Q[-1:]])
        return Bezier(Q)

    def to_bspline(self):
        """The same curve as a clamped :class:`BSpline` with Bezier knots."""
        p = max(self.degree, 1)
        Q = self._P if self.degree >= 1 else np.repeat(self._P, 2, axis=0)
        return BSpline(Q, p, np.concatenate([np.zeros(p + 1), np.ones(p + 1)]))

    def to_nurbs(self):
        return self.to_bspline().to_nurbs()

    def __repr__(self):
        return f"Bezier(degree={self.degree}, dim={self._dim})"


# --------------------------------------------------------------------------- B-spline

class BSpline(Curve):
    """Non-rational B-spline curve.

    Parameters
    ----------
    control_points : (n + 1, dim) float
    degree : int
        ``1 <= degree <= n``.
    knots : (n + degree + 2,) float, optional
        Non-decreasing knot vector; clamped uniform on [0, 1] by default.
        Unclamped and periodic vectors are accepted (the domain is
        ``[U[p], U[n + 1]]``).

    Examples
    --------
    >>> c = BSpline([[0, 0], [1, 1], [2, 0], [3, 1]], 2)
    >>> c([0.0, 1.0])
    array([[0., 0.],
           [3., 1.]])
    >>> bool(np.allclose(c.insert_knot(0.25)(0.3), c(0.3), atol=1e-14))
    True
    """

    def __init__(self, control_points, degree, knots=None):
        P = _points(control_points, "control_points", min_rows=2)
        p = _check_degree(degree)
        if P.shape[0] < p + 1:
            raise ValueError(
                f"control_points: degree {p} needs at least {p + 1} points, got {P.shape[0]}")
        U = clamped_knots(P.shape[0], p) if knots is None else knots
        self._U = validate_knots(U, p, P.shape[0])
        self._P = P
        self._p = p
        self._dim = P.shape[1]
        self._domain = _ops.domain(self._U, p)

    @classmethod
    def periodic(cls, control_points, degree, domain=(0.0, 1.0)):
        """Closed C^(p-1) curve through the cyclic polygon ``control_points``.

        The first ``degree`` points are repeated at the end and the knot vector
        is uniform (:func:`parametric.basis.periodic_knots`), so ``C(a) == C(b)``
        with all derivatives up to ``degree - 1`` equal.
        """
        P = _points(control_points, "control_points", min_rows=2)
        p = _check_degree(degree)
        if P.shape[0] < p + 1:
            raise ValueError(f"control_points: periodic degree {p} needs >= {p + 1} points")
        return cls(np.concatenate([P, P[:p]]), p, periodic_knots(P.shape[0], p, domain))

    @property
    def control_points(self):
        """(n + 1, dim) read-only control points."""
        return self._P

    @property
    def degree(self):
        return self._p

    @property
    def knots(self):
        """Read-only knot vector."""
        return self._U

    def _fast(self, u):
        """Evaluate the (homogeneous) control array at many parameters."""
        ctrl = self._ctrl()
        if u.shape[0] < _ops.POLY_MIN_POINTS:
            return _ops.eval_points(self._U, self._p, ctrl, u)
        table = self.__dict__.get("_table")
        if table is None:
            table = _ops.PolyTable(self._U, self._p, ctrl)
            self.__dict__["_table"] = table
        return table(u).T

    def _eval(self, u):
        return self._fast(u)

    def _derivs(self, u, order):
        return _ops.eval_derivs(self._U, self._p, self._P, u, order)

    def derivative_curve(self):
        """The derivative as a B-spline of degree ``p - 1`` (eq. 3.8)."""
        if self._p == 1:
            raise ValueError("derivative_curve of a degree-1 curve would have degree 0")
        U, Q = _ops.derivative_control(self._U, self._p, self._P)
        return BSpline(Q, self._p - 1, U)

    def insert_knot(self, u, times=1):
        """Insert knot ``u`` ``times`` times (Boehm, A5.1); the curve is unchanged."""
        times = _check_degree(times, "times", minimum=1)
        U, Q = _ops.insert_knot(self._U, self._p, self._ctrl(), float(u), times)
        return self._from_ctrl(Q, self._p, U)

    def refine_knots(self, new_knots):
        """Insert many knots at once (A5.4); the curve is unchanged."""
        U, Q = _ops.refine(self._U, self._p, self._ctrl(), new_knots)
        return self._from_ctrl(Q, self._p, U)

    def remove_knot(self, u, times=1, *, tol=1e-9):
        """Remove knot ``u`` ``times`` times (A5.8) if the curve moves by <= ``tol``.

        Raises
        ------
        ValueError
            If ``u`` is not an interior knot, or fewer than ``times`` removals keep
            the curve within ``tol`` (the message says how many would).
        """
        times = _check_degree(times, "times", minimum=1)
        U, Q, done = _ops.remove_knot(self._U, self._p, self._ctrl(), float(u), times, float(tol))
        if done < times:
            raise ValueError(f"knot u={u} can be removed only {done} of {times} time(s) "
                             f"within tol={tol}")
        return self._from_ctrl(Q, self._p, U)

    def elevate_degree(self, times=1):
        """Raise the degree by ``times``; the curve is unchanged.

        The curve is split into Bezier pieces, each piece is elevated (eq. 5.36)
        and the surplus interior knots are removed again (A5.8), which is the
        route of section 5.5 of The NURBS Book. Every distinct interior knot
        gains ``times`` in multiplicity (so the continuity is kept); the result
        is clamped on the same domain, except for a periodic curve (as built by
        :meth:`periodic`): it is unwrapped over one period, elevated and
        wrapped again, so the result is periodic with the same continuity at
        the seam.
        """
        times = _check_degree(times, "times", minimum=0)
        if times == 0:
            return self
        U, Q = _ops.elevate(self._U, self._p, self._ctrl(), times)
        return self._from_ctrl(Q, self._p + times, U)

    def clamped(self):
        """The same curve with a clamped knot vector on the same domain."""
        U, Q = _ops.clamp(self._U, self._p, self._ctrl())
        return self._from_ctrl(Q, self._p, U)

    def to_bezier_segments(self):
        """Bezier pieces, one per non-empty knot span.

        Returns
        -------
        list of :class:`Bezier`; piece ``i`` maps ``t in [0, 1]`` to the span
        ``[k_i, k_{i+1}]`` via ``u = k_i + t (k_{i+1} - k_i)``.
        """
        return [Bezier(Q) for _, _, Q in _ops.bezier_segments(self._U, self._p, self._P)]

    def to_nurbs(self):
        """The same curve as a :class:`NURBS` with all weights 1."""
        return NURBS(self._P, np.ones(self._P.shape[0]), self._p, self._U)

    # hooks letting NURBS reuse the editing methods in homogeneous space
    def _ctrl(self):
        return self._P

    def _from_ctrl(self, Q, p, U):
        return BSpline(Q, p, U)

    def __repr__(self):
        return f"BSpline(degree={self._p}, n_control={self._P.shape[0]}, dim={self._dim})"


# --------------------------------------------------------------------------- NURBS

class NURBS(BSpline):
    """Non-uniform rational B-spline curve.

    ``P(u) = sum h_i P_i N_i(u) / sum h_i N_i(u)``, evaluated in homogeneous
    coordinates ``(h_i P_i, h_i)``.

    Parameters
    ----------
    control_points : (n + 1, dim) float
    weights : (n + 1,) float, all > 0
    degree : int
    knots : (n + degree + 2,) float, optional (clamped uniform by default)

    Examples
    --------
    >>> w = np.sqrt(0.5)
    >>> quarter = NURBS([[1, 0], [1, 1], [0, 1]], [1, w, 1], 2)
    >>> round(float(np.linalg.norm(quarter(0.3))), 12)
    1.0
    """

    def __init__(self, control_points, weights, degree, knots=None):
        super().__init__(control_points, degree, knots)
        w = _vector(weights, "weights")
        if w.size != self._P.shape[0]:
            raise ValueError(
                f"weights must have one value per control point ({self._P.shape[0]}), got {w.size}")
        if not np.all((w > 0) & np.isfinite(w)):
            raise ValueError("weights must be > 0 and finite")
        self._w = w
        Pw = np.concatenate([self._P * w[:, None], w[:, None]], axis=1)
        Pw.setflags(write=False)
        self._Pw = Pw

    @classmethod
    def from_homogeneous(cls, Pw, degree, knots):
        Pw = np.asarray(Pw, dtype=float)
        w = Pw[:, -1]
        return cls(Pw[:, :-1] / w[:, None], w, degree, knots)

    @classmethod
    def periodic(cls, control_points, weights, degree, domain=(0.0, 1.0)):
        """Closed rational curve (see :meth:`BSpline.periodic`)."""
        P = _points(control_points, "control_points", min_rows=2)
        w = _vector(weights, "weights")
        p = _check_degree(degree)
        return cls(np.concatenate([P, P[:p]]), np.concatenate([w, w[:p]]), p,
                   periodic_knots(P.shape[0], p, domain))

    @property
    def weights(self):
        """(n + 1,) read-only weights."""
        return self._w

    @property
    def homogeneous(self):
        """(n + 1, dim + 1) homogeneous control points ``(w P, w)``."""
        return self._Pw

    def _eval(self, u):
        h = self._fast(u)
        return h[:, :-1] / h[:, -1:]

    def _derivs(self, u, order):
        """Rational derivatives from homogeneous ones (A4.2, vectorized)."""
        from scipy.special import comb  # local: scipy.special costs 0.1 s to import

        H = _ops.eval_derivs(self._U, self._p, self._Pw, u, order)
        A, w = H[:, :, :-1], H[:, :, -1]
        C = np.empty_like(A)
        for k in range(order + 1):
            v = A[:, k].copy()
            for i in range(1, k + 1):
                v -= comb(k, i) * w[:, i, None] * C[:, k - i]
            C[:, k] = v / w[:, 0, None]
        return C

    def _ctrl(self):
        return self._Pw

    def _from_ctrl(self, Q, p, U):
        return NURBS.from_homogeneous(Q, p, U)

    def derivative_curve(self, *, tol=1e-9):
        """The exact derivative ``C'(u)`` as a :class:`NURBS` of degree ``2 p``.

        The derivative of ``C = A / w`` is ``(A' w - A w') / w^2``: on every
        Bezier piece the numerator (degree ``2 p - 1``, elevated once) and
        ``w^2`` are formed with Bezier products, and the pieces are joined with
        the knots they share; a knot of multiplicity ``m < p`` keeps
        multiplicity ``p + m + 1`` (the derivative is ``C^(p - m - 1)`` there),
        the surplus being removed within ``tol`` (relative; rounding only).
        The result is again a NURBS, so derivatives of any order follow by
        calling this method again. The derivative of a periodic curve (see
        :meth:`periodic`) without knots of multiplicity ``p`` is periodic too.

        Raises
        ------
        ValueError
            If the derivative jumps at a knot of multiplicity ``p`` (a corner of
            the curve), where it is not one curve.

        Examples
        --------
        >>> from parametric.conics import circle
        >>> c = circle(1.0, center=(0.0, 0.0))
        >>> d = c.derivative_curve()
        >>> d.degree, bool(np.allclose(d(0.3), c.derivative(0.3), atol=1e-12))
        (4, True)
        """
        U, Q = _ops.rational_derivative(self._U, self._p, self._Pw, float(tol))
        return NURBS.from_homogeneous(Q, 2 * self._p, U)

    def to_bezier_segments(self):
        """Rational Bezier pieces as NURBS curves on their original knot spans."""
        out = []
        for a, b, Q in _ops.bezier_segments(self._U, self._p, self._Pw):
            U = np.concatenate([np.full(self._p + 1, a), np.full(self._p + 1, b)])
            out.append(NURBS.from_homogeneous(Q, self._p, U))
        return out

    def to_nurbs(self):
        return self

    def with_weights(self, weights):
        """Copy with new weights (same control points, degree and knots)."""
        return NURBS(self._P, weights, self._p, self._U)

    def __repr__(self):
        return f"NURBS(degree={self._p}, n_control={self._P.shape[0]}, dim={self._dim})"
