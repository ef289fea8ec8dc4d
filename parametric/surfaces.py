"""Biparametric surfaces: the common base, Coons patches, ruled and bicubic patches.

Tensor-product Bezier, B-spline and NURBS surfaces live in
:mod:`parametric.tensor` and share the :class:`Surface` base defined here.

A surface maps ``(u, v)`` in its rectangular domain to points: ``surface(u, v)``
takes equal-shape (or broadcastable) arrays and returns ``(..., 3)``.
"""

from __future__ import annotations

import numpy as np

from .basis import KNOT_TOL
from .curve_base import fd_stencil
from .curves import Bezier, Curve, FunctionCurve, _check_order, _HERMITE, _power_derivs

__all__ = ["Surface", "CoonsPatch", "RuledSurface", "BicubicPatch"]

#: Corner mismatch allowed by :class:`CoonsPatch`, relative to the patch size.
CORNER_TOL = 1e-9

#: Distance (relative to the surface size) under which a sampled edge counts as
#: closed or collapsed in :meth:`Surface.tessellate` (surfaces without a control net).
SEAM_TOL = 1e-10


def _check_domain_pair(dom, name):
    a, b = (float(x) for x in dom)
    if not a < b:
        raise ValueError(f"{name} must satisfy a < b, got ({a}, {b})")
    return a, b


class Surface:
    """Base of all biparametric surfaces ``S(u, v)``.

    Subclasses implement ``_eval(u, v)`` on flat validated arrays, returning
    ``(n, dim)``, and may override ``_derivs(u, v, order)`` (returning
    ``(n, order + 1, order + 1, dim)``) and ``_grid(us, vs)``; the defaults use
    central differences and point evaluation.
    """

    _domain_u = (0.0, 1.0)
    _domain_v = (0.0, 1.0)
    _dim = 3

    @property
    def domain_u(self):
        return self._domain_u

    @property
    def domain_v(self):
        return self._domain_v

    @property
    def dim(self):
        return self._dim

    def __bool__(self):
        raise TypeError(f"the truth value of a {type(self).__name__} is ambiguous")

    # ---------------------------------------------------------------- parameters
    @staticmethod
    def _check_in(arr, dom, name):
        a, b = dom
        tol = KNOT_TOL * max(1.0, abs(a), abs(b))
        if arr.size:
            ok = np.isfinite(arr) & (arr >= a - tol) & (arr <= b + tol)
            if not np.all(ok):
                raise ValueError(f"{name} must lie in [{a}, {b}], got {arr[~ok].ravel()[0]}")
        return np.clip(arr, a, b)

    def _params(self, u, v):
        try:
            uu = np.asarray(u, dtype=float)
            vv = np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            raise TypeError("u and v must be floats or arrays of floats") from None
        try:
            uu, vv = np.broadcast_arrays(uu, vv)
        except ValueError:
            raise ValueError(f"u and v must have equal (broadcastable) shapes, got "
                             f"{np.shape(u)} and {np.shape(v)}") from None
        shape = uu.shape
        uu = self._check_in(uu.ravel(), self._domain_u, "u")
        vv = self._check_in(vv.ravel(), self._domain_v, "v")
        return uu, vv, shape

    def _params_1d(self, x, dom, name):
        try:
            arr = np.atleast_1d(np.asarray(x, dtype=float))
        except (TypeError, ValueError):
            raise TypeError(f"{name} must be a 1-D array of floats") from None
        if arr.ndim != 1:
            raise ValueError(f"{name} must be 1-D, got shape {arr.shape}")
        return self._check_in(arr, dom, name)

    # ---------------------------------------------------------------- evaluation
    def __call__(self, u, v):
        """Points ``S(u, v)``: (..., dim) for ``u`` and ``v`` of shape (...)."""
        uu, vv, shape = self._params(u, v)
        return self._eval(uu, vv).reshape(shape + (self._dim,))

    def grid(self, us, vs):
        """Points on the tensor grid ``us x vs``: (len(us), len(vs), dim)."""
        us = self._params_1d(us, self._domain_u, "us")
        vs = self._params_1d(vs, self._domain_v, "vs")
        return self._grid(us, vs)

    def _grid(self, us, vs):
        U, V = np.meshgrid(us, vs, indexing="ij")
        return self._eval(U.ravel(), V.ravel()).reshape(us.size, vs.size, self._dim)

    def derivatives(self, u, v, order=1):
        """Partial derivatives ``d^(k+l) S / du^k dv^l`` for ``k, l <= order``.

        Returns
        -------
        (..., order + 1, order + 1, dim) float array; ``[..., k, l, :]`` holds
        the ``k``-th derivative in ``u`` and ``l``-th in ``v``.
        """
        order = _check_order(order)
        uu, vv, shape = self._params(u, v)
        out = self._derivs(uu, vv, order)
        return out.reshape(shape + out.shape[1:])

    def _derivs(self, u, v, order):
        if order > 2:
            return self._derivs_any(u, v, order)
        au, bu = self._domain_u
        av, bv = self._domain_v
        hu = 1e-4 * (bu - au)
        hv = 1e-4 * (bv - av)
        u0, u1 = np.clip(u - hu, au, bu), np.clip(u + hu, au, bu)
        v0, v1 = np.clip(v - hv, av, bv), np.clip(v + hv, av, bv)
        um, vm = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
        su, sv = ((u1 - u0) / 2)[:, None], ((v1 - v0) / 2)[:, None]
        f = self._eval
        out = np.zeros((u.size, order + 1, order + 1, self._dim))
        out[:, 0, 0] = f(u, v)
        if order >= 1:
            out[:, 1, 0] = (f(u1, v) - f(u0, v)) / (2 * su)
            out[:, 0, 1] = (f(u, v1) - f(u, v0)) / (2 * sv)
        if order >= 2:
            out[:, 2, 0] = (f(u1, v) - 2 * f(um, v) + f(u0, v)) / su ** 2
            out[:, 0, 2] = (f(u, v1) - 2 * f(u, vm) + f(u, v0)) / sv ** 2
            out[:, 1, 1] = (f(u1, v1) - f(u1, v0) - f(u0, v1) + f(u0, v0)) / (4 * su * sv)
        return out

    def _derivs_any(self, u, v, order):
        """Partial derivatives of any order by tensor central differences.

        ``d^(k+l) S / du^k dv^l`` uses the product of the ``k``-th difference
        stencil in ``u`` and the ``l``-th in ``v``, both with steps
        ``eps^(1/(k+l+2))`` of their domain (see
        :func:`parametric.curve_base.fd_stencil`); second-order accurate.
        """
        (au, bu), (av, bv) = self._domain_u, self._domain_v
        n = u.size
        out = np.zeros((n, order + 1, order + 1, self._dim))
        one = np.ones((n, 1))
        for k in range(order + 1):
            for l in range(order + 1):
                tot = k + l
                nu_, wu = fd_stencil(u, k, au, bu, tot) if k else (u[:, None], one)
                nv_, wv = fd_stencil(v, l, av, bv, tot) if l else (v[:, None], one)
                a_, b_ = nu_.shape[1], nv_.shape[1]
                U = np.broadcast_to(nu_.T[:, None, :], (a_, b_, n))
                V = np.broadcast_to(nv_.T[None, :, :], (a_, b_, n))
                vals = self._eval(U.ravel(), V.ravel()).reshape(a_, b_, n, self._dim)
                out[:, k, l] = np.einsum("ni,nj,ijnd->nd", wu, wv, vals)
        return out

    def normal(self, u, v):
        """Unit normals ``Su x Sv / |Su x Sv|``: (..., 3)."""
        if self._dim != 3:
            raise ValueError(f"normal needs a 3-D surface, this one has dim {self._dim}")
        d = self.derivatives(u, v, 1)
        n = np.cross(d[..., 1, 0, :], d[..., 0, 1, :])
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    # ---------------------------------------------------------------- curves on the surface
    def isocurve_u(self, u0):
        """The curve ``v -> S(u0, v)``."""
        u0 = float(self._params_1d(u0, self._domain_u, "u0")[0])
        return FunctionCurve(lambda v: self._eval(np.full(v.shape, u0), v), self._domain_v,
                             self._dim)

    def isocurve_v(self, v0):
        """The curve ``u -> S(u, v0)``."""
        v0 = float(self._params_1d(v0, self._domain_v, "v0")[0])
        return FunctionCurve(lambda u: self._eval(u, np.full(u.shape, v0)), self._domain_u,
                             self._dim)

    def isoparametric_lines(self, step=0.1, samples=50):
        """Polylines of the isoparametric curves at ``u`` and ``v`` steps of ``step``.

        ``step`` is a fraction of each domain (0.1 gives 11 lines each way).

        Returns
        -------
        u_lines : (k, samples, dim) float
            Curves of constant ``u`` (``u = a_u + i step (b_u - a_u)``).
        v_lines : (k, samples, dim) float
            Curves of constant ``v``.
        """
        step = float(step)
        if not 0 < step <= 1:
            raise ValueError(f"step must lie in (0, 1], got {step}")
        samples = int(samples)
        if samples < 2:
            raise ValueError(f"samples must be >= 2, got {samples}")
        fr = np.arange(0.0, 1.0 + 1e-9, step)
        fr[-1] = min(fr[-1], 1.0)
        (au, bu), (av, bv) = self._domain_u, self._domain_v
        t = np.linspace(0.0, 1.0, samples)
        u_lines = self._grid(au + fr * (bu - au), av + t * (bv - av))
        v_lines = np.transpose(self._grid(au + t * (bu - au), av + fr * (bv - av)), (1, 0, 2))
        return u_lines, v_lines

    def tessellate(self, nu=32, nv=32, *, merge_seams=True):
        """Triangulate the surface on a regular ``nu x nv`` parameter grid.

        Triangles wind counter-clockwise about ``Su x Sv`` (the :meth:`normal`).

        With ``merge_seams`` (default) the grid is welded by parameter-space
        topology: a closed direction (the edge ``u = a`` is the edge ``u = b``)
        identifies grid point ``(nu - 1, j)`` with ``(0, j)``, and a collapsed
        boundary edge (a pole, e.g. ``v = 0`` of :func:`parametric.tensor.sphere`)
        becomes one vertex; triangles left with a repeated vertex are dropped.
        Which edges are closed or collapsed is decided once per edge (from
        the control net of tensor surfaces, else from the sampled edge), never
        point by point. A NURBS sphere gives a closed 2-manifold with Euler
        characteristic 2, a torus one with 0. With ``merge_seams=False`` the raw
        grid is returned (``nu * nv`` points, ``2 (nu - 1)(nv - 1)`` triangles,
        point ``i * nv + j`` at the ``(i, j)`` grid parameters).

        Returns
        -------
        points : (k, dim) float
        triangles : (t, 3) int

        Examples
        --------
        >>> from parametric.tensor import sphere
        >>> pts, tri = sphere(1.0).tessellate(9, 5)
        >>> pts.shape, tri.shape
        ((26, 3), (48, 3))
        """
        nu, nv = int(nu), int(nv)
        if nu < 2 or nv < 2:
            raise ValueError(f"nu and nv must be >= 2, got {nu}, {nv}")
        (au, bu), (av, bv) = self._domain_u, self._domain_v
        grid = self._grid(np.linspace(au, bu, nu), np.linspace(av, bv, nv))
        pts = grid.reshape(-1, self._dim)
        i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
        a = (i * nv + j).ravel()
        b = a + nv
        c = b + 1
        d = a + 1
        tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int64)
        if not merge_seams:
            return pts, tris
        closed_u, closed_v, poles = self._topology(grid)
        return _weld(pts, tris, nu, nv, closed_u, closed_v, poles)

    def _topology(self, grid):
        """(closed_u, closed_v, poles) of the surface, from a sampled grid.

        ``poles`` is the set of collapsed boundary edges among ``"u0", "u1",
        "v0", "v1"`` (``"v0"``: all points ``S(u, a_v)`` coincide). Tensor
        surfaces decide from their control net instead.
        """
        scale = max(1.0, float(np.ptp(grid.reshape(-1, self._dim), axis=0).max()))
        tol = SEAM_TOL * scale
        same = lambda x, y: bool(np.max(np.linalg.norm(x - y, axis=-1)) <= tol)  # noqa: E731
        closed_u = same(grid[0], grid[-1])
        closed_v = same(grid[:, 0], grid[:, -1])
        poles = {name for name, edge in (("u0", grid[0]), ("u1", grid[-1]),
                                          ("v0", grid[:, 0]), ("v1", grid[:, -1]))
                 if same(edge, edge[:1])}
        return closed_u, closed_v, poles


def _weld(pts, tris, nu, nv, closed_u, closed_v, poles):
    """Merge grid vertices identified by the seams and poles; drop degenerate triangles."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    idx = np.arange(nu * nv).reshape(nu, nv)
    pairs = []
    if closed_u:
        pairs.append((idx[-1], idx[0]))
    if closed_v:
        pairs.append((idx[:, -1], idx[:, 0]))
    for name, edge in (("u0", idx[0]), ("u1", idx[-1]), ("v0", idx[:, 0]), ("v1", idx[:, -1])):
        if name in poles:
            pairs.append((edge, np.full(edge.shape, edge[0])))
    if not pairs:
        return pts, tris
    src = np.concatenate([p[0] for p in pairs])
    dst = np.concatenate([p[1] for p in pairs])
    n = nu * nv
    graph = coo_matrix((np.ones(src.size), (src, dst)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    # number the merged vertices in order of their first grid point
    first = np.full(label.max() + 1, n)
    np.minimum.at(first, label, np.arange(n))
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    new = rank[label]
    T = new[tris]
    keep = (T[:, 0] != T[:, 1]) & (T[:, 1] != T[:, 2]) & (T[:, 0] != T[:, 2])
    return pts[first[order]], T[keep]


# --------------------------------------------------------------------------- Coons

def _as_curve(c, name):
    if isinstance(c, Curve):
        return c
    if callable(c):
        return FunctionCurve(c, (0.0, 1.0))
    raise TypeError(f"{name} must be a curve or a callable u -> points, got {type(c).__name__}")


def _curve_derivs(curve, t, order):
    """Derivatives of ``curve`` reparametrized onto [0, 1]: (n, order+1, dim)."""
    a, b = curve.domain
    d = curve.derivatives(a + t * (b - a), order)
    scale = (b - a) ** np.arange(order + 1)
    return d * scale[None, :, None]


def _blend(kind, t, order):
    """Linear blending f(t) = 1 - t and g = 1 - f with derivatives: (n, order+1) each."""
    out = np.zeros((t.size, order + 1))
    out[:, 0] = 1.0 - t
    if order >= 1:
        out[:, 1] = -1.0
    g = -out.copy()
    g[:, 0] += 1.0
    return out, g


class CoonsPatch(Surface):
    """Coons patch through four boundary curves.

    ``blend="linear"`` (alias ``"bilinear"``), the bilinearly blended patch of
    the lecture notes, with ``f(t) = 1 - t`` and ``g(t) = t``:

    ``P(u,v) = C0(u) f(v) + C1(u) g(v) + D0(v) f(u) + D1(v) g(u)
    - p00 f(u) f(v) - p01 f(u) g(v) - p10 g(u) f(v) - p11 g(u) g(v)``.

    ``blend="cubic"``, the bicubically blended Coons patch: with the cubic
    Hermite blends ``H0 = 1 - 3t² + 2t³``, ``H1 = 3t² - 2t³``,
    ``H2 = t - 2t² + t³``, ``H3 = t³ - t²`` (:class:`Hermite`),

    ``P = sum_b H_b(v) R_b(u) + sum_a H_a(u) S_a(v) - sum_ab H_a(u) M_ab H_b(v)``

    where ``R = (C0, C1, T0, T1)``, ``S = (D0, D1, E0, E1)``; ``T0(u)`` and
    ``T1(u)`` are the cross-boundary derivatives ``dP/dv`` along ``v = 0`` and
    ``v = 1``, ``E0(v)``, ``E1(v)`` the derivatives ``dP/du`` along ``u = 0``
    and ``u = 1``, and the 4 x 4 corner matrix ``M`` holds the corner points,
    the boundary tangents at the corners and the twist vectors
    ``d²P/du dv`` (the twist correction). The patch interpolates the four
    boundaries and the four cross-boundary derivative curves. Cross-boundary
    derivatives not supplied are estimated from the boundaries: those of the
    linear Coons patch (``T0 = C1 - C0 + (1 - u)(D0'(0) - p01 + p00)
    + u (D1'(0) - p11 + p10)`` and alike), plus ``H2``/``H3`` terms that give
    them the twists of supplied neighbours. The twist at a corner is taken
    from the supplied cross derivative curves through it (both must agree),
    else it is the twist of the linear Coons patch. With no cross derivative
    supplied the cubic patch therefore equals the linear one (the Boolean sum
    of Hermite projectors reproduces any function linear in ``u`` or ``v``):
    the cubic blend is for prescribing cross-boundary derivatives, e.g. to
    join neighbouring patches with C^1 continuity.

    References: S. A. Coons, *Surfaces for computer-aided design of space
    forms*, MIT MAC-TR-41 (1967); G. Farin, *Curves and Surfaces for CAGD*,
    5th ed. (2002), ch. 22, doi:10.1016/B978-1-55860-737-8.X5000-5.

    Parameters
    ----------
    c0, c1 : curve or callable
        Boundaries at ``v = 0`` and ``v = 1``, parametrized by ``u``.
    d0, d1 : curve or callable
        Boundaries at ``u = 0`` and ``u = 1``, parametrized by ``v``.
        Curve objects are reparametrized onto [0, 1]; plain callables take
        ``u`` in [0, 1] and return ``(n, 3)``.
    blend : {"linear", "bilinear", "cubic"}
        ``"linear"`` and ``"bilinear"`` name the same patch: linear blends in
        each direction give the bilinearly blended Coons patch.
    tol : float
        Allowed corner mismatch relative to the patch size.
    cross_tangents : sequence of 4 (curve, callable or None), optional
        ``(T0, T1, E0, E1)`` for ``blend="cubic"``: ``T0(u) = dP/dv(u, 0)``,
        ``T1(u) = dP/dv(u, 1)``, ``E0(v) = dP/du(0, v)``, ``E1(v) = dP/du(1, v)``
        (values in patch parameters; curve objects are reparametrized onto
        [0, 1]). ``None`` entries are estimated. Each must start and end on the
        tangents of the boundaries it meets (``T0(0) = D0'(0)``, ...).

    Raises
    ------
    ValueError
        If the corners do not match, ``cross_tangents`` is given with a
        linear blend, a cross derivative does not meet the boundary tangent at
        a corner, or two supplied cross derivatives give different twists.

    Examples
    --------
    >>> from parametric.curves import BSpline
    >>> c0 = BSpline([[0, 0, 0], [1, 0, 1], [2, 0, 0]], 2)
    >>> c1 = BSpline([[0, 2, 0], [1, 2, -1], [2, 2, 0]], 2)
    >>> d0 = BSpline([[0, 0, 0], [0, 2, 0]], 1)
    >>> d1 = BSpline([[2, 0, 0], [2, 2, 0]], 1)
    >>> patch = CoonsPatch(c0, c1, d0, d1)
    >>> patch(0.5, 0.0)
    array([1. , 0. , 0.5])
    >>> lift = lambda u: np.stack([0 * u, 2 + 0 * u, 4 * u * (1 - u)], -1)
    >>> cubic = CoonsPatch(c0, c1, d0, d1, blend="cubic", cross_tangents=(lift, None, None, None))
    >>> cubic.derivatives(0.5, 0.0, 1)[0, 1]
    array([0., 2., 1.])
    """

    def __init__(self, c0, c1, d0, d1, *, blend="linear", tol=CORNER_TOL, cross_tangents=None):
        self._c0 = _as_curve(c0, "c0")
        self._c1 = _as_curve(c1, "c1")
        self._d0 = _as_curve(d0, "d0")
        self._d1 = _as_curve(d1, "d1")
        if blend not in ("linear", "bilinear", "cubic"):
            raise ValueError(f"blend must be 'linear' (alias 'bilinear') or 'cubic', got {blend!r}")
        self._blend = "linear" if blend == "bilinear" else blend
        if cross_tangents is not None:
            if self._blend != "cubic":
                raise ValueError("cross_tangents needs blend='cubic' (the linear patch has no "
                                 "cross-boundary derivative terms)")
            if isinstance(cross_tangents, (str, bytes)) or len(cross_tangents) != 4:
                raise ValueError("cross_tangents must be 4 entries (T0, T1, E0, E1), "
                                 f"got {cross_tangents!r}")
        ends = np.array([0.0, 1.0])
        c0e = _curve_derivs(self._c0, ends, 1)
        c1e = _curve_derivs(self._c1, ends, 1)
        d0e = _curve_derivs(self._d0, ends, 1)
        d1e = _curve_derivs(self._d1, ends, 1)
        dims = {c0e.shape[-1], c1e.shape[-1], d0e.shape[-1], d1e.shape[-1]}
        if len(dims) != 1:
            raise ValueError(f"c0, c1, d0, d1 must share one dimension, got {sorted(dims)}")
        self._dim = dims.pop()
        pts = np.concatenate([c0e[:, 0], c1e[:, 0], d0e[:, 0], d1e[:, 0]])
        scale = max(1.0, float(np.ptp(pts, axis=0).max()))
        checks = [("p00", "c0(0)", c0e[0, 0], "d0(0)", d0e[0, 0]),
                  ("p10", "c0(1)", c0e[1, 0], "d1(0)", d1e[0, 0]),
                  ("p01", "c1(0)", c1e[0, 0], "d0(1)", d0e[1, 0]),
                  ("p11", "c1(1)", c1e[1, 0], "d1(1)", d1e[1, 0])]
        for corner, na, a, nb, b in checks:
            if np.linalg.norm(a - b) > tol * scale:
                raise ValueError(f"corner {corner} does not match: {na} = {a.tolist()} "
                                 f"but {nb} = {b.tolist()}")
        self._corners = {"p00": c0e[0, 0], "p10": c0e[1, 0], "p01": c1e[0, 0], "p11": c1e[1, 0]}
        if self._blend == "cubic":
            self._setup_cubic(c0e, c1e, d0e, d1e, cross_tangents, tol, scale)

    def _setup_cubic(self, c0e, c1e, d0e, d1e, cross, tol, scale):
        c = self._corners
        P = np.array([[c["p00"], c["p01"]], [c["p10"], c["p11"]]])        # P[i, j] = P(i, j)
        Pu = np.array([[c0e[0, 1], c1e[0, 1]], [c0e[1, 1], c1e[1, 1]]])   # dP/du at (i, j)
        Pv = np.array([[d0e[0, 1], d0e[1, 1]], [d1e[0, 1], d1e[1, 1]]])   # dP/dv at (i, j)
        # linear-patch cross derivatives: T_j = C1 - C0 + (1 - u) eT[0, j] + u eT[1, j],
        # E_i = D1 - D0 + (1 - v) eE[i, 0] + v eE[i, 1]
        eT = Pv - (P[:, 1] - P[:, 0])[:, None]
        eE = Pu - (P[1] - P[0])[None]
        tw_lin_T = (Pu[:, 1] - Pu[:, 0])[:, None] - eT[0][None] + eT[1][None]   # T_j'(i)
        tw_lin_E = (Pv[1] - Pv[0])[None] - eE[:, 0][:, None] + eE[:, 1][:, None]  # E_i'(j)
        given = [None] * 4 if cross is None else [
            None if t is None else _as_curve(t, n) for t, n in zip(cross, ("T0", "T1", "E0", "E1"))]
        ends = np.array([0.0, 1.0])
        tw = tw_lin_T.copy()
        src = np.full((2, 2), "", dtype=object)
        tscale = max(1.0, float(np.max(np.abs(np.concatenate([Pu.ravel(), Pv.ravel()])))))
        for idx, curve in enumerate(given):
            if curve is None:
                continue
            name = ("T0", "T1", "E0", "E1")[idx]
            d = _curve_derivs(curve, ends, 1)
            if d.shape[-1] != self._dim:
                raise ValueError(f"cross_tangents {name} must have dimension {self._dim}, "
                                 f"got {d.shape[-1]}")
            for e in (0, 1):
                i, j = (e, idx) if idx < 2 else (idx - 2, e)
                want = Pv[i, j] if idx < 2 else Pu[i, j]
                if np.linalg.norm(d[e, 0] - want) > tol * tscale:
                    raise ValueError(
                        f"cross_tangents {name} at corner p{i}{j} is {d[e, 0].tolist()} but the "
                        f"boundary tangent there is {want.tolist()}")
                if src[i, j] and np.linalg.norm(d[e, 1] - tw[i, j]) > max(tol, 1e-7) * tscale:
                    raise ValueError(
                        f"cross_tangents {src[i, j]} and {name} give different twists at corner "
                        f"p{i}{j}: {tw[i, j].tolist()} and {d[e, 1].tolist()}")
                tw[i, j] = d[e, 1]
                src[i, j] = name
        self._cubic = dict(P=P, Pu=Pu, Pv=Pv, eT=eT, eE=eE, tw=tw, given=given,
                           fixT=tw - tw_lin_T, fixE=tw - tw_lin_E)
        M = np.empty((4, 4, self._dim))
        M[:2, :2] = P
        M[:2, 2:] = Pv
        M[2:, :2] = Pu
        M[2:, 2:] = tw
        self._M = M

    @property
    def corners(self):
        """Dict of the corner points p00, p10, p01, p11 (``p_ij = P(i, j)``)."""
        return dict(self._corners)

    @property
    def twists(self):
        """(2, 2, dim) twist vectors ``d²P/du dv`` at the corners (cubic blend), else None."""
        return None if self._blend != "cubic" else self._cubic["tw"].copy()

    def _cross(self, which, t, order, B0, B1):
        """Cross-boundary derivative curve ``which`` (0..3 = T0, T1, E0, E1) at ``t``."""
        cb = self._cubic
        curve = cb["given"][which]
        if curve is not None:
            return _curve_derivs(curve, t, order)
        lin = np.zeros((t.size, order + 1))
        lin[:, 0] = t
        if order >= 1:
            lin[:, 1] = 1.0
        H = _power_derivs(t, order) @ _HERMITE.T                       # (n, k, 4)
        if which < 2:
            j = which
            e0, e1 = cb["eT"][0, j], cb["eT"][1, j]
            f0, f1 = cb["fixT"][0, j], cb["fixT"][1, j]
        else:
            i = which - 2
            e0, e1 = cb["eE"][i, 0], cb["eE"][i, 1]
            f0, f1 = cb["fixE"][i, 0], cb["fixE"][i, 1]
        one = np.zeros_like(lin)
        one[:, 0] = 1.0
        return (B1 - B0 + (one - lin)[..., None] * e0 + lin[..., None] * e1
                + H[..., 2, None] * f0 + H[..., 3, None] * f1)

    def _derivs(self, u, v, order):
        C0 = _curve_derivs(self._c0, u, order)
        C1 = _curve_derivs(self._c1, u, order)
        D0 = _curve_derivs(self._d0, v, order)
        D1 = _curve_derivs(self._d1, v, order)
        out = np.zeros((u.size, order + 1, order + 1, self._dim))
        if self._blend == "cubic":
            Hu = _power_derivs(u, order) @ _HERMITE.T                  # (n, k, 4)
            Hv = _power_derivs(v, order) @ _HERMITE.T
            R = np.stack([C0, C1, self._cross(0, u, order, C0, C1),
                          self._cross(1, u, order, C0, C1)], axis=2)   # (n, k, 4, dim)
            S = np.stack([D0, D1, self._cross(2, v, order, D0, D1),
                          self._cross(3, v, order, D0, D1)], axis=2)
            out += np.einsum("nlb,nkbd->nkld", Hv, R)
            out += np.einsum("nka,nlad->nkld", Hu, S)
            out -= np.einsum("nka,abd,nlb->nkld", Hu, self._M, Hv)
            return out
        fu, gu = _blend(self._blend, u, order)
        fv, gv = _blend(self._blend, v, order)
        c = self._corners
        for k in range(order + 1):
            for l in range(order + 1):
                val = (C0[:, k] * fv[:, l, None] + C1[:, k] * gv[:, l, None]
                       + D0[:, l] * fu[:, k, None] + D1[:, l] * gu[:, k, None])
                val -= ((fu[:, k] * fv[:, l])[:, None] * c["p00"]
                        + (fu[:, k] * gv[:, l])[:, None] * c["p01"]
                        + (gu[:, k] * fv[:, l])[:, None] * c["p10"]
                        + (gu[:, k] * gv[:, l])[:, None] * c["p11"])
                out[:, k, l] = val
        return out

    def _eval(self, u, v):
        return self._derivs(u, v, 0)[:, 0, 0]


class RuledSurface(Surface):
    """Ruled (linearly lofted) surface ``S(u, v) = (1 - v) C0(u) + v C1(u)``.

    Parameters
    ----------
    c0, c1 : curve or callable
        The two rails, each reparametrized onto ``u in [0, 1]``.

    Examples
    --------
    >>> from parametric.curves import BSpline
    >>> s = RuledSurface(BSpline([[0, 0, 0], [2, 0, 0]], 1), BSpline([[0, 1, 1], [2, 1, 1]], 1))
    >>> s(0.5, 0.5)
    array([1. , 0.5, 0.5])
    """

    def __init__(self, c0, c1):
        self._c0 = _as_curve(c0, "c0")
        self._c1 = _as_curve(c1, "c1")
        d0 = _curve_derivs(self._c0, np.array([0.0]), 0).shape[-1]
        d1 = _curve_derivs(self._c1, np.array([0.0]), 0).shape[-1]
        if d0 != d1:
            raise ValueError(f"c0 and c1 must share one dimension, got {d0} and {d1}")
        self._dim = d0

    def _derivs(self, u, v, order):
        A = _curve_derivs(self._c0, u, order)
        B = _curve_derivs(self._c1, u, order)
        out = np.zeros((u.size, order + 1, order + 1, self._dim))
        out[:, :, 0] = (1.0 - v)[:, None, None] * A + v[:, None, None] * B
        if order >= 1:
            out[:, :, 1] = B - A
        return out

    def _eval(self, u, v):
        return self._derivs(u, v, 0)[:, 0, 0]


# --------------------------------------------------------------------------- bicubic

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
        if t.size != 4 or np.any(t < 0) or np.any(t > 1) or np.unique(t).size != 4:
            raise ValueError(f"{name} must be 4 distinct values in [0, 1], got {x!r}")
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
