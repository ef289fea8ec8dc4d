"""Coons patches (bilinear and bicubically blended) and ruled surfaces between two curves."""

from __future__ import annotations

import numpy as np

from .curves import Curve, FunctionCurve, _HERMITE, _power_derivs

from .surface_base import CORNER_TOL, Surface, _check_domain_pair  # noqa: F401

__all__ = ["CoonsPatch", "RuledSurface"]


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
