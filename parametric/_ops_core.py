"""B-spline algorithms on raw arrays: spans, evaluation, knot insertion, refinement, elevation.

The control array has the control index on axis 0 and any trailing shape, so the
same routines serve curves (``(n+1, dim)``), homogeneous NURBS control points
(``(n+1, dim+1)``) and the rows of surfaces and volumes (``(n+1, m, dim)``).
References are to The NURBS Book (Piegl and Tiller, 2nd ed.).
"""

from __future__ import annotations

import numpy as np

from .basis import (KNOT_TOL, basis_funs, basis_matrix, ders_basis_funs, find_span,
                    greville)


def n_ctrl(U, p):
    return len(U) - p - 1


def domain(U, p):
    return float(U[p]), float(U[len(U) - p - 1])


def eval_points(U, p, P, u):
    """Points ``sum_j N_j(u) P_j`` for ``u`` of shape (N,); returns (N, *P.shape[1:])."""
    n1 = P.shape[0]
    tail = P.shape[1:]
    Pf = P.reshape(n1, -1)
    span = find_span(U, p, n1, u)
    N = basis_funs(U, p, span, u)
    base = span - p
    out = N[:, 0, None] * Pf[base]
    for j in range(1, p + 1):
        out += N[:, j, None] * Pf[base + j]
    return out.reshape((u.shape[0],) + tail)


def eval_derivs(U, p, P, u, d):
    """Derivatives of orders 0..d: (N, d+1, *P.shape[1:]) (A3.2 via A2.3)."""
    n1 = P.shape[0]
    tail = P.shape[1:]
    Pf = P.reshape(n1, -1)
    span = find_span(U, p, n1, u)
    ders = ders_basis_funs(U, p, span, u, d)
    base = span - p
    out = np.zeros((u.shape[0], d + 1, Pf.shape[1]))
    for j in range(p + 1):
        out += ders[:, :, j, None] * Pf[base + j][:, None, :]
    return out.reshape((u.shape[0], d + 1) + tail)


def contract(U, p, P, u0):
    """``sum_j N_j(u0) P_j`` for one parameter value (isocurves, faces)."""
    return eval_points(U, p, P, np.array([float(u0)]))[0]


def derivative_control(U, p, P):
    """Control points and knots of the derivative curve (A3.3 / eq. 3.8)."""
    n1 = P.shape[0]
    denom = U[p + 1:p + n1] - U[1:n1]
    shape = (-1,) + (1,) * (P.ndim - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        fac = np.where(denom > 0, p / np.where(denom > 0, denom, 1.0), 0.0)
    Q = fac.reshape(shape) * (P[1:] - P[:-1])
    return U[1:-1].copy(), Q


def _span_and_mult(U, p, u):
    n1 = n_ctrl(U, p)
    k = int(find_span(U, p, n1, np.array([u]))[0])
    tol = KNOT_TOL * max(1.0, float(np.max(np.abs(U))))
    s = int(np.count_nonzero(np.abs(U - u) <= tol))
    return k, s


def insert_knot(U, p, P, u, r=1):
    """Insert ``u`` ``r`` times (Boehm's algorithm, A5.1). Returns (U', P')."""
    a, b = domain(U, p)
    if not (a < u < b):
        raise ValueError(f"u must lie strictly inside the domain ({a}, {b}) to be inserted, got {u}")
    k, s = _span_and_mult(U, p, u)
    if r + s > p:
        raise ValueError(
            f"inserting u={u} {r} time(s) would give multiplicity {r + s} > degree {p}")
    if r <= 0:
        return U.copy(), P.copy()
    n = P.shape[0] - 1
    UQ = np.concatenate([U[:k + 1], np.full(r, float(u)), U[k + 1:]])
    Q = np.empty((n + r + 1,) + P.shape[1:])
    Q[:k - p + 1] = P[:k - p + 1]
    Q[k - s + r:] = P[k - s:]
    R = P[k - p:k - s + 1].copy()
    L = k - p
    for j in range(1, r + 1):
        L = k - p + j
        i = np.arange(p - j - s + 1)
        alpha = (u - U[L + i]) / (U[i + k + 1] - U[L + i])
        alpha = alpha.reshape((-1,) + (1,) * (P.ndim - 1))
        R[:p - j - s + 1] = alpha * R[1:p - j - s + 2] + (1.0 - alpha) * R[:p - j - s + 1]
        Q[L] = R[0]
        Q[k + r - j - s] = R[p - j - s]
    for i in range(L + 1, k - s):
        Q[i] = R[i - L]
    return UQ, Q


def refine(U, p, P, X):
    """Knot refinement: insert all values of sorted ``X`` at once (A5.4)."""
    X = np.sort(np.asarray(X, dtype=float).ravel())
    if not np.all(np.isfinite(X)):
        raise ValueError(f"new_knots must be finite numbers, got {X.tolist()!r}")
    if X.size == 0:
        return U.copy(), P.copy()
    a, b = domain(U, p)
    if X[0] <= a or X[-1] >= b:
        raise ValueError(f"new_knots must lie strictly inside the domain ({a}, {b})")
    allk = np.concatenate([U, X])
    vals, counts = np.unique(allk[(allk > a) & (allk < b)], return_counts=True)
    if np.any(counts > p):
        raise ValueError(
            f"new_knots would raise knot {vals[counts > p][0]} above multiplicity {p}")
    n = P.shape[0] - 1
    m = n + p + 1
    r = X.size - 1
    n1 = n + 1
    a_ = int(find_span(U, p, n1, X[:1])[0])
    b_ = int(find_span(U, p, n1, X[-1:])[0]) + 1
    Ub = np.empty(m + r + 2)
    Q = np.empty((n + r + 2,) + P.shape[1:])
    Q[:a_ - p + 1] = P[:a_ - p + 1]
    Q[b_ - 1 + r + 1:n + r + 2] = P[b_ - 1:n + 1]
    Ub[:a_ + 1] = U[:a_ + 1]
    Ub[b_ + p + r + 1:m + r + 2] = U[b_ + p:m + 1]
    i = b_ + p - 1
    k = b_ + p + r
    for j in range(r, -1, -1):
        while X[j] <= U[i] and i > a_:
            Q[k - p - 1] = P[i - p - 1]
            Ub[k] = U[i]
            k -= 1
            i -= 1
        Q[k - p - 1] = Q[k - p]
        for l in range(1, p + 1):
            ind = k - p + l
            alfa = Ub[k + l] - X[j]
            if abs(alfa) == 0.0:
                Q[ind - 1] = Q[ind]
            else:
                alfa = alfa / (Ub[k + l] - U[i - p + l])
                Q[ind - 1] = alfa * Q[ind - 1] + (1.0 - alfa) * Q[ind]
        Ub[k] = X[j]
        k -= 1
    return Ub, Q


def collocate(func, U_new, p_new):
    """Control points of the spline in (U_new, p_new) that equals ``func``.

    ``func`` maps (N,) parameters to (N, ...) values and must lie in the spline
    space; the values are matched at the Greville abscissae, which satisfy the
    Schoenberg-Whitney condition, so the square system is nonsingular.
    """
    n1 = len(U_new) - p_new - 1
    g = greville(U_new, p_new)
    a, b = domain(U_new, p_new)
    g = np.clip(g, a, b)
    vals = func(g)
    tail = vals.shape[1:]
    # the collocation matrix is banded: row i holds N_{span-p..span}(g_i)
    span = find_span(U_new, p_new, n1, g)
    N = basis_funs(U_new, p_new, span, g)
    rows = np.arange(n1)[:, None]
    cols = span[:, None] - p_new + np.arange(p_new + 1)
    lower = int(max(0, np.max(rows - cols)))
    upper = int(max(0, np.max(cols - rows)))
    ab = np.zeros((lower + upper + 1, n1))
    ab[upper + rows - cols, cols] = N
    from scipy.linalg import solve_banded  # local: scipy.linalg costs 0.1 s to import

    Q = solve_banded((lower, upper), ab, vals.reshape(n1, -1))
    return Q.reshape((n1,) + tail)


def distinct_interior(U, p):
    a, b = domain(U, p)
    inner = U[(U > a) & (U < b)]
    vals, counts = np.unique(inner, return_counts=True)
    return vals, counts


def clamp(U, p, P):
    """Same curve on its domain with a clamped knot vector (no change if clamped)."""
    a, b = domain(U, p)
    if np.all(U[:p + 1] == a) and np.all(U[-p - 1:] == b):
        return U.copy(), P.copy()
    vals, counts = distinct_interior(U, p)
    Un = np.concatenate([np.full(p + 1, a), np.repeat(vals, counts), np.full(p + 1, b)])
    Q = collocate(lambda t: eval_points(U, p, P, t), Un, p)
    return Un, Q


def periodic_count(U, p, P):
    """Number of distinct control points if (U, p, P) is a wrapped periodic spline, else 0.

    A periodic spline of ``k`` distinct control points is stored with the first
    ``p`` repeated at the end and a knot vector whose spacings repeat with
    period ``k`` (``U[i + k] - U[i] == U[n + 1] - U[p]`` for every ``i``), as
    :meth:`parametric.curves.BSpline.periodic` builds it.
    """
    n1 = P.shape[0]
    k = n1 - p
    a, b = domain(U, p)
    if np.all(U[:p + 1] == a) or k < p + 1:
        return 0
    T = b - a
    tol = 64 * KNOT_TOL * max(1.0, float(np.max(np.abs(U))))
    if not np.all(np.abs(U[k:] - U[:-k] - T) <= tol):
        return 0
    flat = P.reshape(n1, -1)
    size = max(1.0, float(np.max(np.abs(flat))))
    if not np.all(np.abs(flat[k:] - flat[:p]) <= 1e-12 * size):
        return 0
    return k


def periodic_knots_from(vals, mult, q, a, b):
    """Wrapped knot vector of degree ``q`` from the knots of one period.

    ``vals`` in ``[a, b)`` with multiplicities ``mult`` (``vals[0] == a``);
    returns ``(K + 2 q + 1,)`` knots with domain ``[a, b]``, ``K = sum(mult)``.
    """
    s = np.repeat(vals, mult)
    K = s.size
    T = b - a
    idx = np.arange(-q, K + q + 1)
    return s[idx % K] + T * np.floor_divide(idx, K)


def fold_collocate(func, Un, q, K):
    """Control points of the periodic spline (Un, q) with ``K`` distinct points equal to ``func``.

    The wrapped basis columns ``j`` and ``j + K`` are summed (they share one
    control point) and the values are matched in the least-squares sense at
    ``3 K`` parameters of one period (exact when ``func`` lies in the space).
    Returns the wrapped control array ``(K + q, ...)``.
    """
    a, b = domain(Un, q)
    x = a + (b - a) * (np.arange(3 * K) + 0.5) / (3 * K)
    B = basis_matrix(Un, q, K + q, x)
    F = B[:, :K].copy()
    F[:, :q] += B[:, K:]
    vals = func(x)
    tail = vals.shape[1:]
    C, *_ = np.linalg.lstsq(F, vals.reshape(x.size, -1), rcond=None)
    C = np.concatenate([C, C[:q]])
    return C.reshape((K + q,) + tail)


def elevate_periodic(U, p, P, t, k):
    """Degree elevation of a wrapped periodic spline; the result is periodic again.

    Unwrapped over one period the spline has the distinct knots of
    ``[a, b)`` with multiplicities ``m``; the elevated spline has
    multiplicities ``m + t`` at the same knots (continuity kept, section 5.5
    of The NURBS Book), wrapped with period ``b - a``. Its control points are
    recovered by collocation on the folded (periodic) basis.
    """
    a, b = domain(U, p)
    inside = U[(U >= a) & (U < b)]
    vals, counts = np.unique(inside, return_counts=True)
    q = p + t
    Un = periodic_knots_from(vals, counts + t, q, a, b)
    K = int(np.sum(counts + t))
    Q = fold_collocate(lambda x: eval_points(U, p, P, x), Un, q, K)
    return Un, Q


def elevate_collocation(U, p, P, t):
    """Degree elevation by ``t``: every distinct knot gains ``t`` in multiplicity.

    The elevated curve lies in the spline space of degree ``p + t`` whose knot
    multiplicities are raised by ``t`` (The NURBS Book, section 5.5); its control
    points are recovered exactly by collocation at the Greville abscissae.
    """
    a, b = domain(U, p)
    vals, counts = distinct_interior(U, p)
    q = p + t
    Un = np.concatenate([np.full(q + 1, a), np.repeat(vals, counts + t), np.full(q + 1, b)])
    Q = collocate(lambda x: eval_points(U, p, P, x), Un, q)
    return Un, Q


def bezier_segments(U, p, P):
    """Split into Bezier pieces: list of (a_i, b_i, control (p+1, ...))."""
    Uc, Pc = clamp(U, p, P)
    vals, counts = distinct_interior(Uc, p)
    X = np.repeat(vals, p - counts)
    Ur, Q = refine(Uc, p, Pc, X) if X.size else (Uc, Pc)
    breaks = np.concatenate([[Ur[p]], vals, [Ur[-1]]])
    segs = []
    for i in range(breaks.size - 1):
        segs.append((float(breaks[i]), float(breaks[i + 1]), Q[i * p:i * p + p + 1].copy()))
    return segs


# --------------------------------------------------------------------------- fast evaluation

POLY_MIN_POINTS = 4096  # below this, Cox-de Boor is as fast as the table set-up


class PolyTable:
    """Piecewise power-basis form of a spline, for fast evaluation of many points.

    Each non-empty span ``[U[i], U[i+1])`` holds the Taylor coefficients of the
    spline about ``U[i]`` (computed once from A2.3 derivatives); evaluation is a
    span look-up (arithmetic for uniform knots, ``searchsorted`` otherwise) and
    Horner's rule over 1-D coefficient tables.
    """

    def __init__(self, U, p, P):
        n1 = P.shape[0]
        self.p = p
        self.n1 = n1
        self.U = np.asarray(U, dtype=float)
        self.tail = P.shape[1:]
        Pf = P.reshape(n1, -1)
        D = Pf.shape[1]
        spans = np.arange(p, n1)
        live = spans[self.U[spans + 1] > self.U[spans]]
        der = eval_derivs(self.U, p, Pf, self.U[live], p)  # (S, p+1, D)
        fact = np.cumprod(np.concatenate([[1.0], np.arange(1, p + 1)]))
        coef = np.zeros((p + 1, D, n1))
        coef[:, :, live] = np.transpose(der / fact[None, :, None], (1, 2, 0))
        self.coef = coef
        a, b = domain(self.U, p)
        self.a, self.b = a, b
        knots_in = self.U[p:n1 + 1]
        steps = np.diff(knots_in)
        self.uniform = bool(np.all(steps > 0) and np.ptp(steps) <= 1e-12 * (b - a))
        self.h = (b - a) / (n1 - p)
        if not self.uniform:
            # bucket table: span at the left edge of K equal cells, then a few
            # vectorized corrections (cells narrower than the shortest span need one)
            shortest = float(np.min(steps[steps > 0]))
            K = int(min(1 << 18, max(64, np.ceil(2.0 * (b - a) / shortest))))
            edges = a + (b - a) * np.arange(K) / K
            self.K = K
            self.cell_span = find_span(self.U, p, n1, edges)

    def __call__(self, u):
        p = self.p
        if self.uniform:
            span = ((u - self.a) * (1.0 / self.h)).astype(np.intp)
            span += p
            np.clip(span, p, self.n1 - 1, out=span)
        else:
            cell = ((u - self.a) * (self.K / (self.b - self.a))).astype(np.intp)
            np.clip(cell, 0, self.K - 1, out=cell)
            span = np.take(self.cell_span, cell)
            last = self.n1 - 1
            while True:
                step = (span < last) & (np.take(self.U, span + 1) <= u)
                if not step.any():
                    break
                span += step
        t = u - self.U[span]
        D = self.coef.shape[1]
        res = np.empty((D, u.shape[0]))
        for d in range(D):
            o = np.take(self.coef[p, d], span)
            for k in range(p - 1, -1, -1):
                o *= t
                o += np.take(self.coef[k, d], span)
            res[d] = o
        return res


def poly_eval(table, u):
    """Evaluate a :class:`PolyTable`; returns (N, *tail)."""
    res = table(u)
    return res.T.reshape((u.shape[0],) + table.tail)
