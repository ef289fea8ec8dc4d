"""Tensor-product surfaces: Bezier, B-spline and NURBS, and exact NURBS quadrics.

``S(u, v) = sum_i sum_j N_i(u) N_j(v) P_ij`` (rational: with weights ``h_ij``).
Control nets have shape ``(n_u, n_v, dim)``; ``u`` runs along axis 0.
Grids are evaluated as basis matrices ``Nu @ P @ Nv^T``, not per point.

References: The NURBS Book (Piegl and Tiller, 2nd ed.), A3.5-A3.6 (surface
points and derivatives), A4.3-A4.4 (rational), A5.3 (surface knot insertion),
A8.1 (surfaces of revolution).
"""

from __future__ import annotations

import numpy as np

from . import _ops
from .basis import (_check_degree, basis_funs, basis_matrix, clamped_knots, ders_basis_funs,
                    find_span, validate_knots)
from .conics import arc
from .curves import NURBS, BSpline, _check_order
from .surfaces import Surface

__all__ = ["BSplineSurface", "NURBSSurface", "BezierSurface", "surface_of_revolution",
           "sphere", "cylinder", "torus"]


def _net(arr, name):
    try:
        P = np.array(arr, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of shape (n_u, n_v, dim)") from None
    if P.ndim != 3 or P.shape[0] < 2 or P.shape[1] < 2:
        raise ValueError(f"{name} must have shape (n_u >= 2, n_v >= 2, dim), got {P.shape}")
    if not np.all(np.isfinite(P)):
        raise ValueError(f"{name} must be finite")
    P.setflags(write=False)
    return P


def tp_derivs(Uu, p, Uv, q, P, u, v, du, dv):
    """Tensor-product derivatives up to (du, dv): (N, du+1, dv+1, D) (A3.6)."""
    nu, nv = P.shape[:2]
    D = P.shape[2]
    su = find_span(Uu, p, nu, u)
    sv = find_span(Uv, q, nv, v)
    if du == 0:
        Bu = basis_funs(Uu, p, su, u)[:, None, :]
    else:
        Bu = ders_basis_funs(Uu, p, su, u, du)
    if dv == 0:
        Bv = basis_funs(Uv, q, sv, v)[:, None, :]
    else:
        Bv = ders_basis_funs(Uv, q, sv, v, dv)
    iu = su[:, None] - p + np.arange(p + 1)
    iv = sv[:, None] - q + np.arange(q + 1)
    flat = np.ascontiguousarray(P).reshape(nu * nv, D)
    idx = (iu[:, :, None] * nv + iv[:, None, :]).reshape(-1)
    G = np.take(flat, idx, axis=0).reshape(u.size, p + 1, (q + 1) * D)
    T = np.matmul(Bu, G).reshape(u.size, du + 1, q + 1, D)      # (N, k, j, D)
    T = np.transpose(T, (0, 1, 3, 2))                            # (N, k, D, j)
    out = np.matmul(T, np.transpose(Bv, (0, 2, 1))[:, None])     # (N, k, D, l)
    return np.transpose(out, (0, 1, 3, 2))


class BSplineSurface(Surface):
    """Tensor-product B-spline surface.

    Parameters
    ----------
    control_points : (n_u, n_v, dim) float
    degree_u, degree_v : int
    knots_u, knots_v : 1-D float, optional
        Clamped uniform on [0, 1] by default.

    Examples
    --------
    >>> g = np.stack(np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 5),
    ...                          indexing="ij"), -1)
    >>> net = np.concatenate([g, np.zeros((4, 5, 1))], axis=-1)
    >>> s = BSplineSurface(net, 3, 2)
    >>> s(0.25, 0.5)
    array([0.25, 0.5 , 0.  ])
    >>> s.grid(np.linspace(0, 1, 10), np.linspace(0, 1, 20)).shape
    (10, 20, 3)
    """

    def __init__(self, control_points, degree_u, degree_v, knots_u=None, knots_v=None):
        P = _net(control_points, "control_points")
        p = _check_degree(degree_u, "degree_u")
        q = _check_degree(degree_v, "degree_v")
        nu, nv = P.shape[:2]
        if nu < p + 1 or nv < q + 1:
            raise ValueError(f"control_points {P.shape[:2]} too small for degrees ({p}, {q})")
        self._Uu = validate_knots(clamped_knots(nu, p) if knots_u is None else knots_u, p, nu,
                                  "knots_u")
        self._Uv = validate_knots(clamped_knots(nv, q) if knots_v is None else knots_v, q, nv,
                                  "knots_v")
        self._P = P
        self._p, self._q = p, q
        self._dim = P.shape[2]
        self._domain_u = _ops.domain(self._Uu, p)
        self._domain_v = _ops.domain(self._Uv, q)

    # ------------------------------------------------------------ properties
    @property
    def control_points(self):
        """(n_u, n_v, dim) read-only control net."""
        return self._P

    @property
    def degree_u(self):
        return self._p

    @property
    def degree_v(self):
        return self._q

    @property
    def knots_u(self):
        return self._Uu

    @property
    def knots_v(self):
        return self._Uv

    # ------------------------------------------------------------ hooks for NURBS
    def _ctrl(self):
        return self._P

    def _from_ctrl(self, Q, p, q, Uu, Uv):
        return BSplineSurface(Q, p, q, Uu, Uv)

    def _project(self, H):
        return H

    # ------------------------------------------------------------ evaluation
    def _eval(self, u, v):
        H = tp_derivs(self._Uu, self._p, self._Uv, self._q, self._ctrl(), u, v, 0, 0)[:, 0, 0]
        return self._project(H)

    def _derivs(self, u, v, order):
        return tp_derivs(self._Uu, self._p, self._Uv, self._q, self._P, u, v, order, order)

    def basis_grid(self, us, vs):
        """Dense basis matrices ``Nu (len(us), n_u)`` and ``Nv (len(vs), n_v)``."""
        nu, nv = self._P.shape[:2]
        return (basis_matrix(self._Uu, self._p, nu, us), basis_matrix(self._Uv, self._q, nv, vs))

    def _grid(self, us, vs):
        Nu, Nv = self.basis_grid(us, vs)
        C = self._ctrl()
        nu, nv, D = C.shape
        T = (Nu @ C.reshape(nu, nv * D)).reshape(us.size, nv, D)
        H = np.matmul(np.transpose(T, (0, 2, 1)), Nv.T)  # (A, D, B)
        H = np.transpose(H, (0, 2, 1))
        return self._project(H)

    def _topology(self, grid):
        """Closed directions and poles from the control net (clamped knots).

        With clamped knots the edge ``u = a`` is the curve of control row
        ``P[0]`` (and ``u = b`` of ``P[-1]``): the direction is closed when the
        two rows (homogeneous for NURBS) are equal, an edge is a pole when all
        points of its row coincide; a wrapped periodic direction is closed.
        Unclamped, non-periodic directions fall back to the sampled grid.
        """
        closed_s, closed_v_s, poles_s = Surface._topology(self, grid)
        C = self._ctrl()
        P = self._P
        tol = 1e-12 * max(1.0, float(np.max(np.abs(C))))
        same = lambda x, y: bool(np.max(np.abs(x - y)) <= tol)  # noqa: E731
        out = []
        poles = set()
        for axis, (U, p) in enumerate(((self._Uu, self._p), (self._Uv, self._q))):
            Ct = C if axis == 0 else np.transpose(C, (1, 0, 2))
            Pt = P if axis == 0 else np.transpose(P, (1, 0, 2))
            name = "uv"[axis]
            if np.all(U[:p + 1] == U[p]) and np.all(U[-p - 1:] == U[-1]):
                out.append(same(Ct[0], Ct[-1]))
                poles |= {name + "0"} if same(Pt[0], Pt[0, :1]) else set()
                poles |= {name + "1"} if same(Pt[-1], Pt[-1, :1]) else set()
            elif _ops.periodic_count(U, p, Ct):
                out.append(True)
            else:
                out.append(closed_s if axis == 0 else closed_v_s)
                poles |= {x for x in poles_s if x[0] == name}
        return out[0], out[1], poles

    # ------------------------------------------------------------ isocurves
    def isocurve_u(self, u0):
        """Exact curve ``v -> S(u0, v)`` (a :class:`BSpline`, or :class:`NURBS`)."""
        u0 = float(self._params_1d(u0, self._domain_u, "u0")[0])
        Q = _ops.contract(self._Uu, self._p, self._ctrl(), u0)
        return self._curve(Q, self._q, self._Uv)

    def isocurve_v(self, v0):
        """Exact curve ``u -> S(u, v0)``."""
        v0 = float(self._params_1d(v0, self._domain_v, "v0")[0])
        Q = _ops.contract(self._Uv, self._q, np.transpose(self._ctrl(), (1, 0, 2)), v0)
        return self._curve(Q, self._p, self._Uu)

    def _curve(self, Q, deg, U):
        return BSpline(Q, deg, U)

    # ------------------------------------------------------------ editing
    def _edit_u(self, fn):
        Uu, Q = fn(self._Uu, self._p, self._ctrl())
        return Uu, Q

    def _edit_v(self, fn):
        Uv, Q = fn(self._Uv, self._q, np.transpose(self._ctrl(), (1, 0, 2)))
        return Uv, np.transpose(Q, (1, 0, 2))

    def insert_knot_u(self, u, times=1):
        """Insert knot ``u`` ``times`` times in the u direction (A5.3); same surface."""
        times = _check_degree(times, "times", minimum=1)
        Uu, Q = self._edit_u(lambda U, p, C: _ops.insert_knot(U, p, C, float(u), times))
        return self._from_ctrl(Q, self._p, self._q, Uu, self._Uv)

    def insert_knot_v(self, v, times=1):
        """Insert knot ``v`` ``times`` times in the v direction (A5.3); same surface."""
        times = _check_degree(times, "times", minimum=1)
        Uv, Q = self._edit_v(lambda U, p, C: _ops.insert_knot(U, p, C, float(v), times))
        return self._from_ctrl(Q, self._p, self._q, self._Uu, Uv)

    def refine_knots(self, new_knots_u=(), new_knots_v=()):
        """Insert many knots in either direction (A5.5); same surface."""
        out = self
        if len(new_knots_u):
            Uu, Q = out._edit_u(lambda U, p, C: _ops.refine(U, p, C, new_knots_u))
            out = out._from_ctrl(Q, out._p, out._q, Uu, out._Uv)
        if len(new_knots_v):
            Uv, Q = out._edit_v(lambda U, p, C: _ops.refine(U, p, C, new_knots_v))
            out = out._from_ctrl(Q, out._p, out._q, out._Uu, Uv)
        return out

    def elevate_degree(self, times_u=0, times_v=0):
        """Raise the degrees by ``times_u`` and ``times_v``; same surface (clamped result)."""
        tu = _check_degree(times_u, "times_u", minimum=0)
        tv = _check_degree(times_v, "times_v", minimum=0)
        out = self
        if tu:
            Uu, Q = out._edit_u(lambda U, p, C: _ops.elevate(U, p, C, tu))
            out = out._from_ctrl(Q, out._p + tu, out._q, Uu, out._Uv)
        if tv:
            Uv, Q = out._edit_v(lambda U, p, C: _ops.elevate(U, p, C, tv))
            out = out._from_ctrl(Q, out._p, out._q + tv, out._Uu, Uv)
        return out

    def to_nurbs(self):
        """The same surface as a :class:`NURBSSurface` with all weights 1."""
        return NURBSSurface(self._P, np.ones(self._P.shape[:2]), self._p, self._q,
                            self._Uu, self._Uv)

    def __repr__(self):
        return (f"{type(self).__name__}(degrees=({self._p}, {self._q}), "
                f"n_control={self._P.shape[:2]}, dim={self._dim})")


class NURBSSurface(BSplineSurface):
    """Tensor-product NURBS surface (homogeneous-coordinate evaluation).

    Parameters
    ----------
    control_points : (n_u, n_v, dim) float
    weights : (n_u, n_v) float, all > 0
    degree_u, degree_v : int
    knots_u, knots_v : 1-D float, optional

    Examples
    --------
    >>> net = np.zeros((3, 2, 3))
    >>> net[:, :, 0] = [[1, 1], [1, 1], [0, 0]]
    >>> net[:, :, 1] = [[0, 0], [1, 1], [1, 1]]
    >>> net[:, :, 2] = [[0, 1], [0, 1], [0, 1]]
    >>> w = np.array([[1, 1], [np.sqrt(0.5)] * 2, [1, 1]])
    >>> quarter_cylinder = NURBSSurface(net, w, 2, 1)
    >>> round(float(np.hypot(*quarter_cylinder(0.3, 0.7)[:2])), 12)
    1.0
    """

    def __init__(self, control_points, weights, degree_u, degree_v, knots_u=None, knots_v=None):
        super().__init__(control_points, degree_u, degree_v, knots_u, knots_v)
        try:
            w = np.array(weights, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("weights must be a numeric array of shape (n_u, n_v)") from None
        if w.shape != self._P.shape[:2]:
            raise ValueError(f"weights must have shape {self._P.shape[:2]}, got {w.shape}")
        if not np.all((w > 0) & np.isfinite(w)):
            raise ValueError("weights must be > 0 and finite")
        w.setflags(write=False)
        self._w = w
        Pw = np.concatenate([self._P * w[..., None], w[..., None]], axis=-1)
        Pw.setflags(write=False)
        self._Pw = Pw

    @classmethod
    def from_homogeneous(cls, Pw, degree_u, degree_v, knots_u, knots_v):
        Pw = np.asarray(Pw, dtype=float)
        w = Pw[..., -1]
        return cls(Pw[..., :-1] / w[..., None], w, degree_u, degree_v, knots_u, knots_v)

    @property
    def weights(self):
        return self._w

    @property
    def homogeneous(self):
        """(n_u, n_v, dim + 1) homogeneous control net ``(h P, h)``."""
        return self._Pw

    def _ctrl(self):
        return self._Pw

    def _from_ctrl(self, Q, p, q, Uu, Uv):
        return NURBSSurface.from_homogeneous(Q, p, q, Uu, Uv)

    def _project(self, H):
        return H[..., :-1] / H[..., -1:]

    def _curve(self, Q, deg, U):
        return NURBS.from_homogeneous(Q, deg, U)

    def _derivs(self, u, v, order):
        """Rational partial derivatives from homogeneous ones (A4.4)."""
        from scipy.special import comb  # local: scipy.special costs 0.1 s to import

        H = tp_derivs(self._Uu, self._p, self._Uv, self._q, self._Pw, u, v, order, order)
        A, w = H[..., :-1], H[..., -1]
        S = np.zeros_like(A)
        for k in range(order + 1):
            for l in range(order + 1):
                val = A[:, k, l].copy()
                for j in range(1, l + 1):
                    val -= comb(l, j) * w[:, 0, j, None] * S[:, k, l - j]
                for i in range(1, k + 1):
                    val -= comb(k, i) * w[:, i, 0, None] * S[:, k - i, l]
                    for j in range(1, l + 1):
                        val -= comb(k, i) * comb(l, j) * w[:, i, j, None] * S[:, k - i, l - j]
                S[:, k, l] = val / w[:, 0, 0, None]
        return S

    def to_nurbs(self):
        return self


class BezierSurface(BSplineSurface):
    """Tensor-product Bezier surface ``sum B_{i,m}(u) B_{j,n}(v) P_ij`` on [0, 1]².

    Parameters
    ----------
    control_points : (m + 1, n + 1, dim) float
        The characteristic polygon; degrees are ``m`` and ``n``.

    Examples
    --------
    >>> net = np.zeros((3, 3, 3))
    >>> net[..., 0], net[..., 1] = np.meshgrid([0, 1, 2], [0, 1, 2], indexing="ij")
    >>> net[1, 1, 2] = 4.0
    >>> BezierSurface(net)(0.5, 0.5)
    array([1., 1., 1.])
    """

    def __init__(self, control_points):
        P = _net(control_points, "control_points")
        m, n = P.shape[0] - 1, P.shape[1] - 1
        Uu = np.concatenate([np.zeros(m + 1), np.ones(m + 1)])
        Uv = np.concatenate([np.zeros(n + 1), np.ones(n + 1)])
        super().__init__(P, m, n, Uu, Uv)

    def _from_ctrl(self, Q, p, q, Uu, Uv):
        return BSplineSurface(Q, p, q, Uu, Uv)

    def elevate_degree(self, times_u=0, times_v=0):
        out = super().elevate_degree(times_u, times_v)
        return BezierSurface(out.control_points) if isinstance(out, BSplineSurface) else out


# --------------------------------------------------------------------------- exact surfaces

def _unit_axis(axis):
    a = np.asarray(axis, dtype=float).ravel()
    if a.size != 3 or not np.linalg.norm(a) > 0:
        raise ValueError(f"axis must be a non-zero 3-vector, got {axis!r}")
    return a / np.linalg.norm(a)


def surface_of_revolution(profile, axis=(0.0, 0.0, 1.0), *, axis_point=(0.0, 0.0, 0.0),
                          angle=2 * np.pi):
    """Exact NURBS surface sweeping ``profile`` about an axis (A8.1).

    ``u`` runs around the axis (an exact circular arc of ``angle``), ``v`` along the
    profile. Each control point ``P_j`` of the profile becomes a circle of control
    points ``A + (d.a) a + cx_i d_perp + cy_i a x d_perp`` with ``d = P_j - A``,
    where ``(cx_i, cy_i)`` and ``w_i`` are the unit arc's control points and
    weights; weights multiply.

    Parameters
    ----------
    profile : BSpline or NURBS, 3-D
    axis : (3,) float
        Direction of the axis; the surface turns counter-clockwise about it.
    axis_point : (3,) float
        A point of the axis.
    angle : float, radians in (0, 2 pi]

    Returns
    -------
    NURBSSurface of degree (2, profile.degree).

    Examples
    --------
    >>> from parametric.curves import BSpline
    >>> cone = surface_of_revolution(BSpline([[1, 0, 0], [0, 0, 1]], 1))
    >>> p = cone(0.3, 0.25)
    >>> round(float(np.hypot(p[0], p[1])), 12), round(float(p[2]), 12)
    (0.75, 0.25)
    """
    if not isinstance(profile, BSpline):
        raise TypeError(f"profile must be a BSpline or NURBS curve, got {type(profile).__name__}")
    if profile.dim != 3:
        raise ValueError(f"profile must be 3-D, got dim {profile.dim}")
    a = _unit_axis(axis)
    A = np.asarray(axis_point, dtype=float).ravel()
    if A.size != 3:
        raise ValueError(f"axis_point must have 3 coordinates, got {A.size}")
    circ = arc(1.0, 0.0, angle, center=(0.0, 0.0))
    cx, cy = circ.control_points[:, 0], circ.control_points[:, 1]
    prof = profile.to_nurbs()
    d = prof.control_points - A
    along = (d @ a)[:, None] * a
    perp = d - along
    rot = np.cross(a, perp)
    P = (A + along)[None, :, :] + cx[:, None, None] * perp[None] + cy[:, None, None] * rot[None]
    W = circ.weights[:, None] * prof.weights[None, :]
    return NURBSSurface(P, W, 2, prof.degree, circ.knots, prof.knots)


def sphere(radius=1.0, center=(0.0, 0.0, 0.0)):
    """Exact NURBS sphere: a semicircle revolved about z (degree 2 x 2, 9 x 5 net).

    ``u`` is the longitude, ``v`` runs from the south pole (v = 0) to the north pole.

    Examples
    --------
    >>> s = sphere(2.0)
    >>> round(float(np.linalg.norm(s(0.3, 0.6))), 12)
    2.0
    """
    r = float(radius)
    if not r > 0:
        raise ValueError(f"radius must be > 0, got {radius}")
    c = np.asarray(center, dtype=float).ravel()
    prof = arc(r, -np.pi / 2, np.pi, center=c, normal=(0.0, -1.0, 0.0), x_axis=(1.0, 0.0, 0.0))
    return surface_of_revolution(prof, (0.0, 0.0, 1.0), axis_point=c)


def cylinder(radius=1.0, height=1.0, center=(0.0, 0.0, 0.0)):
    """Exact NURBS cylinder side, axis z, base circle at ``center`` (degree 2 x 1).

    Examples
    --------
    >>> p = cylinder(2.0, 3.0)(0.1, 0.5)
    >>> round(float(np.hypot(p[0], p[1])), 12), round(float(p[2]), 12)
    (2.0, 1.5)
    """
    r, h = float(radius), float(height)
    if not (r > 0 and h > 0):
        raise ValueError(f"radius and height must be > 0, got {radius}, {height}")
    c = np.asarray(center, dtype=float).ravel()
    prof = NURBS([c + [r, 0.0, 0.0], c + [r, 0.0, h]], [1.0, 1.0], 1)
    return surface_of_revolution(prof, (0.0, 0.0, 1.0), axis_point=c)


def torus(major_radius=2.0, minor_radius=0.5, center=(0.0, 0.0, 0.0)):
    """Exact NURBS torus about the z axis (degree 2 x 2, 9 x 9 net).

    Examples
    --------
    >>> p = torus(2.0, 0.5)(0.2, 0.7)
    >>> round(float(np.hypot(np.hypot(p[0], p[1]) - 2.0, p[2])), 12)
    0.5
    """
    R, r = float(major_radius), float(minor_radius)
    if not (R > 0 and r > 0):
        raise ValueError(f"major_radius and minor_radius must be > 0, got {R}, {r}")
    c = np.asarray(center, dtype=float).ravel()
    prof = arc(r, 0.0, 2 * np.pi, center=c + [R, 0.0, 0.0], normal=(0.0, -1.0, 0.0),
               x_axis=(1.0, 0.0, 0.0))
    return surface_of_revolution(prof, (0.0, 0.0, 1.0), axis_point=c)
