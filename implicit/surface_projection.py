"""Parametric surfaces and volumes as plain data, closest points on surfaces,
generalized winding numbers.

Helpers of `implicit.parametric_solids`:

* `surface_to_dict` / `surface_from_dict`, `volume_to_dict` /
  `volume_from_dict`: tensor-product surfaces and trivariate volumes as JSON
  values, so that nodes holding them round-trip through `implicit.serialize`;
* `SurfaceProjector`: closest points on a surface for many points at once,
  after The NURBS Book, section 6.1 (a kd-tree of samples, built once, seeds
  vectorized Newton steps, projected onto the domain's edges);
* `winding_number`: the generalized winding number of points with respect to
  a triangle soup (Jacobson et al. 2013).

References
----------
L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997, section 6.1.
A. Jacobson, L. Kavan and O. Sorkine-Hornung, "Robust inside-outside
segmentation using generalized winding numbers", ACM Trans. Graph. 32(4),
2013, doi:10.1145/2461912.2461916.
"""

from __future__ import annotations

import numpy as np

from parametric.surfaces import BicubicPatch, Surface
from parametric.tensor import BezierSurface, BSplineSurface, NURBSSurface
from parametric.volumes import BezierVolume, BSplineVolume, NURBSVolume

__all__ = [
    "surface_to_dict", "surface_from_dict", "volume_to_dict", "volume_from_dict",
    "SurfaceProjector", "winding_number", "NEWTON_ITERATIONS",
]

#: Newton iterations of surface and volume point inversion.
NEWTON_ITERATIONS = 12
#: Seed samples per control point along each surface direction (clipped to
#: [MIN_SURFACE_SAMPLES, MAX_SURFACE_SAMPLES]).
SURFACE_SAMPLES_PER_CONTROL = 8
MIN_SURFACE_SAMPLES = 24
MAX_SURFACE_SAMPLES = 192
#: Tessellation of each patch for winding numbers and orientation.
WINDING_GRID = 48
#: Relative residual below which a volume inversion counts as converged.


# ---------------------------------------------------------------------------
# surfaces and volumes as plain data
# ---------------------------------------------------------------------------

def _from_typed_dict(data, name, what, builders):
    """``builders[data["type"]](data)``; an unknown type, a missing key or a
    refused value raise one ValueError naming `name` (the kinds listed in the
    order of `builders`)."""
    kind = data.get("type")
    # an unhashable tag is simply an unknown type, as with any other bad value
    build = builders.get(kind) if isinstance(kind, str) else None
    if build is not None:
        try:
            return build(data)
        except KeyError as exc:
            raise ValueError(f"{name}: missing key {exc.args[0]!r} for a {kind} {what}") from None
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{name}: {exc}") from None
    known = [repr(k) for k in builders]
    expected = known[0] if len(known) == 1 else ", ".join(known[:-1]) + " or " + known[-1]
    raise ValueError(f"{name}.type: expected {expected}, got {kind!r}")


def surface_to_dict(surface) -> dict:
    """A tensor-product surface as plain JSON values.

    Parameters
    ----------
    surface : BezierSurface, BSplineSurface, NURBSSurface or BicubicPatch
        A bicubic patch is stored as its Bezier control net.

    Returns
    -------
    dict
        ``{"type": "nurbs" | "bspline" | "bezier", "control_points": ...,
        "weights": ..., "degree_u", "degree_v", "knots_u", "knots_v"}``.

    Examples
    --------
    >>> from parametric.tensor import sphere
    >>> surface_to_dict(sphere(1.0))["type"]
    'nurbs'
    """
    if isinstance(surface, BicubicPatch):
        return {"type": "bezier", "control_points": np.asarray(surface.bezier_control_points()).tolist()}
    if isinstance(surface, BezierSurface):
        return {"type": "bezier", "control_points": np.asarray(surface.control_points).tolist()}
    if isinstance(surface, BSplineSurface):
        out = {"type": "nurbs" if isinstance(surface, NURBSSurface) else "bspline",
               "control_points": np.asarray(surface.control_points).tolist(),
               "degree_u": int(surface.degree_u), "degree_v": int(surface.degree_v),
               "knots_u": np.asarray(surface.knots_u).tolist(), "knots_v": np.asarray(surface.knots_v).tolist()}
        if isinstance(surface, NURBSSurface):
            out["weights"] = np.asarray(surface.weights).tolist()
        return out
    raise TypeError("surface: expected a BezierSurface, BSplineSurface, NURBSSurface or BicubicPatch, "
                    f"got {type(surface).__name__}")


_SURFACE_BUILDERS = {
    "nurbs": lambda d: NURBSSurface(d["control_points"], d["weights"], d["degree_u"], d["degree_v"],
                                    d["knots_u"], d["knots_v"]),
    "bspline": lambda d: BSplineSurface(d["control_points"], d["degree_u"], d["degree_v"],
                                        d["knots_u"], d["knots_v"]),
    "bezier": lambda d: BezierSurface(d["control_points"]),
}

_VOLUME_BUILDERS = {
    "nurbs": lambda d: NURBSVolume(d["control_points"], d["weights"], d["degrees"], d["knots"]),
    "bspline": lambda d: BSplineVolume(d["control_points"], d["degrees"], d["knots"]),
    "bezier": lambda d: BezierVolume(d["control_points"]),
}


def surface_from_dict(data, name: str = "surface") -> Surface:
    """Rebuild a surface from `surface_to_dict` output (a surface passes through)."""
    if isinstance(data, BicubicPatch):
        return BezierSurface(data.bezier_control_points())
    if isinstance(data, Surface):
        surface_to_dict(data)  # type check
        return data
    if not isinstance(data, dict):
        raise TypeError(f"{name}: expected a tensor-product surface or its dict, got {type(data).__name__}")
    return _from_typed_dict(data, name, "surface", _SURFACE_BUILDERS)


def volume_to_dict(volume) -> dict:
    """A B-spline / NURBS / Bezier volume as plain JSON values."""
    if not isinstance(volume, BSplineVolume):
        raise TypeError(f"volume: expected a BSplineVolume, NURBSVolume or BezierVolume, got {type(volume).__name__}")
    if isinstance(volume, BezierVolume):
        return {"type": "bezier", "control_points": np.asarray(volume.control_points).tolist()}
    out = {"type": "nurbs" if isinstance(volume, NURBSVolume) else "bspline",
           "control_points": np.asarray(volume.control_points).tolist(),
           "degrees": [int(d) for d in volume.degrees],
           "knots": [np.asarray(k).tolist() for k in volume.knots]}
    if isinstance(volume, NURBSVolume):
        out["weights"] = np.asarray(volume.weights).tolist()
    return out


def volume_from_dict(data, name: str = "volume") -> BSplineVolume:
    """Rebuild a volume from `volume_to_dict` output (a volume passes through)."""
    if isinstance(data, BSplineVolume):
        return data
    if not isinstance(data, dict):
        raise TypeError(f"{name}: expected a BSplineVolume or its dict, got {type(data).__name__}")
    return _from_typed_dict(data, name, "volume", _VOLUME_BUILDERS)


# ---------------------------------------------------------------------------
# closest points on a surface, with a cached seed tree
# ---------------------------------------------------------------------------

def _dot(a, b):
    return np.einsum("nd,nd->n", a, b)


class SurfaceProjector:
    """Closest points on a surface for many query points.

    Parameters
    ----------
    surface : Surface
    samples : (2,) int, optional
        Seed grid (default 8 samples per control point each way, 24 to 192).

    Examples
    --------
    >>> from parametric.tensor import sphere
    >>> uv, x, d = SurfaceProjector(sphere(1.0)).project(np.array([[0.0, 0.0, 3.0]]))
    >>> round(float(d[0]), 9)
    2.0
    """

    def __init__(self, surface: Surface, samples=None):
        if samples is None:
            ctrl = np.asarray(getattr(surface, "control_points", np.zeros((4, 4, 3))))
            samples = tuple(int(np.clip(SURFACE_SAMPLES_PER_CONTROL * n, MIN_SURFACE_SAMPLES,
                                        MAX_SURFACE_SAMPLES)) for n in ctrl.shape[:2])
        (au, bu), (av, bv) = surface.domain_u, surface.domain_v
        self.surface = surface
        self.dom = (float(au), float(bu), float(av), float(bv))
        # seeds on a regular grid that includes the domain's edges, except an
        # edge collapsed to a point (a pole): its samples all coincide, so the
        # seed's other parameter would be arbitrary there
        nu, nv = int(samples[0]), int(samples[1])
        su, sv = np.linspace(au, bu, nu), np.linspace(av, bv, nv)
        grid = surface.grid(su, sv)
        size = float(np.max(grid.reshape(-1, 3).max(axis=0) - grid.reshape(-1, 3).min(axis=0)))
        tol = 1e-9 * max(size, 1e-300)
        keep_u = np.ones(nu, bool)
        keep_v = np.ones(nv, bool)
        for idx in (0, -1):
            keep_u[idx] = np.ptp(grid[idx], axis=0).max() > tol
            keep_v[idx] = np.ptp(grid[:, idx], axis=0).max() > tol
        #: Closed directions (the edges u = a, u = b coincide): parameters wrap there.
        self.closed_u = bool(np.max(np.linalg.norm(grid[0] - grid[-1], axis=-1)) <= tol)
        self.closed_v = bool(np.max(np.linalg.norm(grid[:, 0] - grid[:, -1], axis=-1)) <= tol)
        self.su, self.sv = su[keep_u], sv[keep_v]
        self.points = np.ascontiguousarray(grid[keep_u][:, keep_v].reshape(-1, 3))
        from scipy.spatial import cKDTree  # local: scipy.spatial costs 0.25 s to import

        self.tree = cKDTree(self.points)

    def _edge_steps(self, ua, va, du, dv, cu, cv, f, g, a11, a12, a22):
        """Steps of the points whose Newton step leaves the domain: the crossing
        parameter stops on its edge and the other takes the quadratic model's
        best step with it fixed; when both cross, the better of the two."""
        au, bu, av, bv = self.dom
        tu = self._clip_step(ua, du, au, bu, self.closed_u)
        tv = self._clip_step(va, dv, av, bv, self.closed_v)
        a11p, a22p = np.maximum(a11, 1e-300), np.maximum(a22, 1e-300)
        a_u, a_v = tu, self._clip_step(va, -(g + a12 * tu) / a22p, av, bv, self.closed_v)
        b_v, b_u = tv, self._clip_step(ua, -(f + a12 * tv) / a11p, au, bu, self.closed_u)

        def model(x, y):
            return f * x + g * y + 0.5 * (a11 * x * x + 2 * a12 * x * y + a22 * y * y)

        take_a = cu & (~cv | (model(a_u, a_v) <= model(b_u, b_v)))
        return np.where(take_a, a_u, b_u), np.where(take_a, a_v, b_v)

    @staticmethod
    def _clip_step(x, dx, a, b, closed):
        return dx if closed else np.clip(x + dx, a, b) - x

    def _move(self, u, v):
        au, bu, av, bv = self.dom
        u = au + np.mod(u - au, bu - au) if self.closed_u else np.clip(u, au, bu)
        v = av + np.mod(v - av, bv - av) if self.closed_v else np.clip(v, av, bv)
        return u, v

    def project(self, P: np.ndarray, iterations: int = NEWTON_ITERATIONS, tol: float = 1e-12):
        """``(uv (n, 2), closest (n, 3), distance (n,))`` for points (n, 3)."""
        S = self.surface
        au, bu, av, bv = self.dom
        d_seed, idx = self.tree.query(P)
        nv = self.sv.size
        u, v = self.su[idx // nv], self.sv[idx % nv]
        dk = d_seed ** 2
        active = np.arange(P.shape[0])
        for _ in range(int(iterations)):
            if active.size == 0:
                break
            ua, va, Pa = u[active], v[active], P[active]
            D = S.derivatives(ua, va, 2)
            r = D[:, 0, 0] - Pa
            Su, Sv = D[:, 1, 0], D[:, 0, 1]
            f, g = _dot(Su, r), _dot(Sv, r)
            a11 = _dot(Su, Su) + _dot(D[:, 2, 0], r)
            a12 = _dot(Su, Sv) + _dot(D[:, 1, 1], r)
            a22 = _dot(Sv, Sv) + _dot(D[:, 0, 2], r)
            det = a11 * a22 - a12 * a12
            bad = (det <= 0) | (a11 <= 0)
            if np.any(bad):  # damped Gauss-Newton where the Hessian is not positive
                suu, svv = _dot(Su, Su), _dot(Sv, Sv)
                lam = 1e-9 * (suu + svv) + 1e-300
                a11 = np.where(bad, suu + lam, a11)
                a12 = np.where(bad, _dot(Su, Sv), a12)
                a22 = np.where(bad, svv + lam, a22)
                det = a11 * a22 - a12 * a12
            det = np.where(np.abs(det) > 1e-300, det, 1e-300)
            du = -(a22 * f - a12 * g) / det
            dv = -(a11 * g - a12 * f) / det
            # projected Newton: a step that would cross a domain edge stops on
            # it, and the other parameter takes the quadratic model's best step
            # with the first one fixed
            cu = np.zeros(du.shape, bool) if self.closed_u else (ua + du < au) | (ua + du > bu)
            cv = np.zeros(dv.shape, bool) if self.closed_v else (va + dv < av) | (va + dv > bv)
            k = np.flatnonzero(cu | cv)
            if k.size:
                du[k], dv[k] = self._edge_steps(ua[k], va[k], du[k], dv[k], cu[k], cv[k],
                                                f[k], g[k], a11[k], a12[k], a22[k])
            du = np.clip(du, -0.25 * (bu - au), 0.25 * (bu - au))
            dv = np.clip(dv, -0.25 * (bv - av), 0.25 * (bv - av))
            nu_, nv_ = self._move(ua + du, va + dv)
            rn = S(nu_, nv_) - Pa
            dn = _dot(rn, rn)
            worse = np.flatnonzero(dn > dk[active])
            for factor in (0.5, 0.125):  # shorter steps where the full one overshoots
                if worse.size == 0:
                    break
                hu, hv = self._move(ua[worse] + factor * du[worse], va[worse] + factor * dv[worse])
                rh = S(hu, hv) - Pa[worse]
                dh = _dot(rh, rh)
                ok = dh < dk[active][worse]
                nu_[worse] = np.where(ok, hu, ua[worse])
                nv_[worse] = np.where(ok, hv, va[worse])
                dn[worse] = np.where(ok, dh, dk[active][worse])
                worse = worse[~ok]
            mu, mv = np.abs(nu_ - ua) / (bu - au), np.abs(nv_ - va) / (bv - av)
            if self.closed_u:
                mu = np.minimum(mu, 1.0 - mu)
            if self.closed_v:
                mv = np.minimum(mv, 1.0 - mv)
            moved = np.maximum(mu, mv)
            u[active], v[active], dk[active] = nu_, nv_, dn
            active = active[moved > tol]
        closest = S(u, v)
        return np.stack([u, v], axis=1), closest, np.linalg.norm(closest - P, axis=1)

    def normals(self, uv: np.ndarray, pull: float = 1e-7) -> np.ndarray:
        """Unnormalized normals ``Su x Sv`` at parameters pulled off the domain's
        edges by `pull` (relative), so collapsed edges (poles) still get a
        direction."""
        au, bu, av, bv = self.dom
        u = np.clip(uv[:, 0], au + pull * (bu - au), bu - pull * (bu - au))
        v = np.clip(uv[:, 1], av + pull * (bv - av), bv - pull * (bv - av))
        D = self.surface.derivatives(u, v, 1)
        return np.cross(D[:, 1, 0], D[:, 0, 1])


def _control_box(surface, samples):
    ctrl = getattr(surface, "control_points", None)
    if ctrl is not None:
        C = np.asarray(ctrl).reshape(-1, 3)
        return C.min(axis=0), C.max(axis=0)
    lo, hi = samples.min(axis=0), samples.max(axis=0)
    pad = 0.05 * float(np.max(hi - lo))
    return lo - pad, hi + pad


def _tessellation(surfaces, n=WINDING_GRID):
    """Triangles (t, 3, 3) of all patches: 6 rows per control point, at most `n`."""
    tris = []
    for s in surfaces:
        ctrl = np.asarray(getattr(s, "control_points", np.zeros((n, n, 3))))
        nu, nv = (int(np.clip(6 * (k - 1), 2, n)) for k in ctrl.shape[:2])
        pts, tri = s.tessellate(nu, nv)
        tris.append(pts[tri])
    return np.concatenate(tris)


def winding_number(points, triangles, *, chunk: int = 2_000_000) -> np.ndarray:
    """Generalized winding number of points with respect to triangles.

    Parameters
    ----------
    points : (n, 3) float
    triangles : (t, 3, 3) float
        Triangle corners, counter-clockwise about the outward normal.
    chunk : int
        Point-triangle pairs evaluated at once.

    Returns
    -------
    (n,) float
        About 1 inside a closed outward surface, 0 outside (Van Oosterom and
        Strackee's solid angle, summed over the triangles, over 4 pi).

    Examples
    --------
    >>> tet = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> faces = tet[[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]]
    >>> np.round(winding_number(np.array([[0.1, 0.1, 0.1], [2.0, 2.0, 2.0]]), faces), 9)
    array([1., 0.])
    """
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    T = np.asarray(triangles, dtype=float)
    out = np.empty(P.shape[0])
    step = max(1, int(chunk) // max(T.shape[0], 1))
    for s in range(0, P.shape[0], step):
        q = P[s:s + step, None, None, :]
        a, b, c = (T[None, :, k, :] - q[:, :, 0, :] for k in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("ntd,ntd->nt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ntd,ntd->nt", a, b) * lc + np.einsum("ntd,ntd->nt", b, c) * la
               + np.einsum("ntd,ntd->nt", c, a) * lb)
        out[s:s + step] = np.arctan2(det, den).sum(axis=1) / (2.0 * np.pi)
    return out


def _signed_volume(triangles) -> float:
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    return float(np.einsum("nd,nd->n", a, np.cross(b, c)).sum() / 6.0)


