"""The curve contract shared by every parametric curve, and a callable wrapper.

``curve(u)`` takes a scalar or an ``(n,)`` array and returns ``(n, dim)`` points
(``(dim,)`` for a scalar); parameters outside :attr:`Curve.domain` raise
``ValueError`` naming ``u``. Curves are immutable and refuse truthiness.
"""

from __future__ import annotations

import numpy as np

from .basis import KNOT_TOL

__all__ = ["Curve", "FunctionCurve"]


def _points(arr, name, min_rows=1):
    try:
        P = np.array(arr, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of shape (n, dim)") from None
    if P.ndim != 2 or P.shape[1] < 1:
        raise ValueError(f"{name} must have shape (n, dim), got {P.shape}")
    if P.shape[0] < min_rows:
        raise ValueError(f"{name} needs at least {min_rows} points, got {P.shape[0]}")
    if not np.all(np.isfinite(P)):
        raise ValueError(f"{name} must be finite")
    P.setflags(write=False)
    return P


def _vector(arr, name):
    try:
        v = np.array(arr, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric vector") from None
    if v.ndim != 1 or v.size < 1:
        raise ValueError(f"{name} must be a 1-D vector, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite")
    v.setflags(write=False)
    return v


def fd_step(k, length):
    """Step of the ``k``-th central difference: ``eps^(1/(k+2))`` of the domain length."""
    return np.finfo(float).eps ** (1.0 / (k + 2)) * length


def fd_stencil(u, k, a, b, total=None):
    """Nodes ``(n, k + 2)`` and weights ``(n, k + 2)`` of the ``k``-th derivative at ``u``.

    ``k + 2`` equally spaced nodes (step ``fd_step(total)``, ``total = k`` by
    default; a mixed partial passes its total order), centred on ``u`` and
    shifted inside ``[a, b]`` near the ends; the weights make the rule exact for
    polynomials of degree ``k + 1``, so it is second-order accurate everywhere.
    """
    from math import factorial

    h = fd_step(k if total is None else total, b - a)
    m = k + 2
    t0 = np.clip(u - 0.5 * (m - 1) * h, a, b - (m - 1) * h)
    nodes = t0[:, None] + np.arange(m) * h
    s = (nodes - u[:, None]) / h                           # (n, m) offsets in steps
    j = np.arange(m)
    V = s[:, None, :] ** j[None, :, None] / np.array([factorial(x) for x in j])[None, :, None]
    rhs = np.zeros((u.shape[0], m, 1))
    rhs[:, k] = 1.0
    wts = np.linalg.solve(V, rhs)[..., 0] / h ** k
    return nodes, wts


def _difference(f, u, k, a, b):
    """``k``-th derivative of ``f: (n,) -> (n, dim)`` by a central difference."""
    nodes, wts = fd_stencil(u, k, a, b)
    vals = f(nodes.T.ravel()).reshape(k + 2, u.shape[0], -1)
    return np.einsum("ni,ind->nd", wts, vals)


def _check_order(order):
    if isinstance(order, (bool, np.bool_)) or not isinstance(order, (int, np.integer)):
        raise TypeError(f"order must be an int, got {type(order).__name__}")
    if order < 0:
        raise ValueError(f"order must be >= 0, got {order}")
    return int(order)


class Curve:
    """Base of all parametric curves.

    Subclasses implement ``_eval(u)`` and ``_derivs(u, order)`` on validated
    ``(n,)`` arrays and set ``_domain`` and ``_dim``.
    """

    _domain = (0.0, 1.0)
    _dim = 3

    @property
    def domain(self):
        """(a, b): the parametric domain."""
        return self._domain

    @property
    def dim(self):
        """Dimension of the points (2 or 3 usually)."""
        return self._dim

    def _params(self, u):
        try:
            arr = np.asarray(u, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("u must be a float or an array of floats") from None
        if arr.ndim > 1:
            raise ValueError(f"u must be a scalar or a 1-D array, got shape {arr.shape}")
        scalar = arr.ndim == 0
        arr = np.atleast_1d(arr)
        a, b = self._domain
        tol = KNOT_TOL * max(1.0, abs(a), abs(b))
        if arr.size and not (np.all(np.isfinite(arr)) and arr.min() >= a - tol and arr.max() <= b + tol):
            bad = arr[~((arr >= a - tol) & (arr <= b + tol))]
            raise ValueError(
                f"u must lie in the domain [{a}, {b}], got {bad[0] if bad.size else 'nan'}")
        return np.clip(arr, a, b), scalar

    def __call__(self, u):
        uu, scalar = self._params(u)
        out = self._eval(uu)
        return out[0] if scalar else out

    def derivatives(self, u, order=1):
        """All derivatives of orders ``0..order``.

        Returns
        -------
        (n, order + 1, dim) float array (``(order + 1, dim)`` for a scalar ``u``).
        """
        order = _check_order(order)
        uu, scalar = self._params(u)
        out = self._derivs(uu, order)
        return out[0] if scalar else out

    def derivative(self, u, order=1):
        """The ``order``-th derivative ``d^k C / du^k``: (n, dim) or (dim,)."""
        d = self.derivatives(u, order)
        return d[..., order, :]

    def tangent(self, u):
        """Unit tangent vectors: (n, dim) or (dim,)."""
        d = self.derivative(u, 1)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def sample(self, n=100):
        """``n`` points at uniformly spaced parameters: (n, dim)."""
        a, b = self._domain
        return self(np.linspace(a, b, int(n)))

    def _derivs(self, u, order):  # generic fallback: central differences
        a, b = self._domain
        h = 1e-4 * (b - a)
        out = [self._eval(u)]
        for k in range(1, order + 1):
            if k > 2:
                out.append(_difference(self._eval, u, k, a, b))
                continue
            lo = np.clip(u - h, a, b)
            hi = np.clip(u + h, a, b)
            mid = 0.5 * (lo + hi)
            step = (hi - lo) / 2.0
            if k == 1:
                out.append((self._eval(hi) - self._eval(lo)) / (2.0 * step)[:, None])
            else:
                out.append((self._eval(hi) - 2.0 * self._eval(mid) + self._eval(lo))
                           / (step ** 2)[:, None])
        return np.stack(out, axis=1)

    def __bool__(self):
        raise TypeError(f"the truth value of a {type(self).__name__} is ambiguous")


class FunctionCurve(Curve):
    """Wrap any callable ``u -> (n, dim)`` points as a curve (derivatives by differences).

    Examples
    --------
    >>> c = FunctionCurve(lambda u: np.stack([u, u**2], axis=-1), (0.0, 1.0))
    >>> c(0.5)
    array([0.5 , 0.25])
    """

    def __init__(self, func, domain=(0.0, 1.0), dim=None):
        if not callable(func):
            raise TypeError(f"func must be callable, got {type(func).__name__}")
        self._func = func
        a, b = (float(x) for x in domain)
        if not a < b:
            raise ValueError(f"domain must satisfy a < b, got ({a}, {b})")
        self._domain = (a, b)
        probe = np.asarray(func(np.array([a])), dtype=float)
        self._dim = int(probe.shape[-1]) if dim is None else int(dim)

    def _eval(self, u):
        return np.asarray(self._func(u), dtype=float).reshape(u.shape[0], self._dim)
