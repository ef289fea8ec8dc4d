"""Solids from parametric curves: closed curve profiles, revolution, extrusion, sweeps.

`CurveProfile` turns a closed planar curve of `parametric` (Bezier, B-spline,
NURBS, Hermite) into a 2D `Profile` whose field is the distance to the curve:
each point is seeded with the nearest of a dense set of curve samples (a
kd-tree built once) and refined by vectorized Newton steps on
``C'(u) . (C(u) - p) = 0`` (The NURBS Book, section 6.1); the sign comes from
the side of the tangent at the closest point, and from the even-odd rule on
the dense polyline where that is ambiguous (a corner of the curve).  The
result is an exact distance up to the Newton tolerance, and never larger than
the distance to the nearest sample.

`revolve_curve` and `extrude_curve` hand such a profile to the `revolve` and
`extrude` nodes of `implicit.sweeps`, so they are exact where those are, and
`sweep` moves a profile along a 3D path curve with a rotation-minimizing frame.

Curves are stored in a node's parameters as plain JSON values
(`curve_to_dict`), so the nodes round-trip through `implicit.serialize`.

References
----------
L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997, section 6.1.
W. Wang, B. Juettler, D. Zheng and Y. Liu, "Computation of rotation minimizing
frames", ACM Trans. Graph. 27(1), 2008, doi:10.1145/1330511.1330513.
"""

from __future__ import annotations

import numbers

import numpy as np

from parametric.curves import BSpline, Curve

from .solid import Solid
from .curve_data import (MIN_SAMPLES, SAMPLES_PER_CONTROL, _as_samples, _hull_box,  # noqa: F401
                         curve_from_dict, curve_to_dict)
from .sweeps import Extrude, Profile, Revolve

__all__ = [
    "CurveProfile",
    "Sweep",
    "curve_profile",
    "revolve_curve",
    "extrude_curve",
    "sweep",
    "curve_to_dict",
    "curve_from_dict",
    "rotation_minimizing_frames",
    "CurveProjector",
]

#: Relative gap |C(a) - C(b)| / size below which a curve counts as closed.
CLOSED_TOL = 1e-9
#: Newton iterations of the closest-point refinement.
NEWTON_ITERATIONS = 8


# ---------------------------------------------------------------------------
# closest points
# ---------------------------------------------------------------------------

class CurveProjector:
    """Closest points on a curve for many query points, with a cached seed tree.

    Parameters
    ----------
    curve : Curve
    samples : int
        Seeds at uniformly spaced parameters.
    closed : bool
        Wrap parameters around the domain (a closed curve).

    Notes
    -----
    The distance returned is ``min(|C(u*) - p|, |C(u_seed) - p|)`` for the
    Newton result ``u*``, so it never exceeds the distance to the nearest
    sample; a wrong local minimum can only happen when the true closest point
    is farther than half a sample spacing from the nearest sample's point.
    """

    def __init__(self, curve: Curve, samples: int, closed: bool):
        a, b = curve.domain
        self.curve = curve
        self.closed = bool(closed)
        self.a, self.b = float(a), float(b)
        ts = np.linspace(a, b, int(samples) + 1)
        if isinstance(curve, BSpline):  # sample every knot: corners are seeds themselves
            ts = np.union1d(ts, np.clip(np.asarray(curve.knots, dtype=float), a, b))
        self.ts = ts[:-1] if closed else ts
        self.points = curve(self.ts)
        from scipy.spatial import cKDTree  # local: scipy.spatial costs 0.25 s to import

        self.tree = cKDTree(self.points)
        self.dt = (self.b - self.a) / int(samples)

    def _wrap(self, u):
        if self.closed:
            return self.a + np.mod(u - self.a, self.b - self.a)
        return np.clip(u, self.a, self.b)

    def project(self, P: np.ndarray):
        """``(u, closest, distance)`` for ``(n, dim)`` points."""
        d_seed, idx = self.tree.query(P)
        C = self.points[idx].copy()
        d = d_seed.copy()
        # Start between the nearest sample and its nearer neighbour: the
        # minimizer lies on that side, and a seed on a corner (a knot of a
        # C0 curve) then does not stall on the wrong segment.
        m = len(self.ts)
        if self.closed:
            lo_i, hi_i = (idx - 1) % m, (idx + 1) % m
        else:
            lo_i, hi_i = np.maximum(idx - 1, 0), np.minimum(idx + 1, m - 1)
        d_lo = np.linalg.norm(self.points[lo_i] - P, axis=1)
        d_hi = np.linalg.norm(self.points[hi_i] - P, axis=1)
        t_lo, t_hi = self.ts[lo_i], self.ts[hi_i]
        if self.closed:
            span = self.b - self.a
            t_lo = np.where(t_lo > self.ts[idx], t_lo - span, t_lo)
            t_hi = np.where(t_hi < self.ts[idx], t_hi + span, t_hi)
        u = self._wrap(0.5 * (self.ts[idx] + np.where(d_lo < d_hi, t_lo, t_hi)))
        u_seed = self.ts[idx]
        dk = np.linalg.norm(self.curve(u) - P, axis=1)
        active = np.arange(P.shape[0])
        tol = 1e-13 * (self.b - self.a)
        for _ in range(NEWTON_ITERATIONS):
            if active.size == 0:
                break
            ua, Pa = u[active], P[active]
            D = self.curve.derivatives(ua, 2)
            r = D[:, 0] - Pa
            f = np.einsum("nd,nd->n", D[:, 1], r)
            g2 = np.einsum("nd,nd->n", D[:, 1], D[:, 1])
            fp = g2 + np.einsum("nd,nd->n", D[:, 2], r)
            fp = np.where(fp > 1e-12 * np.maximum(g2, 1e-300), fp, np.maximum(g2, 1e-300))
            step = np.clip(-f / fp, -2.0 * self.dt, 2.0 * self.dt)
            un = self._wrap(ua + step)
            dn = np.linalg.norm(self.curve(un) - Pa, axis=1)
            worse = dn > dk[active]
            if np.any(worse):  # one halving, else stay
                step[worse] *= 0.5
                uh = self._wrap(ua[worse] + step[worse])
                dh = np.linalg.norm(self.curve(uh) - Pa[worse], axis=1)
                ok = dh <= dk[active][worse]
                un[worse] = np.where(ok, uh, ua[worse])
                dn[worse] = np.where(ok, dh, dk[active][worse])
                step[worse] = np.where(ok, step[worse], 0.0)
            u[active], dk[active] = un, dn
            active = active[np.abs(step) > tol]
        use_seed = d < dk
        u = np.where(use_seed, u_seed, u)
        C = np.where(use_seed[:, None], C, self.curve(u))
        d = np.minimum(d, dk)
        return u, C, d


# ---------------------------------------------------------------------------
# closed planar curve as a profile
# ---------------------------------------------------------------------------

def _check_closed(curve, name):
    a, b = curve.domain
    ends = curve(np.array([a, b], dtype=float))
    pts = curve(np.linspace(a, b, 64))
    size = float(np.max(pts.max(axis=0) - pts.min(axis=0)))
    gap = float(np.linalg.norm(ends[1] - ends[0]))
    if not size > 0:
        raise ValueError(f"{name}: the curve is degenerate (a single point)")
    return gap <= CLOSED_TOL * max(size, 1.0)


def _even_odd(points, poly):
    """Inside mask of points (n, 2) in a closed polygon (k, 2) (compiled even-odd test)."""
    from skimage.measure import points_in_poly  # noqa: PLC0415

    return points_in_poly(points, poly)


class CurveProfile(Profile):
    """A 2D region bounded by a closed planar parametric curve.

    Parameters
    ----------
    curve : Curve or dict
        Closed 2D curve (``C(a) == C(b)``), either orientation, not
        self-intersecting.
    samples : int, optional
        Seeds of the closest-point search (default 64 per control point, at
        least 1024).

    The field is the signed distance to the curve (exact up to the Newton
    tolerance, see the module notes), so `exact` is True.

    Examples
    --------
    >>> from parametric.conics import circle as nurbs_circle
    >>> disc = CurveProfile(nurbs_circle(2.0, center=(0.0, 0.0)))
    >>> round(float(disc([[3.0, 0.0]])[0]), 12)
    1.0
    """

    kind = "curve_profile"
    __slots__ = ("_curve", "_proj", "_orient", "_poly")

    def __init__(self, curve, samples=None):
        c = curve_from_dict(curve)
        if c.dim != 2:
            raise ValueError(f"curve: expected a planar (2D) curve, got dimension {c.dim}")
        if not _check_closed(c, "curve"):
            raise ValueError("curve: expected a closed curve (C(a) == C(b))")
        n = _as_samples(samples, c)
        proj = CurveProjector(c, n, closed=True)
        poly = proj.points
        x, y = poly[:, 0], poly[:, 1]
        area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        lo, hi = _hull_box(c, poly)
        super().__init__((), {"curve": curve_to_dict(c), "samples": n}, (lo, hi), True)
        object.__setattr__(self, "_curve", c)
        object.__setattr__(self, "_proj", proj)
        object.__setattr__(self, "_orient", 1.0 if area > 0 else -1.0)
        object.__setattr__(self, "_poly", poly)

    @property
    def curve(self) -> Curve:
        """The boundary curve."""
        return self._curve

    def __repr__(self) -> str:
        return f"curve_profile({self._curve!r})"

    def _evaluate(self, p):
        u, C, d = self._proj.project(p)
        T = self._curve.derivative(u, 1)
        q = p - C
        cross = T[:, 0] * q[:, 1] - T[:, 1] * q[:, 0]
        tn = np.linalg.norm(T, axis=1)
        inside = cross * self._orient > 0
        ambiguous = np.abs(cross) < 0.5 * tn * d
        if np.any(ambiguous):
            inside[ambiguous] = _even_odd(p[ambiguous], self._poly)
        return np.where(inside, -d, d)


def curve_profile(curve, *, samples=None) -> CurveProfile:
    """The region bounded by a closed planar curve, as a `Profile`.

    Parameters
    ----------
    curve : Bezier, BSpline, NURBS or Hermite (2D, closed)
    samples : int, optional

    Returns
    -------
    CurveProfile

    Examples
    --------
    >>> from parametric.conics import ellipse
    >>> prof = curve_profile(ellipse(2.0, 1.0, center=(0.0, 0.0)))
    >>> round(float(prof([[0.0, 0.0]])[0]), 9)
    -1.0
    """
    return CurveProfile(curve, samples)


def _profile_of(profile, name="profile") -> Profile:
    if isinstance(profile, Profile):
        return profile
    if isinstance(profile, Curve):
        return CurveProfile(profile)
    if isinstance(profile, dict) and "kind" in profile:
        return Profile.from_dict(profile, name)
    raise TypeError(f"{name}: expected a closed 2D curve or a Profile, got {type(profile).__name__}")


def revolve_curve(profile_curve, axis=(0.0, 0.0, 1.0), angle_degrees=360.0, center=(0.0, 0.0, 0.0),
                  *, samples=None) -> Solid:
    """Revolve a closed curve of the ``(r, z)`` half-plane about `axis`.

    Parameters
    ----------
    profile_curve : Curve (2D, closed, ``r >= 0``)
        Coordinates ``(r, z)``: distance from the axis and height along it.
    axis : (3,) array_like
    angle_degrees : float
        Sweep in (0, 360]; a partial sweep starts at the local +x direction.
    center : (3,) array_like
        A point of the axis.
    samples : int, optional
        Seeds of the closest-point search on the curve.

    Returns
    -------
    Solid
        A `revolve` node of a `CurveProfile`: exact for a full turn (distance
        in the meridian plane to the curve), a bound inside a partial turn.

    Examples
    --------
    >>> from parametric.conics import circle as nurbs_circle
    >>> ring = revolve_curve(nurbs_circle(0.5, center=(2.0, 0.0)))   # a torus
    >>> round(float(ring([[2.0, 0.0, 0.0]])[0]), 9)
    -0.5
    """
    if isinstance(angle_degrees, bool) or not isinstance(angle_degrees, numbers.Real):
        raise TypeError(f"angle_degrees: expected a number, got {angle_degrees!r}")
    if isinstance(profile_curve, Curve):
        prof = CurveProfile(profile_curve, samples)
    else:
        prof = _profile_of(profile_curve, "profile_curve")
    return Revolve(prof, float(angle_degrees), center, axis)


def extrude_curve(closed_planar_curve, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
                  *, samples=None) -> Solid:
    """Extrude the region bounded by a closed planar curve along `axis`.

    Parameters
    ----------
    closed_planar_curve : Curve (2D, closed)
        In the local ``(x, y)`` plane of the extrusion (the frame taking +z
        onto `axis`, see `implicit.sweeps`).
    height : float
        Full length along the axis, centred on `center`.
    center, axis : (3,) array_like
    samples : int, optional

    Returns
    -------
    Solid
        An exact `extrude` node (2D curve distance combined with the slab).

    Examples
    --------
    >>> from parametric.conics import circle as nurbs_circle
    >>> rod = extrude_curve(nurbs_circle(1.0, center=(0.0, 0.0)), 2.0)
    >>> round(float(rod([[0.0, 0.0, 1.5]])[0]), 9)
    0.5
    """
    if isinstance(closed_planar_curve, Curve):
        prof = CurveProfile(closed_planar_curve, samples)
    else:
        prof = _profile_of(closed_planar_curve, "closed_planar_curve")
    return Extrude(prof, height, center, axis)


# ---------------------------------------------------------------------------
# sweep along a path curve
# ---------------------------------------------------------------------------

def rotation_minimizing_frames(points, tangents, r0=None, *, closed=False):
    """Rotation-minimizing frames along a sampled curve (double reflection).

    Parameters
    ----------
    points : (m, 3) float
        Curve samples in order.
    tangents : (m, 3) float
        Unit tangents at the samples.
    r0 : (3,) float, optional
        First reference vector (default: a unit vector normal to the first
        tangent).
    closed : bool
        Spread the closing twist linearly over arc length so that the last
        frame equals the first.

    Returns
    -------
    (m, 3) float
        Unit reference vectors ``r_i`` normal to ``t_i``; the frame is
        ``(r_i, t_i x r_i, t_i)``.

    Notes
    -----
    The recursion ``r_i -> r_{i+1}`` of Wang et al. (2008) is sequential by
    nature; it runs once per path sample when a sweep is built, never per
    query point.
    """
    X = np.asarray(points, dtype=float)
    T = np.asarray(tangents, dtype=float)
    m = X.shape[0]
    if r0 is None:
        helper = np.eye(3)[int(np.argmin(np.abs(T[0])))]
        r0 = np.cross(T[0], helper)
    r = np.asarray(r0, dtype=float) - np.dot(r0, T[0]) * T[0]
    r = r / np.linalg.norm(r)
    R = np.empty((m, 3))
    R[0] = r
    V1 = X[1:] - X[:-1]
    C1 = np.einsum("ij,ij->i", V1, V1)
    for i in range(m - 1):
        v1, c1 = V1[i], C1[i]
        if c1 <= 0.0:
            R[i + 1] = R[i]
            continue
        rl = R[i] - (2.0 / c1) * np.dot(v1, R[i]) * v1
        tl = T[i] - (2.0 / c1) * np.dot(v1, T[i]) * v1
        v2 = T[i + 1] - tl
        c2 = np.dot(v2, v2)
        R[i + 1] = rl if c2 <= 1e-300 else rl - (2.0 / c2) * np.dot(v2, rl) * v2
    if closed:
        s = np.concatenate([[0.0], np.cumsum(np.sqrt(C1))])
        t0 = T[0]
        rend = R[-1] - np.dot(R[-1], t0) * t0
        ang = np.arctan2(np.dot(np.cross(rend, R[0]), t0), np.dot(rend, R[0]))
        th = ang * s / s[-1]
        R = R * np.cos(th)[:, None] + np.cross(T, R) * np.sin(th)[:, None]
    R = R - np.einsum("ij,ij->i", R, T)[:, None] * T
    return R / np.linalg.norm(R, axis=1, keepdims=True)


class Sweep(Solid):
    """A 2D profile swept along a 3D path curve with a rotation-minimizing frame.

    At a point ``p`` the closest path point ``C(u)`` is found (kd-tree seed
    and Newton steps), the frame ``(r, b, t)`` at ``u`` is interpolated from
    the rotation-minimizing frames of the samples, and the profile's field
    is evaluated at ``((p - C) . r, (p - C) . b)``.  An open path gets flat
    end caps (the planes through ``C(a)``, ``C(b)`` normal to the path),
    combined with the profile as in an extrusion.

    The field is a bound, not an exact distance.  It is the exact distance
    for a disc profile centred on the path (a pipe), and for any exact
    profile along a straight path (an extrusion).  For a curved path it is
    conservative (``|f| <=`` the distance to the surface) where the profile
    stays inside the path's curvature radius (``max |profile point| <
    1 / kappa``) and the query point's closest path point is unique; near the
    focal set of a tightly curved path the field may overestimate.
    """

    kind = "sweep_curve"
    __slots__ = ("_profile", "_path", "_proj", "_R", "_closed", "_ends")

    def __init__(self, profile, path, samples=None):
        prof = _profile_of(profile)
        c = curve_from_dict(path, "path")
        if c.dim != 3:
            raise ValueError(f"path: expected a 3D curve, got dimension {c.dim}")
        n = _as_samples(samples, c)
        closed = _check_closed(c, "path")
        if closed:
            a, b = c.domain
            tan = c.tangent(np.array([a, b], dtype=float))
            closed = float(np.dot(tan[0], tan[1])) > 1.0 - 1e-9
        proj = CurveProjector(c, n, closed=closed)
        ts = proj.ts
        if closed:
            ts = np.append(ts, c.domain[1])
        X = c(ts)
        T = c.tangent(ts)
        R = rotation_minimizing_frames(X, T, closed=closed)
        lo2, hi2 = prof.bounds
        rad = float(np.max(np.abs(np.array([lo2, hi2]))) * np.sqrt(2.0))
        plo, phi = _hull_box(c, X)
        params = {"profile": prof.to_dict(), "path": curve_to_dict(c), "samples": n}
        super().__init__((), params, (plo - rad, phi + rad), exact=False)
        a, b = c.domain
        ends = (c(float(a)), c.tangent(float(a)), c(float(b)), c.tangent(float(b)))
        for name, value in (("_profile", prof), ("_path", c), ("_proj", proj), ("_R", (ts, R)),
                            ("_closed", closed), ("_ends", ends)):
            object.__setattr__(self, name, value)

    @classmethod
    def from_params(cls, children, params):
        return cls(**params)

    @property
    def profile(self) -> Profile:
        return self._profile

    @property
    def path(self) -> Curve:
        return self._path

    def _label(self) -> str:
        return f"sweep_curve({self._profile!r}, path={self._path!r})"

    def frames(self, u):
        """Frames at parameters `u` (n,): ``(r, b, t)`` each (n, 3)."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        ts, R = self._R
        T = self._path.tangent(u)
        k = np.clip(np.searchsorted(ts, u, side="right") - 1, 0, len(ts) - 2)
        f = ((u - ts[k]) / (ts[k + 1] - ts[k]))[:, None]
        r = (1.0 - f) * R[k] + f * R[k + 1]
        r = r - np.einsum("ij,ij->i", r, T)[:, None] * T
        r = r / np.linalg.norm(r, axis=1, keepdims=True)
        return r, np.cross(T, r), T

    def _evaluate(self, p):
        u, C, _ = self._proj.project(p)
        r, b, _ = self.frames(u)
        q = p - C
        d = self._profile._evaluate(np.stack([np.einsum("ij,ij->i", q, r), np.einsum("ij,ij->i", q, b)], axis=1))
        if self._closed:
            return d
        c0, t0, c1, t1 = self._ends
        dz = np.maximum((c0 - p) @ t0, (p - c1) @ t1)
        return np.hypot(np.maximum(d, 0.0), np.maximum(dz, 0.0)) + np.minimum(np.maximum(d, dz), 0.0)


def sweep(profile, path_curve, *, samples=None) -> Solid:
    """Sweep a 2D profile along a 3D path curve.

    Parameters
    ----------
    profile : Profile or closed 2D Curve
        Region in the normal plane, coordinates ``(x, y)`` along the frame's
        ``r`` and ``t x r`` (``r`` starts normal to the first tangent and is
        transported without twist).
    path_curve : Curve (3D)
        The spine.  A closed, tangent-continuous path gives a ring without caps.
    samples : int, optional
        Path samples for the closest-point seeds and the frames.

    Returns
    -------
    Sweep
        A conservative bound, see `Sweep` for where it holds.

    Examples
    --------
    >>> from parametric.conics import circle as nurbs_circle
    >>> from implicit.sweeps import circle
    >>> ring = sweep(circle(0.5), nurbs_circle(2.0))   # torus R = 2, r = 0.5
    >>> round(float(ring([[2.0, 0.0, 0.0]])[0]), 9)
    -0.5
    """
    return Sweep(profile, path_curve, samples)

