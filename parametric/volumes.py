"""Parametric solids: trivariate Bezier, B-spline and NURBS volumes.

A volume maps the parameter box ``(u, v, w)`` to space,
``p(u, v, w) = sum_ijk N_i(u) N_j(v) N_k(w) P_ijk`` (analytical solid modeling).
Mass properties integrate ``|det J|`` over the parameter box by tensor
Gauss-Legendre quadrature on every knot span; for polynomial maps the rule is
exact once it has ``floor(5 p / 2) + 1`` points per span and direction (the
integrand ``x x^T |det J|`` has degree ``5 p - 1`` in each parameter).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _ops
from .basis import (_check_degree, basis_funs, basis_matrix, clamped_knots, ders_basis_funs,
                    find_span, validate_knots)
from .tensor import BSplineSurface, NURBSSurface

__all__ = ["VolumeProperties", "BSplineVolume", "BezierVolume", "NURBSVolume"]


@dataclass(frozen=True)
class VolumeProperties:
    """Mass properties of a parametric volume.

    Attributes
    ----------
    volume : float
    mass : float
        ``density * volume``.
    density : float
    centroid : (3,) float
    inertia : (3, 3) float
        Inertia tensor about the centroid, ``density * int (|r|² E - r rᵀ) dV``.
    """

    volume: float
    mass: float
    density: float
    centroid: np.ndarray
    inertia: np.ndarray

    @property
    def principal_moments(self):
        """(3,) ascending eigenvalues of :attr:`inertia`."""
        return np.linalg.eigvalsh(self.inertia)


def _gauss_spans(U, p, n):
    """Gauss-Legendre nodes and weights over every non-empty span of the domain."""
    a, b = _ops.domain(U, p)
    br = np.unique(U[(U >= a) & (U <= b)])
    x, wt = np.polynomial.legendre.leggauss(n)
    lo, hi = br[:-1, None], br[1:, None]
    nodes = (0.5 * (hi - lo) * x[None, :] + 0.5 * (hi + lo)).ravel()
    weights = (0.5 * (hi - lo) * wt[None, :]).ravel()
    return nodes, weights


class BSplineVolume:
    """Trivariate tensor-product B-spline volume ``p(u, v, w)``.

    Parameters
    ----------
    control_points : (n_u, n_v, n_w, 3) float
    degrees : (3,) int
    knots : tuple of three 1-D float arrays, optional
        Clamped uniform on [0, 1] in each direction by default.

    Examples
    --------
    >>> g = np.stack(np.meshgrid(*[np.linspace(0, 1, 2)] * 3, indexing="ij"), -1)
    >>> cube = BSplineVolume(g * [2.0, 3.0, 4.0], (1, 1, 1))
    >>> round(cube.mass_properties().volume, 12)
    24.0
    """

    def __init__(self, control_points, degrees, knots=None):
        try:
            P = np.array(control_points, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("control_points must be a numeric array of shape "
                            "(n_u, n_v, n_w, 3)") from None
        if P.ndim != 4 or P.shape[3] != 3:
            raise ValueError(f"control_points must have shape (n_u, n_v, n_w, 3), got {P.shape}")
        if not np.all(np.isfinite(P)):
            raise ValueError("control_points must be finite")
        try:
            degs = tuple(degrees)
        except TypeError:
            raise TypeError(f"degrees must be a sequence of 3 ints, got {degrees!r}") from None
        if len(degs) != 3:
            raise ValueError(f"degrees must hold 3 ints, got {len(degs)}")
        degs = tuple(_check_degree(d, f"degrees[{i}]") for i, d in enumerate(degs))
        for i, (n, d) in enumerate(zip(P.shape[:3], degs)):
            if n < d + 1:
                raise ValueError(f"control_points axis {i} has {n} points; degree {d} needs {d + 1}")
        if knots is None:
            knots = [None, None, None]
        if len(knots) != 3:
            raise ValueError(f"knots must hold 3 knot vectors, got {len(knots)}")
        self._U = tuple(
            validate_knots(clamped_knots(n, d) if k is None else k, d, n, f"knots[{i}]")
            for i, (n, d, k) in enumerate(zip(P.shape[:3], degs, knots)))
        P.setflags(write=False)
        self._P = P
        self._deg = degs
        self._domains = tuple(_ops.domain(U, d) for U, d in zip(self._U, degs))

    # ------------------------------------------------------------ properties
    @property
    def control_points(self):
        return self._P

    @property
    def degrees(self):
        return self._deg

    @property
    def knots(self):
        return self._U

    @property
    def domains(self):
        """((a_u, b_u), (a_v, b_v), (a_w, b_w))."""
        return self._domains

    def _ctrl(self):
        return self._P

    def __bool__(self):
        raise TypeError(f"the truth value of a {type(self).__name__} is ambiguous")

    # ------------------------------------------------------------ evaluation
    def _params(self, u, v, w):
        try:
            arrs = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (u, v, w)))
        except ValueError:
            raise ValueError("u, v and w must have equal (broadcastable) shapes") from None
        shape = arrs[0].shape
        out = []
        for name, arr, (a, b) in zip("uvw", arrs, self._domains):
            arr = arr.ravel()
            tol = 1e-12 * max(1.0, abs(a), abs(b))
            ok = np.isfinite(arr) & (arr >= a - tol) & (arr <= b + tol)
            if not np.all(ok):
                raise ValueError(f"{name} must lie in [{a}, {b}], got {arr[~ok][0]}")
            out.append(np.clip(arr, a, b))
        return out, shape

    def _homog_derivs(self, u, v, w, first):
        """Homogeneous values (and first partials): (N, 4 if first else 1, D)."""
        C = self._ctrl()
        (Uu, Uv, Uw), (p, q, r) = self._U, self._deg
        n = [C.shape[i] for i in range(3)]
        su, sv, sw = (find_span(U, d, m, x) for U, d, m, x in zip(self._U, self._deg, n, (u, v, w)))
        d = 1 if first else 0
        Bu, Bv, Bw = (ders_basis_funs(U, deg, s, x, d) if first else basis_funs(U, deg, s, x)[:, None]
                      for U, deg, s, x in ((Uu, p, su, u), (Uv, q, sv, v), (Uw, r, sw, w)))
        iu = su[:, None] - p + np.arange(p + 1)
        combos = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)] if first else [(0, 0, 0)]
        out = np.zeros((u.size, len(combos), C.shape[3]))
        for j in range(q + 1):
            for k in range(r + 1):
                col = C[iu, (sv - q + j)[:, None], (sw - r + k)[:, None]]  # (N, p+1, D)
                A = np.einsum("nai,nid->nad", Bu, col)
                for c, (a, b, e) in enumerate(combos):
                    out[:, c] += A[:, a] * (Bv[:, b, j] * Bw[:, e, k])[:, None]
        return out

    def _points_and_jac(self, H):
        return H[:, 0], (np.stack([H[:, 1], H[:, 2], H[:, 3]], axis=-1) if H.shape[1] > 1 else None)

    def __call__(self, u, v, w):
        """Points ``p(u, v, w)``: (..., 3)."""
        (uu, vv, ww), shape = self._params(u, v, w)
        x, _ = self._points_and_jac(self._homog_derivs(uu, vv, ww, False))
        return x.reshape(shape + (3,))

    def jacobian(self, u, v, w):
        """Jacobian matrices ``J[..., i, j] = d x_i / d (u, v, w)_j``: (..., 3, 3)."""
        (uu, vv, ww), shape = self._params(u, v, w)
        _, J = self._points_and_jac(self._homog_derivs(uu, vv, ww, True))
        return J.reshape(shape + (3, 3))

    def det_jacobian(self, u, v, w):
        """``det J``: (...)."""
        return np.linalg.det(self.jacobian(u, v, w))

    # ------------------------------------------------------------ boundary
    def _face(self, axis, end):
        C = np.moveaxis(self._ctrl(), axis, 0)
        U, d = self._U[axis], self._deg[axis]
        Q = _ops.contract(U, d, C, self._domains[axis][end])
        rest = [i for i in range(3) if i != axis]
        return self._surface(Q, self._deg[rest[0]], self._deg[rest[1]],
                             self._U[rest[0]], self._U[rest[1]])

    def _surface(self, Q, p, q, Uu, Uv):
        return BSplineSurface(Q, p, q, Uu, Uv)

    def boundary_surfaces(self):
        """The six boundary surfaces as surface objects.

        Returns
        -------
        dict with keys ``"u0", "u1", "v0", "v1", "w0", "w1"``; the ``"u0"`` face
        is ``(v, w) -> p(a_u, v, w)`` and similarly for the others (parameters in
        increasing axis order, so orientation is not adjusted outward).
        """
        return {f"{'uvw'[ax]}{end}": self._face(ax, end) for ax in range(3) for end in (0, 1)}

    # ------------------------------------------------------------ integrals
    def _default_gauss(self):
        return max(self._deg) * 5 // 2 + 1

    def mass_properties(self, density=1.0, *, n_gauss=None):
        """Volume, centroid and inertia tensor by tensor Gauss-Legendre quadrature.

        Parameters
        ----------
        density : float > 0
        n_gauss : int, optional
            Points per knot span and direction; exact for polynomial maps by
            default (``floor(5 max(degrees) / 2) + 1``).

        Returns
        -------
        VolumeProperties
            Integrals of ``|det J|`` (a map that folds over itself is counted once
            per cover).
        """
        rho = float(density)
        if not rho > 0:
            raise ValueError(f"density must be > 0, got {density}")
        n = self._default_gauss() if n_gauss is None else _check_degree(n_gauss, "n_gauss")
        C = self._ctrl()
        mats, wts = [], []
        for U, d, m in zip(self._U, self._deg, C.shape[:3]):
            x, wt = _gauss_spans(U, d, n)
            mats.append(basis_matrix(U, d, m, x, n_ders=1))
            wts.append(wt)
        (N0u, N1u), (N0v, N1v), (N0w, N1w) = mats

        def contract3(Au, Av, Aw):
            T = np.tensordot(Au, C, axes=(1, 0))          # (a, nv, nw, D)
            T = np.tensordot(Av, T, axes=(1, 1))          # (b, a, nw, D)
            T = np.tensordot(Aw, T, axes=(1, 2))          # (c, b, a, D)
            return np.transpose(T, (2, 1, 0, 3)).reshape(-1, C.shape[3])

        H = np.stack([contract3(N0u, N0v, N0w), contract3(N1u, N0v, N0w),
                      contract3(N0u, N1v, N0w), contract3(N0u, N0v, N1w)], axis=1)
        x, J = self._points_and_jac(H)
        W = (wts[0][:, None, None] * wts[1][None, :, None] * wts[2][None, None, :]).ravel()
        W = W * np.abs(np.linalg.det(J))
        vol = float(W.sum())
        if not vol > 0:
            raise ValueError("the volume map is degenerate (zero volume)")
        c = (W @ x) / vol
        r = x - c
        M2 = np.einsum("n,ni,nj->ij", W, r, r)
        inertia = rho * (np.trace(M2) * np.eye(3) - M2)
        return VolumeProperties(volume=vol, mass=rho * vol, density=rho, centroid=c,
                                inertia=inertia)

    def __repr__(self):
        return f"{type(self).__name__}(degrees={self._deg}, n_control={self._P.shape[:3]})"


class BezierVolume(BSplineVolume):
    """Trivariate Bezier volume on [0, 1]³; degrees follow from the control array.

    Parameters
    ----------
    control_points : (l + 1, m + 1, n + 1, 3) float

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> net = np.stack(np.meshgrid(t, t, t, indexing="ij"), -1)
    >>> mp = BezierVolume(net).mass_properties()
    >>> round(mp.volume, 12), np.round(np.diag(mp.inertia), 12).tolist()
    (1.0, [0.166666666667, 0.166666666667, 0.166666666667])
    """

    def __init__(self, control_points):
        P = np.asarray(control_points, dtype=float)
        if P.ndim != 4 or min(P.shape[:3]) < 2:
            raise ValueError(f"control_points must have shape (l+1, m+1, n+1, 3) with each "
                             f"count >= 2, got {P.shape}")
        degs = tuple(s - 1 for s in P.shape[:3])
        knots = [np.concatenate([np.zeros(d + 1), np.ones(d + 1)]) for d in degs]
        super().__init__(P, degs, knots)


class NURBSVolume(BSplineVolume):
    """Trivariate NURBS volume (homogeneous coordinates).

    Parameters
    ----------
    control_points : (n_u, n_v, n_w, 3) float
    weights : (n_u, n_v, n_w) float, all > 0
    degrees : (3,) int
    knots : tuple of three 1-D float arrays, optional

    Notes
    -----
    The integrand of :meth:`mass_properties` is rational, so Gauss quadrature
    converges rather than being exact; the default adds 6 points per span.
    """

    def __init__(self, control_points, weights, degrees, knots=None):
        super().__init__(control_points, degrees, knots)
        w = np.asarray(weights, dtype=float)
        if w.shape != self._P.shape[:3]:
            raise ValueError(f"weights must have shape {self._P.shape[:3]}, got {w.shape}")
        if not np.all((w > 0) & np.isfinite(w)):
            raise ValueError("weights must be > 0 and finite")
        self._w = w
        self._Pw = np.concatenate([self._P * w[..., None], w[..., None]], axis=-1)

    @property
    def weights(self):
        return self._w

    def _ctrl(self):
        return self._Pw

    def _points_and_jac(self, H):
        wt = H[:, 0, 3:]
        x = H[:, 0, :3] / wt
        if H.shape[1] == 1:
            return x, None
        cols = [(H[:, c, :3] - x * H[:, c, 3:]) / wt for c in (1, 2, 3)]
        return x, np.stack(cols, axis=-1)

    def _surface(self, Q, p, q, Uu, Uv):
        return NURBSSurface.from_homogeneous(Q, p, q, Uu, Uv)

    def _default_gauss(self):
        return max(self._deg) * 5 // 2 + 7

    @classmethod
    def revolve_rectangle(cls, r_inner, r_outer, z0, z1, angle=2 * np.pi):
        """Solid of revolution of the rectangle ``[r_inner, r_outer] x [z0, z1]`` about z.

        ``r_inner = 0`` gives a solid cylinder, ``r_inner > 0`` a tube. Parameters are
        (radius, angle, height); degrees (1, 2, 1).

        Examples
        --------
        >>> cyl = NURBSVolume.revolve_rectangle(0.0, 1.0, 0.0, 2.0)
        >>> round(cyl.mass_properties().volume / np.pi, 12)
        2.0
        """
        from .conics import arc
        if not (0 <= r_inner < r_outer and z0 < z1):
            raise ValueError(f"need 0 <= r_inner < r_outer and z0 < z1, got "
                             f"{r_inner}, {r_outer}, {z0}, {z1}")
        circ = arc(1.0, 0.0, angle, center=(0.0, 0.0))
        cx, cy = circ.control_points[:, 0], circ.control_points[:, 1]
        radii = np.array([r_inner, r_outer], dtype=float)
        zs = np.array([z0, z1], dtype=float)
        P = np.zeros((2, cx.size, 2, 3))
        P[..., 0] = radii[:, None, None] * cx[None, :, None]
        P[..., 1] = radii[:, None, None] * cy[None, :, None]
        P[..., 2] = zs[None, None, :]
        W = np.broadcast_to(circ.weights[None, :, None], (2, cx.size, 2))
        lin = np.array([0.0, 0.0, 1.0, 1.0])
        return cls(P, W, (1, 2, 1), (lin, circ.knots, lin))
