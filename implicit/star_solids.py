"""Star-shaped solids given by a radial function ``r(theta, phi)`` about a centre.

A star-shaped solid is ``{c + rho w : |w| = 1, 0 <= rho <= r(w)}``.  Its radial
function is stored as a scalar tensor B-spline ``R(u, v)`` (control values of
shape ``(n_u, n_v, 1)``), periodic in ``u = theta / 2 pi`` and clamped in
``v = 1 - phi / pi`` (``phi`` the polar angle from +z, so ``v = 0`` is the
south pole), with constant first and last control rows so the poles are
single points.

Field: ``G(x) = |x - c| / r(w(x)) - 1`` has the right sign and zero set, and
``|grad G| <= sqrt(1 / r_min^2 + g^2 / r_min^4)`` with ``r_min`` the smallest
control value (a lower bound of ``r`` by the convex hull property) and ``g``
the largest angular gradient ``|grad_w r|``.  Dividing by that constant gives a
1-Lipschitz field, hence a conservative bound (``|f| <=`` the distance to the
boundary).  ``g`` is taken from the derivatives sampled on a dense grid and
enlarged by `GRADIENT_MARGIN`.
"""

from __future__ import annotations

import numpy as np

from parametric.basis import basis_matrix, clamped_knots, periodic_knots
from parametric.tensor import BSplineSurface

from .solid import Solid, as_vector

__all__ = ["StarSolid", "star_solid", "fit_radial_function", "GRADIENT_MARGIN"]

#: Factor applied to the sampled angular-gradient maximum.
GRADIENT_MARGIN = 1.25
#: Sampling grid of the gradient maximum (theta x phi).
GRADIENT_GRID = (256, 129)


def _periodic_basis(t, n_unique, p):
    U = periodic_knots(n_unique, p)
    A = basis_matrix(U, p, n_unique + p, np.clip(t, 0.0, 1.0))
    A[:, :p] += A[:, n_unique:]
    return A[:, :n_unique], U


def fit_radial_function(radii, *, n_control=(16, 8), degree=(3, 3)):
    """Least-squares scalar B-spline of a radial function sampled on a sphere grid.

    Parameters
    ----------
    radii : (n_theta, n_phi) float
        ``r`` at ``theta_i = 2 pi i / n_theta`` and ``phi_j = pi j / (n_phi - 1)``
        (both poles included).
    n_control : (2,) int
        Distinct control values around (``u``) and from pole to pole (``v``).
    degree : (2,) int

    Returns
    -------
    radial : BSplineSurface
        Scalar (dim 1) surface on [0, 1]^2, periodic in ``u``, pole rows
        constant (the mean of the samples at each pole).
    max_deviation : float
        Largest ``|R(u_i, v_j) - radii[i, j]|``.

    Examples
    --------
    >>> R, dev = fit_radial_function(np.full((32, 17), 2.0))
    >>> round(float(R(0.3, 0.6)[0]), 12), dev < 1e-12
    (2.0, True)
    """
    R = np.asarray(radii, dtype=float)
    if R.ndim != 2:
        raise ValueError(f"radii: expected shape (n_theta, n_phi), got {R.shape}")
    if not np.all(np.isfinite(R)) or np.any(R <= 0):
        raise ValueError("radii: expected finite positive values")
    nt, nph = R.shape
    p, q = (int(d) for d in degree)
    nu, nv = (int(n) for n in n_control)
    if not p + 1 <= nu <= nt:
        raise ValueError(f"n_control[0]: expected a value in [{p + 1}, {nt}], got {nu}")
    if not max(q + 1, 3) <= nv <= nph:
        raise ValueError(f"n_control[1]: expected a value in [{max(q + 1, 3)}, {nph}], got {nv}")
    tu = np.arange(nt) / nt
    tv = 1.0 - np.linspace(0.0, 1.0, nph)
    Au, Uu = _periodic_basis(tu, nu, p)
    Uv = clamped_knots(nv, q)
    Av = basis_matrix(Uv, q, nv, tv)
    north, south = R[:, 0].mean(), R[:, -1].mean()
    rhs = R - Av[None, :, 0] * south - Av[None, :, -1] * north
    inner = np.linalg.pinv(Au) @ rhs @ np.linalg.pinv(Av[:, 1:-1]).T
    P = np.empty((nu, nv))
    P[:, 0], P[:, -1], P[:, 1:-1] = south, north, inner
    P = np.concatenate([P, P[:p]], axis=0)
    radial = BSplineSurface(P[..., None], p, q, Uu, Uv)
    fit = radial.grid(tu, tv)[..., 0]
    return radial, float(np.max(np.abs(fit - R)))


def _directions(p):
    rho = np.linalg.norm(p, axis=1)
    safe = np.where(rho > 0, rho, 1.0)
    theta = np.mod(np.arctan2(p[:, 1], p[:, 0]), 2 * np.pi)
    phi = np.arccos(np.clip(p[:, 2] / safe, -1.0, 1.0))
    return rho, theta / (2 * np.pi), 1.0 - phi / np.pi


class StarSolid(Solid):
    """A star-shaped solid from a scalar radial B-spline (see the module notes).

    Parameters
    ----------
    radial : BSplineSurface or dict
        Scalar surface ``R(u, v)`` (dim 1) with positive control values, or
        its `surface_to_dict` form.
    center : (3,) array_like
    """

    kind = "star_solid"
    __slots__ = ("_radial", "_c", "_scale")

    def __init__(self, radial, center=(0.0, 0.0, 0.0)):
        from .parametric_solids import surface_from_dict, surface_to_dict

        R = surface_from_dict(radial, "radial")
        if R.dim != 1:
            raise ValueError(f"radial: expected a scalar (dim 1) surface, got dimension {R.dim}")
        ctrl = np.asarray(R.control_points)[..., 0]
        rmin, rmax = float(ctrl.min()), float(ctrl.max())
        if not rmin > 0:
            raise ValueError(f"radial: expected positive control values, the smallest is {rmin:g}")
        c = as_vector(center, "center")
        nt, nph = GRADIENT_GRID
        us = np.arange(nt) / nt
        ph = np.linspace(0.0, np.pi, nph)[1:-1]
        D = R.derivatives(*np.meshgrid(us, 1.0 - ph / np.pi, indexing="ij"), 1)
        r_theta = D[..., 1, 0, 0] / (2 * np.pi)
        r_phi = -D[..., 0, 1, 0] / np.pi
        grad2 = (r_theta / np.sin(ph)[None, :]) ** 2 + r_phi ** 2
        g = GRADIENT_MARGIN * float(np.sqrt(grad2.max()))
        lip = np.sqrt(1.0 / rmin ** 2 + g ** 2 / rmin ** 4)
        super().__init__((), {"radial": surface_to_dict(R), "center": c.tolist()},
                         (c - rmax, c + rmax), exact=False)
        object.__setattr__(self, "_radial", R)
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_scale", 1.0 / lip)

    @classmethod
    def from_params(cls, children, params):
        return cls(**params)

    @property
    def radial(self) -> BSplineSurface:
        return self._radial

    @property
    def center(self) -> np.ndarray:
        return self._c.copy()

    def _label(self) -> str:
        return f"star_solid(radial {np.asarray(self._radial.control_points).shape[:2]}, center={self._c.tolist()})"

    def radius(self, u, v) -> np.ndarray:
        """Radial function ``r`` at parameters ``u, v`` (same shapes)."""
        return self._radial(u, v)[..., 0]

    def _evaluate(self, p):
        rho, u, v = _directions(p - self._c)
        r = self._radial(u, v)[:, 0]
        return (rho / r - 1.0) * self._scale

    def volume(self, n=(96, 64)) -> float:
        """Enclosed volume ``int r^3 / 3 dw`` by Gauss-Legendre quadrature in
        ``phi`` and the trapezoid rule (exact for periodic data) in ``theta``."""
        nt, nph = int(n[0]), int(n[1])
        x, w = np.polynomial.legendre.leggauss(nph)
        ph = 0.5 * np.pi * (x + 1.0)
        us = np.arange(nt) / nt
        r = self._radial.grid(us, 1.0 - ph / np.pi)[..., 0]
        integrand = (r ** 3 / 3.0) * np.sin(ph)[None, :]
        return float((integrand @ w).sum() * (2 * np.pi / nt) * (0.5 * np.pi))


def star_solid(radial, center=(0.0, 0.0, 0.0)) -> Solid:
    """A star-shaped solid from a scalar radial B-spline ``r(theta, phi)``.

    Parameters
    ----------
    radial : BSplineSurface
        Scalar (dim 1) radial function, e.g. from `fit_radial_function`.
    center : (3,) array_like

    Returns
    -------
    StarSolid
        A conservative 1-Lipschitz bound of the signed distance.

    Examples
    --------
    >>> R, _ = fit_radial_function(np.full((32, 17), 2.0))
    >>> ball = star_solid(R)
    >>> round(ball.volume() / (4 / 3 * np.pi * 8), 9)
    1.0
    >>> np.round(ball([[0.0, 0.0, 3.0], [1.0, 0.0, 0.0]]), 12)
    array([ 1., -1.])
    """
    return StarSolid(radial, center)
