"""The base of biparametric surfaces: `Surface` (evaluation, derivatives, normals, tessellation).

A surface maps ``(u, v)`` in its rectangular domain to points: ``surface(u, v)``
takes equal-shape (or broadcastable) arrays and returns ``(..., 3)``.
"""

from __future__ import annotations

import numpy as np

from .basis import KNOT_TOL
from .curve_base import fd_stencil
from .curves import FunctionCurve, _check_order

__all__ = ["Surface", "CORNER_TOL", "SEAM_TOL"]

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
