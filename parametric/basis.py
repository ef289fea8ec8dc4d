"""Bernstein polynomials, knot vectors and B-spline basis functions.

Every routine here is vectorized over arrays of parameter values: the only Python
loops run over the degree (or derivative order), never over parameter values.

Conventions follow L. Piegl and W. Tiller, *The NURBS Book*, 2nd ed. (Springer,
1997), doi:10.1007/978-3-642-59223-2: a B-spline of degree ``p`` with ``n + 1``
control points has a knot vector ``U`` of ``n + p + 2`` non-decreasing values and
the parametric domain ``[U[p], U[n + 1]]``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "KNOT_TOL",
    "bernstein",
    "bernstein_matrix",
    "clamped_knots",
    "uniform_knots",
    "periodic_knots",
    "validate_knots",
    "find_span",
    "basis_funs",
    "ders_basis_funs",
    "basis_matrix",
    "knot_multiplicity",
    "greville",
]

#: Relative tolerance used when comparing knot values and domain ends.
KNOT_TOL = 1e-12


def _as_params(u, name="u"):
    arr = np.asarray(u, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got non-finite values")
    return arr


def bernstein(degree, u):
    """Bernstein polynomials ``B_{i,n}(u)`` for ``i = 0..n``.

    Parameters
    ----------
    degree : int
        Polynomial degree ``n >= 0``.
    u : float or (m,) array_like
        Parameter values (any real; the polynomials are usually used on [0, 1]).

    Returns
    -------
    (m, n + 1) float array (``(n + 1,)`` for a scalar ``u``).

    Examples
    --------
    >>> bernstein(2, 0.5)
    array([0.25, 0.5 , 0.25])
    """
    from scipy.special import comb  # local: scipy.special costs 0.1 s to import

    n = _check_degree(degree, "degree", minimum=0)
    uu = _as_params(u)
    scalar = uu.ndim == 0
    uu = np.atleast_1d(uu).ravel()
    i = np.arange(n + 1)
    # u**i with 0**0 == 1, as numpy does
    out = comb(n, i)[None, :] * uu[:, None] ** i * (1.0 - uu[:, None]) ** (n - i)
    return out[0] if scalar else out


def bernstein_matrix(degree, u):
    """Alias of :func:`bernstein` that always returns a 2-D ``(m, n + 1)`` array."""
    return np.atleast_2d(bernstein(degree, np.atleast_1d(u)))


def _check_degree(degree, name="degree", minimum=1):
    if isinstance(degree, (bool, np.bool_)) or not isinstance(degree, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(degree).__name__}")
    if degree < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {degree}")
    return int(degree)


def _check_count(n_ctrl, degree, name="n_control"):
    if isinstance(n_ctrl, (bool, np.bool_)) or not isinstance(n_ctrl, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(n_ctrl).__name__}")
    if n_ctrl < degree + 1:
        raise ValueError(f"{name} must be >= degree + 1 = {degree + 1}, got {n_ctrl}")
    return int(n_ctrl)


def clamped_knots(n_control, degree, domain=(0.0, 1.0)):
    """Clamped (open) uniform knot vector.

    The first and last knots repeat ``degree + 1`` times, so the curve
    interpolates its first and last control points.

    Parameters
    ----------
    n_control : int
        Number of control points (``>= degree + 1``).
    degree : int
        Degree ``p >= 1``.
    domain : (2,) float
        Parametric domain ``(a, b)`` with ``a < b``.

    Returns
    -------
    (n_control + degree + 1,) float array

    Examples
    --------
    >>> clamped_knots(4, 2)
    array([0. , 0. , 0. , 0.5, 1. , 1. , 1. ])
    """
    p = _check_degree(degree)
    n = _check_count(n_control, p)
    a, b = _check_domain(domain)
    inner = np.linspace(a, b, n - p + 1)[1:-1]
    return np.concatenate([np.full(p + 1, a), inner, np.full(p + 1, b)])


def uniform_knots(n_control, degree, domain=(0.0, 1.0)):
    """Uniform unclamped knot vector whose domain ``[U[p], U[n+1]]`` is ``domain``.

    Returns
    -------
    (n_control + degree + 1,) float array

    Examples
    --------
    >>> uniform_knots(4, 2)
    array([-1. , -0.5,  0. ,  0.5,  1. ,  1.5,  2. ])
    """
    p = _check_degree(degree)
    n = _check_count(n_control, p)
    a, b = _check_domain(domain)
    h = (b - a) / (n - p)
    return a + h * (np.arange(n + p + 1) - p)


def periodic_knots(n_unique, degree, domain=(0.0, 1.0)):
    """Knot vector of a closed (periodic) uniform B-spline.

    A periodic curve with ``n_unique`` distinct control points is stored as an
    unclamped curve with ``n_unique + degree`` control points, the first
    ``degree`` repeated at the end (see :meth:`parametric.curves.BSpline.periodic`).

    Returns
    -------
    (n_unique + 2 * degree + 1,) float array, uniform spacing
    ``(b - a) / n_unique``, domain ``[U[p], U[n_unique + p]] == domain``.
    """
    p = _check_degree(degree)
    if isinstance(n_unique, (bool, np.bool_)) or not isinstance(n_unique, (int, np.integer)):
        raise TypeError(f"n_unique must be an int, got {type(n_unique).__name__}")
    if n_unique < p + 1:
        raise ValueError(f"n_unique must be >= degree + 1 = {p + 1}, got {n_unique}")
    a, b = _check_domain(domain)
    h = (b - a) / n_unique
    return a + h * (np.arange(n_unique + 2 * p + 1) - p)


def _check_domain(domain):
    try:
        a, b = (float(x) for x in domain)
    except (TypeError, ValueError):
        raise TypeError(f"domain must be a pair of floats (a, b), got {domain!r}") from None
    if not (np.isfinite(a) and np.isfinite(b) and a < b):
        raise ValueError(f"domain must satisfy a < b with finite ends, got ({a}, {b})")
    return a, b


def validate_knots(knots, degree, n_control, name="knots"):
    """Check a knot vector and return it as a read-only float array.

    Raises
    ------
    TypeError
        If ``knots`` is not a 1-D numeric sequence.
    ValueError
        If its length is not ``n_control + degree + 1``, it decreases, an interior
        knot repeats more than ``degree`` times, or the domain is empty.
    """
    p = _check_degree(degree)
    try:
        U = np.array(knots, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a 1-D sequence of floats") from None
    if U.ndim != 1:
        raise TypeError(f"{name} must be 1-D, got shape {U.shape}")
    need = n_control + p + 1
    if U.size != need:
        raise ValueError(
            f"{name} must have n_control + degree + 1 = {need} values, got {U.size}")
    if not np.all(np.isfinite(U)):
        raise ValueError(f"{name} must be finite")
    if np.any(np.diff(U) < 0):
        raise ValueError(f"{name} must be non-decreasing")
    a, b = U[p], U[n_control]
    if not a < b:
        raise ValueError(f"{name} gives an empty domain [U[p], U[n+1]] = [{a}, {b}]")
    if not U[n_control - 1] < b:
        raise ValueError(
            f"{name}: knot U[n] = {U[n_control - 1]} must be below the domain end {b}")
    vals, counts = np.unique(U, return_counts=True)
    if np.any(counts > p + 1):
        raise ValueError(
            f"{name}: knot {vals[counts > p + 1][0]} repeats {counts[counts > p + 1][0]} times; "
            f"at most degree + 1 = {p + 1} allowed (at the ends)")
    inner = U[p + 1:n_control]
    if inner.size:
        vals, counts = np.unique(inner, return_counts=True)
        bad = counts > p
        if np.any(bad):
            raise ValueError(
                f"{name}: interior knot {vals[bad][0]} repeats {counts[bad][0]} times; "
                f"at most degree = {p} allowed")
    U.setflags(write=False)
    return U


def find_span(knots, degree, n_control, u):
    """Knot span index of every parameter (The NURBS Book, A2.1, vectorized).

    Returns ``k`` with ``U[k] <= u < U[k+1]`` and ``degree <= k <= n_control - 1``;
    the right end of the domain belongs to the last non-empty span.

    Parameters
    ----------
    knots : (m,) float
    degree : int
    n_control : int
    u : (N,) float

    Returns
    -------
    (N,) int array
    """
    U = knots
    span = np.searchsorted(U, u, side="right") - 1
    np.clip(span, degree, n_control - 1, out=span)
    # u == U[n+1] with repeated knots: step back to the last non-empty span
    return span


def basis_funs(knots, degree, span, u):
    """Non-vanishing basis functions ``N_{span-p..span, p}(u)`` (A2.2, vectorized).

    Parameters
    ----------
    knots : (m,) float
    degree : int
    span : (N,) int, from :func:`find_span`
    u : (N,) float

    Returns
    -------
    (N, degree + 1) float array; row sums are 1 (partition of unity).
    """
    N = _basis_levels(knots, degree, span, u)[-1]
    return np.ascontiguousarray(N.T)


def _basis_levels(knots, degree, span, u):
    """A2.2 on row-major ``(q + 1, N)`` arrays; returns the functions of every degree."""
    p = degree
    U = knots
    m = u.shape[0]
    N = np.empty((p + 1, m))
    N[0] = 1.0
    left = np.empty((p + 1, m))
    right = np.empty((p + 1, m))
    levels = [N[:1].copy()]
    for j in range(1, p + 1):
        left[j] = u - U[span + 1 - j]
        right[j] = U[span + j] - u
        saved = np.zeros(m)
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            N[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        N[j] = saved
        levels.append(N[:j + 1].copy())
    return levels


def ders_basis_funs(knots, degree, span, u, n_ders):
    """Basis functions and their derivatives up to ``n_ders`` (vectorized).

    The derivative recurrence behind A2.3 (eq. 2.9),
    ``N'_{j,q} = q N_{j,q-1} / (U_{j+q} - U_j) - q N_{j+1,q-1} / (U_{j+q+1} - U_{j+1})``,
    is applied ``k`` times to the degree ``p - k`` functions, with whole
    ``(N, q)`` arrays per step; :func:`_ders_basis_funs_a23` is the literal A2.3.

    Parameters
    ----------
    knots : (m,) float
    degree : int
    span : (N,) int
    u : (N,) float
    n_ders : int
        Highest derivative order; orders above ``degree`` are zero.

    Returns
    -------
    (N, n_ders + 1, degree + 1) float array: ``ders[:, k, j]`` is the ``k``-th
    derivative of ``N_{span - p + j, p}`` at ``u``.
    """
    p = degree
    U = knots
    m = u.shape[0]
    levels = _basis_levels(U, p, span, u)  # levels[q]: (q + 1, m)
    ders = np.zeros((n_ders + 1, p + 1, m))
    ders[0] = levels[p]
    top = min(n_ders, p)
    # inverse knot differences q / (U[span + s] - U[span - q + s]), s = 0..q+1, per degree q
    inv = {}
    for q in range(p - top + 1, p + 1):
        s = np.arange(q + 2)[:, None]
        d = U[np.minimum(span[None, :] + s, U.size - 1)] - U[span[None, :] - q + s]
        with np.errstate(divide="ignore"):
            inv[q] = np.where(d > 0, q / np.where(d > 0, d, 1.0), 0.0)
    for k in range(1, top + 1):
        X = levels[p - k]  # functions N_{span-(p-k)..span, p-k}
        for q in range(p - k + 1, p + 1):
            Z = np.zeros((q + 2, m))
            Z[1:q + 1] = X
            Z *= inv[q]
            X = Z[:-1] - Z[1:]
        ders[k] = X
    return np.ascontiguousarray(np.transpose(ders, (2, 0, 1)))


def _ders_basis_funs_a23(knots, degree, span, u, n_ders):
    """Basis functions and their derivatives up to ``n_ders`` (A2.3, vectorized).

    Parameters
    ----------
    knots : (m,) float
    degree : int
    span : (N,) int
    u : (N,) float
    n_ders : int
        Highest derivative order; orders above ``degree`` are zero.

    Returns
    -------
    (N, n_ders + 1, degree + 1) float array: ``ders[:, k, j]`` is the ``k``-th
    derivative of ``N_{span - p + j, p}`` at ``u``.
    """
    p = degree
    U = knots
    m = u.shape[0]
    ndu = np.empty((m, p + 1, p + 1))
    ndu[:, 0, 0] = 1.0
    left = np.empty((m, p + 1))
    right = np.empty((m, p + 1))
    for j in range(1, p + 1):
        left[:, j] = u - U[span + 1 - j]
        right[:, j] = U[span + j] - u
        saved = np.zeros(m)
        for r in range(j):
            ndu[:, j, r] = right[:, r + 1] + left[:, j - r]  # lower triangle: knot differences
            temp = ndu[:, r, j - 1] / ndu[:, j, r]
            ndu[:, r, j] = saved + right[:, r + 1] * temp  # upper triangle: basis functions
            saved = left[:, j - r] * temp
        ndu[:, j, j] = saved
    ders = np.zeros((m, n_ders + 1, p + 1))
    ders[:, 0, :] = ndu[:, :, p]
    top = min(n_ders, p)
    a = np.zeros((2, p + 1, m))
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0, 0] = 1.0
        for k in range(1, top + 1):
            d = np.zeros(m)
            rk = r - k
            pk = p - k
            if r >= k:
                a[s2, 0] = a[s1, 0] / ndu[:, pk + 1, rk]
                d = a[s2, 0] * ndu[:, rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, j] = (a[s1, j] - a[s1, j - 1]) / ndu[:, pk + 1, rk + j]
                d = d + a[s2, j] * ndu[:, rk + j, pk]
            if r <= pk:
                a[s2, k] = -a[s1, k - 1] / ndu[:, pk + 1, r]
                d = d + a[s2, k] * ndu[:, r, pk]
            ders[:, k, r] = d
            s1, s2 = s2, s1
    fac = float(p)
    for k in range(1, top + 1):
        ders[:, k, :] *= fac
        fac *= p - k
    return ders


def basis_matrix(knots, degree, n_control, u, n_ders=0):
    """Dense collocation matrices of all basis functions (and derivatives).

    Parameters
    ----------
    knots : (m,) float
    degree : int
    n_control : int
    u : (N,) float, inside the domain
    n_ders : int, default 0

    Returns
    -------
    (N, n_control) float array if ``n_ders == 0``, else
    ``(n_ders + 1, N, n_control)``.

    Examples
    --------
    >>> basis_matrix(clamped_knots(3, 2), 2, 3, np.array([0.0, 0.5, 1.0]))
    array([[1.  , 0.  , 0.  ],
           [0.25, 0.5 , 0.25],
           [0.  , 0.  , 1.  ]])
    """
    u = np.atleast_1d(np.asarray(u, dtype=float)).ravel()
    span = find_span(knots, degree, n_control, u)
    cols = span[:, None] - degree + np.arange(degree + 1)
    rows = np.broadcast_to(np.arange(u.size)[:, None], cols.shape)
    if n_ders == 0:
        out = np.zeros((u.size, n_control))
        out[rows, cols] = basis_funs(knots, degree, span, u)
        return out
    ders = ders_basis_funs(knots, degree, span, u, n_ders)
    out = np.zeros((n_ders + 1, u.size, n_control))
    for k in range(n_ders + 1):
        out[k][rows, cols] = ders[:, k, :]
    return out


def knot_multiplicity(knots, u):
    """Number of knots equal to ``u`` (exact comparison after a relative snap)."""
    U = np.asarray(knots, dtype=float)
    tol = KNOT_TOL * max(1.0, float(np.max(np.abs(U))))
    return int(np.count_nonzero(np.abs(U - u) <= tol))


def greville(knots, degree):
    """Greville abscissae ``(U[i+1] + ... + U[i+p]) / p`` of every control point.

    Returns
    -------
    (len(knots) - degree - 1,) float array
    """
    U = np.asarray(knots, dtype=float)
    n = U.size - degree - 1
    c = np.concatenate([[0.0], np.cumsum(U)])
    i = np.arange(n)
    return (c[i + degree + 1] - c[i + 1]) / degree
