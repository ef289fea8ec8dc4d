"""Primitive solids: half-spaces and signed-distance primitives.

Each factory validates its arguments and returns an immutable `Solid` whose
field is an exact signed distance unless its docstring says "bound".  Sizes
are full lengths (``box(size=(2, 1, 1))`` is 2 long in x).

References
----------
I. Quilez, "Distance functions" (exact SDFs of box, capped cone, torus).
"""

from __future__ import annotations

import numpy as np

from .solid import Solid, as_finite, as_positive, as_vector, unit

__all__ = [
    "HalfSpace",
    "Sphere",
    "Box",
    "Cylinder",
    "Cone",
    "Torus",
    "Ellipsoid",
    "Capsule",
    "halfspace",
    "sphere",
    "box",
    "rounded_box",
    "cylinder",
    "cone",
    "frustum",
    "torus",
    "ellipsoid",
    "capsule",
    "frame_from_axis",
]


def frame_from_axis(axis) -> np.ndarray:
    """Orthonormal frame (3, 3) whose rows are (e1, e2, axis/|axis|).

    Local coordinates of a point are ``frame @ (p - centre)``; the third is
    the coordinate along the axis.
    """
    w = unit(as_vector(axis, "axis", nonzero=True))
    helper = np.array([1.0, 0.0, 0.0]) if abs(w[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(w, helper)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    return np.array([u, v, w])


class _Primitive(Solid):
    """A leaf of the tree, exact unless stated otherwise."""

    __slots__ = ()
    #: Leaves take no operands (checked when a tree is read from JSON).
    takes_children = False

    def __init__(self, params, bounds, *, exact=True, lipschitz=1.0):
        super().__init__((), params, bounds, exact=exact, lipschitz=lipschitz)


def _axial_bounds(centre, axis, radius, z0, z1):
    """Bounds of a solid of revolution: discs of `radius` at axial positions z0..z1."""
    w = axis / np.linalg.norm(axis)
    # Half-extent of a disc of radius r and normal w along coordinate i: r * sqrt(1 - w_i^2).
    disc = radius * np.sqrt(np.clip(1.0 - w * w, 0.0, 1.0))
    ends = np.array([centre + z0 * w, centre + z1 * w])
    return ends.min(axis=0) - disc, ends.max(axis=0) + disc


class HalfSpace(_Primitive):
    """Points with ``dot(p - point, normal) <= 0`` (normal points out)."""

    kind = "halfspace"
    __slots__ = ("_n", "_d")

    def __init__(self, normal, point=(0.0, 0.0, 0.0)):
        n = unit(as_vector(normal, "normal", nonzero=True))
        q = as_vector(point, "point")
        lo = np.full(3, -np.inf)
        hi = np.full(3, np.inf)
        # An axis-aligned half-space is bounded on one side.
        axis = np.flatnonzero(np.abs(n) == 1.0)
        if axis.size == 1:
            i = axis[0]
            if n[i] > 0:
                hi[i] = q[i]
            else:
                lo[i] = q[i]
        super().__init__({"normal": n.tolist(), "point": q.tolist()}, (lo, hi))
        object.__setattr__(self, "_n", n)
        object.__setattr__(self, "_d", float(n @ q))

    def _evaluate(self, p):
        return p @ self._n - self._d


class Sphere(_Primitive):
    """Ball of `radius` about `center`."""

    kind = "sphere"
    __slots__ = ("_c", "_r")

    def __init__(self, radius=1.0, center=(0.0, 0.0, 0.0)):
        r = as_positive(radius, "radius")
        c = as_vector(center, "center")
        super().__init__({"radius": r, "center": c.tolist()}, (c - r, c + r))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_r", r)

    def _evaluate(self, p):
        d = p - self._c
        return np.sqrt(np.einsum("ij,ij->i", d, d)) - self._r


class Box(_Primitive):
    """Axis-aligned box of full edge lengths `size`, corners rounded by `radius`."""

    kind = "box"
    __slots__ = ("_c", "_h", "_rr")

    def __init__(self, size=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.0), radius=0.0):
        s = as_vector(size, "size")
        if np.any(s <= 0):
            raise ValueError(f"size: expected positive edge lengths, got {s.tolist()}")
        c = as_vector(center, "center")
        rr = as_positive(radius, "radius", allow_zero=True)
        if rr > 0.5 * s.min():
            raise ValueError(f"radius: expected at most half the smallest edge ({0.5 * s.min():g}), got {rr:g}")
        params = {"size": s.tolist(), "center": c.tolist()}
        if rr:
            params["radius"] = rr
        super().__init__(params, (c - s / 2, c + s / 2))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_h", s / 2 - rr)
        object.__setattr__(self, "_rr", rr)

    def _evaluate(self, p):
        q = np.abs(p - self._c) - self._h
        outside = np.sqrt(np.einsum("ij,ij->i", np.maximum(q, 0), np.maximum(q, 0)))
        inside = np.minimum(q.max(axis=1), 0.0)
        return outside + inside - self._rr


class Cylinder(_Primitive):
    """Capped cylinder of `radius` and `height`, centred on `center`, along `axis`."""

    kind = "cylinder"
    __slots__ = ("_c", "_frame", "_r", "_hh")

    def __init__(self, radius, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)):
        r = as_positive(radius, "radius")
        h = as_positive(height, "height")
        c = as_vector(center, "center")
        frame = frame_from_axis(axis)
        a = frame[2]
        super().__init__({"radius": r, "height": h, "center": c.tolist(), "axis": a.tolist()},
                         _axial_bounds(c, a, r, -h / 2, h / 2))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_frame", frame)
        object.__setattr__(self, "_r", r)
        object.__setattr__(self, "_hh", h / 2)

    def _evaluate(self, p):
        q = (p - self._c) @ self._frame.T
        dr = np.hypot(q[:, 0], q[:, 1]) - self._r
        dz = np.abs(q[:, 2]) - self._hh
        outside = np.hypot(np.maximum(dr, 0), np.maximum(dz, 0))
        return outside + np.minimum(np.maximum(dr, dz), 0.0)


def capped_cone_parts(qx, qy, hh, r1, r2):
    """Quilez's exact capped cone in its (radial, axial) plane: the vectors to the nearest
    points of the cap (``ca``) and of the slanted side (``cb``), and the sign (-1 inside).

    ``qx`` is the distance from the axis, ``qy`` the axial coordinate minus ``hh``; the
    distance is ``sign * sqrt(min(|ca|^2, |cb|^2))``.
    """
    k2x, k2y = r2 - r1, 2.0 * hh
    cax = qx - np.minimum(qx, np.where(qy < 0.0, r1, r2))
    cay = np.abs(qy) - hh
    t = np.clip(((r2 - qx) * k2x + (hh - qy) * k2y) / (k2x * k2x + k2y * k2y), 0.0, 1.0)
    cbx = qx - r2 + k2x * t
    cby = qy - hh + k2y * t
    sign = np.where((cbx < 0.0) & (cay < 0.0), -1.0, 1.0)
    return cax, cay, cbx, cby, sign


class Cone(_Primitive):
    """Cone frustum: disc of `radius` at `center`, disc of `top_radius` at
    `center + height * axis` (``top_radius=0`` is a pointed cone)."""

    kind = "cone"
    __slots__ = ("_c", "_frame", "_r1", "_r2", "_hh")

    def __init__(self, radius, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), top_radius=0.0):
        r1 = as_positive(radius, "radius")
        h = as_positive(height, "height")
        r2 = as_positive(top_radius, "top_radius", allow_zero=True)
        c = as_vector(center, "center")
        frame = frame_from_axis(axis)
        a = frame[2]
        params = {"radius": r1, "height": h, "center": c.tolist(), "axis": a.tolist()}
        if r2:
            params["top_radius"] = r2
        super().__init__(params, _axial_bounds(c, a, max(r1, r2), 0.0, h))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_frame", frame)
        object.__setattr__(self, "_r1", r1)
        object.__setattr__(self, "_r2", r2)
        object.__setattr__(self, "_hh", h / 2)

    def _evaluate(self, p):
        # Quilez's exact capped cone, in the local frame with the axis from -hh to +hh.
        loc = (p - self._c) @ self._frame.T
        qx = np.hypot(loc[:, 0], loc[:, 1])
        cax, cay, cbx, cby, sign = capped_cone_parts(qx, loc[:, 2] - self._hh, self._hh, self._r1, self._r2)
        return sign * np.sqrt(np.minimum(cax * cax + cay * cay, cbx * cbx + cby * cby))


class Torus(_Primitive):
    """Torus about `axis` through `center`: tube of `minor_radius` around a
    circle of `major_radius`."""

    kind = "torus"
    __slots__ = ("_c", "_frame", "_R", "_r")

    def __init__(self, major_radius, minor_radius, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)):
        big = as_positive(major_radius, "major_radius")
        small = as_positive(minor_radius, "minor_radius")
        if small >= big:
            raise ValueError(f"minor_radius: expected less than major_radius ({big:g}), got {small:g}")
        c = as_vector(center, "center")
        frame = frame_from_axis(axis)
        a = frame[2]
        super().__init__({"major_radius": big, "minor_radius": small, "center": c.tolist(), "axis": a.tolist()},
                         _axial_bounds(c, a, big + small, -small, small))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_frame", frame)
        object.__setattr__(self, "_R", big)
        object.__setattr__(self, "_r", small)

    def _evaluate(self, p):
        q = (p - self._c) @ self._frame.T
        return np.hypot(np.hypot(q[:, 0], q[:, 1]) - self._R, q[:, 2]) - self._r


class Ellipsoid(_Primitive):
    """Axis-aligned ellipsoid of semi-axes `radii` about `center` (a bound).

    The field ``(|(p - c) / r| - 1) * min(r)`` is a conservative 1-Lipschitz
    bound, not an exact distance: its gradient is
    ``min(r) * (q / r^2) / |q / r|`` with ``q = p - c``, whose norm is at most
    ``min(r) * (1 / min(r)) * |q / r| / |q / r| = 1``; a 1-Lipschitz field that
    vanishes on the boundary and has the right sign never exceeds the
    distance to the boundary in magnitude.  It is exact on a sphere.
    (Quilez's ``k0 * (k0 - 1) / k1`` is closer to the distance but not a bound:
    it overestimates near the ends of the long axes.)
    """

    kind = "ellipsoid"
    __slots__ = ("_c", "_r", "_rmin")

    def __init__(self, radii=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.0)):
        r = as_vector(radii, "radii")
        if np.any(r <= 0):
            raise ValueError(f"radii: expected positive semi-axes, got {r.tolist()}")
        c = as_vector(center, "center")
        super().__init__({"radii": r.tolist(), "center": c.tolist()}, (c - r, c + r),
                         exact=bool(np.all(r == r[0])))
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_r", r)
        object.__setattr__(self, "_rmin", float(r.min()))

    @property
    def bound_slack_factor(self) -> float:
        """``max(r) / min(r)``: a field value t puts a point within
        ``t * max(r) / min(r)`` of the bounds."""
        return float(self._r.max() / self._rmin)

    def _evaluate(self, p):
        q = (p - self._c) / self._r
        return (np.sqrt(np.einsum("ij,ij->i", q, q)) - 1.0) * self._rmin


class Capsule(_Primitive):
    """All points within `radius` of the segment from `a` to `b` (exact)."""

    kind = "capsule"
    __slots__ = ("_a", "_ab", "_ab2", "_r")

    def __init__(self, a=(0.0, 0.0, 0.0), b=(0.0, 0.0, 1.0), radius=0.5):
        pa = as_vector(a, "a")
        pb = as_vector(b, "b")
        r = as_positive(radius, "radius")
        ab = pb - pa
        super().__init__({"a": pa.tolist(), "b": pb.tolist(), "radius": r},
                         (np.minimum(pa, pb) - r, np.maximum(pa, pb) + r))
        object.__setattr__(self, "_a", pa)
        object.__setattr__(self, "_ab", ab)
        object.__setattr__(self, "_ab2", float(ab @ ab))
        object.__setattr__(self, "_r", r)

    def _evaluate(self, p):
        kernels = capsule_kernels()
        if kernels is not None and p.ndim == 2 and p.shape[1] == 3:
            out = np.empty(p.shape[0])
            kernels[0](np.ascontiguousarray(p, dtype=np.float64), self._a, self._ab, self._ab2, self._r, out)
            return out
        w = p - self._a
        if self._ab2 > 0.0:
            t = np.clip((w @ self._ab) / self._ab2, 0.0, 1.0)
            w = w - t[:, None] * self._ab
        return np.sqrt(np.einsum("ij,ij->i", w, w)) - self._r


_CAPSULE_KERNELS: list = []


def capsule_kernels():
    """The compiled ``(capsule_distance, capsule_gradient)`` of `implicit.primitive_kernels`, or None
    without numba (then numpy evaluates capsules).  Every capsule evaluation takes the same path in a
    process, whatever ran before: numpy and the loop may round differently."""
    if not _CAPSULE_KERNELS:
        try:
            from .primitive_kernels import capsule_distance, capsule_gradient
        except ImportError:
            _CAPSULE_KERNELS.append(None)
        else:
            _CAPSULE_KERNELS.append((capsule_distance, capsule_gradient))
    return _CAPSULE_KERNELS[0]


def ellipsoid(radii=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.0)) -> Solid:
    """Axis-aligned ellipsoid with semi-axes `radii` (a conservative bound).

    Parameters
    ----------
    radii : (3,) array_like or float
        Semi-axes along x, y, z (a number for a sphere).
    center : (3,) array_like

    Examples
    --------
    >>> from implicit import ellipsoid
    >>> float(ellipsoid((2, 1, 1))([[4.0, 0, 0]])[0])
    1.0
    """
    if np.ndim(radii) == 0:
        radii = [as_positive(radii, "radii")] * 3
    return Ellipsoid(radii, center)


def capsule(a=(0.0, 0.0, 0.0), b=(0.0, 0.0, 1.0), radius=0.5) -> Solid:
    """Capsule: points within `radius` of the segment ``a``-``b`` (exact).

    Examples
    --------
    >>> from implicit import capsule
    >>> float(capsule((0, 0, 0), (0, 0, 2), 0.5)([[0, 0, 3.0]])[0])
    0.5
    """
    return Capsule(a, b, radius)


def halfspace(normal, point=(0.0, 0.0, 0.0)) -> Solid:
    """Half-space ``dot(p - point, normal) <= 0``; `normal` points outward.

    Examples
    --------
    >>> from implicit import halfspace
    >>> float(halfspace((0, 0, 1))([[0, 0, 2.0]])[0])
    2.0
    """
    return HalfSpace(normal, point)


def sphere(radius=1.0, center=(0.0, 0.0, 0.0)) -> Solid:
    """Ball of `radius` about `center`.

    Examples
    --------
    >>> from implicit import sphere
    >>> float(sphere(2.0)([[3.0, 0, 0]])[0])
    1.0
    """
    return Sphere(radius, center)


def box(size=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.0)) -> Solid:
    """Axis-aligned box; `size` is the full edge lengths (a number for a cube).

    Examples
    --------
    >>> from implicit import box
    >>> float(box((2, 2, 2))([[0, 0, 3.0]])[0])
    2.0
    """
    if np.ndim(size) == 0:
        size = [as_positive(size, "size")] * 3
    return Box(size, center)


def rounded_box(size=(1.0, 1.0, 1.0), radius=0.1, center=(0.0, 0.0, 0.0)) -> Solid:
    """Box with edges and corners rounded by `radius` (exact distance)."""
    if np.ndim(size) == 0:
        size = [as_positive(size, "size")] * 3
    return Box(size, center, radius=radius)


def cylinder(radius=1.0, height=1.0, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Capped cylinder centred on `center`, its axis along `axis`.

    Examples
    --------
    >>> from implicit import cylinder
    >>> float(cylinder(1.0, 2.0)([[0, 0, 1.5]])[0])
    0.5
    """
    return Cylinder(radius, height, center, axis)


def cone(radius=1.0, height=1.0, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Cone: base disc of `radius` at `center`, apex at `center + height * axis`.

    Examples
    --------
    >>> from implicit import cone
    >>> float(cone(1.0, 1.0)([[0, 0, 2.0]])[0])
    1.0
    """
    return Cone(radius, height, center, axis)


def frustum(radius, top_radius, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Truncated cone: disc of `radius` at `center`, of `top_radius` at the top."""
    as_positive(top_radius, "top_radius")
    return Cone(radius, height, center, axis, top_radius=top_radius)


def torus(major_radius=1.0, minor_radius=0.25, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Torus: a tube of `minor_radius` around a circle of `major_radius`.

    Examples
    --------
    >>> from implicit import torus
    >>> float(torus(1.0, 0.25)([[1.0, 0, 0]])[0])
    -0.25
    """
    return Torus(major_radius, minor_radius, center, axis)
