"""Bicubic patches: ``sum k_ij u^i v^j`` through a 4 x 4 grid of points."""

from __future__ import annotations

import numpy as np

from .curves import Bezier, _HERMITE, _power_derivs

from .surface_base import Surface, _check_domain_pair  # noqa: F401

__all__ = ["BicubicPatch"]

#: Smallest gap between two interpolation parameters of a patch.
_MIN_GAP = 1e-3

_BEZ3 = np.array([[1.0, 0.0, 0.0, 0.0],
                  [-3.0, 3.0, 0.0, 0.0],
                  [3.0, -6.0, 3.0, 0.0],
                  [-1.0, 3.0, -3.0, 1.0]])  # [1,u,u²,u³] @ _BEZ3 = Bernstein row


class BicubicPatch(Surface):
    """Bicubic patch ``p(u, v) = sum_{i,j=0..3} k_ij u^i v^j`` on [0, 1]².

    The 16 vector coefficients are found by interpolation through a 4 x 4 grid
    of points (Lagrange interpolation in each direction).

    Parameters
    ----------
    points : (4, 4, dim) float
        ``points[a, b]`` is the surface point at ``(u_params[a], v_params[b])``.
    u_params, v_params : (4,) float, optional
        Distinct parameters in [0, 1]; uniform ``0, 1/3, 2/3, 1`` by default.

    Examples
    --------
    >>> g = np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij"), -1)
    >>> pts = np.concatenate([g, (g[..., :1] * g[..., 1:]) / 9], axis=-1)
    >>> patch = BicubicPatch(pts)
    >>> np.allclose(patch(1 / 3, 2 / 3), pts[1, 2])
    True
    """

    def __init__(self, points, u_params=None, v_params=None):
        try:
            G = np.array(points, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("points must be a numeric array of shape (4, 4, dim)") from None
        if G.ndim != 3 or G.shape[:2] != (4, 4):
            raise ValueError(f"points must have shape (4, 4, dim), got {G.shape}")
        if not np.all(np.isfinite(G)):
            raise ValueError("points must be finite numbers (got NaN or infinity)")
        us = self._p4(u_params, "u_params")
        vs = self._p4(v_params, "v_params")
        Mu = np.vander(us, 4, increasing=True)
        Mv = np.vander(vs, 4, increasing=True)
        K = np.einsum("ia,abd,jb->ijd", np.linalg.inv(Mu), G, np.linalg.inv(Mv))
        self._set(K)

    @staticmethod
    def _p4(x, name):
        if x is None:
            return np.linspace(0.0, 1.0, 4)
        t = np.asarray(x, dtype=float).ravel()
        if t.size != 4 or not np.all(np.isfinite(t)) or np.any(t < 0) or np.any(t > 1):
            raise ValueError(f"{name} must be 4 distinct values in [0, 1], got {x!r}")
        # the Vandermonde inverse grows like 1/gap^3: nearly equal parameters
        # give coefficients of no precision
        gap = np.min(np.diff(np.sort(t)))
        if not gap >= _MIN_GAP:
            raise ValueError(f"{name} must be 4 distinct values in [0, 1] at least {_MIN_GAP:g} apart, "
                             f"got {x!r}")
        return t

    def _set(self, K):
        K = np.array(K, dtype=float)
        K.setflags(write=False)
        self._K = K
        self._dim = K.shape[2]

    @classmethod
    def from_coefficients(cls, coefficients):
        """Patch from the algebraic coefficients ``k_ij``: (4, 4, dim)."""
        K = np.asarray(coefficients, dtype=float)
        if K.ndim != 3 or K.shape[:2] != (4, 4):
            raise ValueError(f"coefficients must have shape (4, 4, dim), got {K.shape}")
        obj = cls.__new__(cls)
        obj._set(K)
        return obj

    @classmethod
    def hermite(cls, corners, u_tangents, v_tangents, twists):
        """Ferguson (Hermite) bicubic patch from corner data.

        Parameters
        ----------
        corners : (2, 2, dim) float
            ``corners[i, j] = P(i, j)``.
        u_tangents, v_tangents : (2, 2, dim) float
            ``dP/du`` and ``dP/dv`` at the corners.
        twists : (2, 2, dim) float
            ``d²P/du dv`` at the corners (zero twists give a Ferguson patch).

        Examples
        --------
        >>> P = np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]], float)
        >>> Pu = np.broadcast_to([1.0, 0, 0], (2, 2, 3))
        >>> Pv = np.broadcast_to([0, 1.0, 0], (2, 2, 3))
        >>> s = BicubicPatch.hermite(P, Pu, Pv, np.zeros((2, 2, 3)))
        >>> s(1.0, 1.0)
        array([1., 1., 1.])
        """
        arrs = []
        for a, n in ((corners, "corners"), (u_tangents, "u_tangents"),
                     (v_tangents, "v_tangents"), (twists, "twists")):
            x = np.asarray(a, dtype=float)
            if x.ndim != 3 or x.shape[:2] != (2, 2):
                raise ValueError(f"{n} must have shape (2, 2, dim), got {x.shape}")
            arrs.append(x)
        if len({x.shape for x in arrs}) != 1:
            raise ValueError("corners, u_tangents, v_tangents and twists must share one shape")
        P, Pu, Pv, Puv = arrs
        B = np.empty((4, 4, P.shape[2]))
        B[:2, :2] = P
        B[:2, 2:] = Pv
        B[2:, :2] = Pu
        B[2:, 2:] = Puv
        K = np.einsum("ai,abd,bj->ijd", _HERMITE, B, _HERMITE)
        return cls.from_coefficients(K)

    @property
    def coefficients(self):
        """(4, 4, dim) algebraic coefficients ``k_ij``."""
        return self._K

    def _derivs(self, u, v, order):
        Pu = _power_derivs(u, order)
        Pv = _power_derivs(v, order)
        return np.einsum("nki,ijd,nlj->nkld", Pu, self._K, Pv)

    def _eval(self, u, v):
        Pu = _power_derivs(u, 0)[:, 0]
        Pv = _power_derivs(v, 0)[:, 0]
        return np.einsum("ni,ijd,nj->nd", Pu, self._K, Pv)

    def _grid(self, us, vs):
        Pu = _power_derivs(us, 0)[:, 0]
        Pv = _power_derivs(vs, 0)[:, 0]
        return np.einsum("ai,ijd,bj->abd", Pu, self._K, Pv)

    def bezier_control_points(self):
        """(4, 4, dim) control net of the same patch as a bicubic Bezier surface."""
        inv = np.linalg.inv(_BEZ3)
        return np.einsum("ia,abd,jb->ijd", inv, self._K, inv)

    def isocurve_u(self, u0):
        """The curve ``v -> S(u0, v)`` as a cubic :class:`Bezier`."""
        u0 = float(self._params_1d(u0, self._domain_u, "u0")[0])
        coef = np.einsum("i,ijd->jd", _power_derivs(np.array([u0]), 0)[0, 0], self._K)
        return Bezier(np.linalg.solve(_BEZ3, coef))

    def isocurve_v(self, v0):
        """The curve ``u -> S(u, v0)`` as a cubic :class:`Bezier`."""
        v0 = float(self._params_1d(v0, self._domain_v, "v0")[0])
        coef = np.einsum("j,ijd->id", _power_derivs(np.array([v0]), 0)[0, 0], self._K)
        return Bezier(np.linalg.solve(_BEZ3, coef))
