"""Sweep representation: 2D profiles swept into solids by extrusion and revolution.

Profiles (`implicit.profiles`, re-exported here) are small immutable 2D
signed distance fields; `extrude` sweeps one along a straight line,
`revolve` turns one about an axis.

The local frame of a sweep is the rotation that takes +z onto `axis` by the
smallest angle (the identity for the default axis +z): profile coordinates
``(u, v)`` are the local x and y of an extrusion, and ``(r, z)`` (distance
from the axis, height along it) of a revolution.

References
----------
I. Quilez, "2D distance functions" (polygon, box), and "Extrusion and
revolution of 2D SDFs".
"""

from __future__ import annotations

import numbers

import numpy as np

from .profiles import (  # noqa: F401  (re-exported: profiles live beside their sweeps)
    MAX_POLYGON_VERTICES, Circle, Polygon, Profile, ProfileDifference, ProfileIntersection, ProfileOffset,
    ProfileUnion, Rectangle, as_polygon, as_profile, circle, polygon, polygon_distance, rectangle,
)
from .solid import Solid, _fmt, as_finite, as_positive, as_vector, unit

__all__ = [
    "Profile",
    "Circle",
    "Rectangle",
    "Polygon",
    "ProfileUnion",
    "ProfileIntersection",
    "ProfileDifference",
    "ProfileOffset",
    "Extrude",
    "Revolve",
    "circle",
    "rectangle",
    "polygon",
    "extrude",
    "revolve",
    "polygon_distance",
    "rotation_to_axis",
]

def rotation_to_axis(axis) -> np.ndarray:
    """Rotation matrix (3, 3) taking +z onto `axis` by the smallest angle.

    Local coordinates of a point are ``(p - centre) @ R``; for ``axis = -z``
    the rotation is a half turn about x.
    """
    w = unit(as_vector(axis, "axis", nonzero=True))
    c = w[2]
    if c < -1.0 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    k = np.array([-w[1], w[0], 0.0])  # z x w
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + kx + kx @ kx / (1.0 + c)


# ---------------------------------------------------------------------------
# sweeps
# ---------------------------------------------------------------------------

class Extrude(Solid):
    """A profile extruded along `axis`, `height` long, centred on `center`.

    The field combines the 2D distance ``d`` and the slab ``|z| - h/2`` as
    ``|max((d, |z| - h/2), 0)| + min(max(d, |z| - h/2), 0)``: exact when the
    profile's field is exact.
    """

    kind = "extrude"
    takes_children = False
    __slots__ = ("_profile", "_rot", "_c", "_hh")

    def __init__(self, profile, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)):
        prof = as_profile(profile)
        h = as_positive(height, "height")
        c = as_vector(center, "center")
        rot = rotation_to_axis(axis)
        lo2, hi2 = prof.bounds
        a = unit(as_vector(axis, "axis"))
        if np.any(lo2 > hi2):
            bounds = (np.full(3, np.inf), np.full(3, -np.inf))
        else:
            local = np.array([[x, y, z] for x in (lo2[0], hi2[0]) for y in (lo2[1], hi2[1]) for z in (-h / 2, h / 2)])
            world = local @ rot.T + c
            bounds = (world.min(axis=0), world.max(axis=0))
        super().__init__((), {"profile": prof.to_dict(), "height": h, "center": c.tolist(), "axis": a.tolist()},
                         bounds, exact=prof.exact)
        object.__setattr__(self, "_profile", prof)
        object.__setattr__(self, "_rot", rot)
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_hh", h / 2)

    @property
    def profile(self) -> Profile:
        return self._profile

    def _label(self) -> str:
        return (f"extrude({self._profile!r}, height={self._hh * 2:g}, center={_fmt(self._c.tolist())}, "
                f"axis={_fmt(self._rot[:, 2].round(12).tolist())})")

    __repr__ = _label

    def _evaluate(self, p):
        q = (p - self._c) @ self._rot
        d = self._profile._evaluate(np.ascontiguousarray(q[:, :2]))
        dz = np.abs(q[:, 2]) - self._hh
        outside = np.hypot(np.maximum(d, 0.0), np.maximum(dz, 0.0))
        return outside + np.minimum(np.maximum(d, dz), 0.0)


class Revolve(Solid):
    """A profile in the ``(r, z)`` half-plane turned about `axis` through `center`.

    The profile lies in ``r >= 0`` or is symmetric about ``r = 0`` (a disc
    centred on the axis makes a ball).  The field of a full turn is the
    profile's distance in the point's own meridian half-plane, evaluated on
    the *meridian* (the profile joined with its mirror image, see
    `Profile.meridian`, so that an edge lying on the axis is not a
    boundary): exact for an exact meridian, since the nearest boundary point
    lies in that half-plane.  When no exact meridian can be built (a boolean
    of other profiles with an edge on the axis) the plain profile is used
    and the node is marked a bound.

    A partial turn of `angle` degrees, starting at local +x and running
    counter-clockwise about the axis, is exact outside the solid for a
    profile in ``r >= 0`` (the nearest point lies on the lateral surface at
    the point's own angle or on one of the two planar end faces) and a
    bound inside (``max`` of the meridian distance and the angular sector's
    half-planes).
    """

    kind = "revolve"
    takes_children = False
    __slots__ = ("_profile", "_meridian", "_rot", "_c", "_alpha", "_half")

    def __init__(self, profile, angle=360.0, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)):
        prof = as_profile(profile)
        ang = as_finite(angle, "angle")
        if not 0.0 < ang <= 360.0:
            raise ValueError(f"angle: expected degrees in (0, 360], got {angle!r}")
        c = as_vector(center, "center")
        rot = rotation_to_axis(axis)
        lo2, hi2 = prof.bounds
        half = bool(lo2[0] >= 0.0)
        if not half and not prof.symmetric():
            raise ValueError(f"profile: expected a profile in the half-plane r >= 0 or symmetric about r = 0, "
                             f"its bounds reach r = {lo2[0]:g}")
        meridian = prof.meridian()
        exact_meridian = meridian is not None
        if meridian is None:
            meridian = prof
        rmax = max(hi2[0], -lo2[0])
        local = np.array([[x, y, z] for x in (-rmax, rmax) for y in (-rmax, rmax) for z in (lo2[1], hi2[1])])
        world = local @ rot.T + c
        super().__init__((), {"profile": prof.to_dict(), "angle": ang, "center": c.tolist(),
                              "axis": unit(as_vector(axis, "axis")).tolist()},
                         (world.min(axis=0), world.max(axis=0)),
                         exact=prof.exact and meridian.exact and exact_meridian and ang == 360.0)
        object.__setattr__(self, "_profile", prof)
        object.__setattr__(self, "_meridian", meridian)
        object.__setattr__(self, "_rot", rot)
        object.__setattr__(self, "_c", c)
        object.__setattr__(self, "_alpha", np.radians(ang))
        object.__setattr__(self, "_half", half)

    @property
    def profile(self) -> Profile:
        return self._profile

    def _label(self) -> str:
        return (f"revolve({self._profile!r}, angle={np.degrees(self._alpha):g}, center={_fmt(self._c.tolist())}, "
                f"axis={_fmt(self._rot[:, 2].round(12).tolist())})")

    __repr__ = _label

    def _cap(self, u, z, h):
        """Distance to an end face: the profile's part in r >= 0, in its plane."""
        d = self._profile._evaluate(np.stack([u, z], axis=1))
        if not self._half:
            d = np.maximum(d, -u)      # a bound where the face is cut at the axis
        return np.hypot(np.maximum(d, 0.0), h)

    def _evaluate(self, p):
        q = (p - self._c) @ self._rot
        x, y, z = q[:, 0], q[:, 1], q[:, 2]
        r = np.hypot(x, y)
        d = self._meridian._evaluate(np.stack([r, z], axis=1))
        alpha = self._alpha
        if alpha >= 2.0 * np.pi:
            return d
        phi = np.mod(np.arctan2(y, x), 2.0 * np.pi)
        in_range = (phi <= alpha) | (r == 0.0)
        # Signed distances to the two end planes, positive away from the sector.
        ca, sa = np.cos(alpha), np.sin(alpha)
        a = -y                        # plane at angle 0, outward normal (0, -1)
        b = -sa * x + ca * y          # plane at angle alpha, outward normal (-sin a, cos a)
        sector = np.maximum(a, b) if alpha <= np.pi else np.minimum(a, b)
        inside_value = np.where(d >= 0.0, d, np.maximum(d, sector))
        # Outside the angular range: distance to the nearer planar end face.
        u = ca * x + sa * y
        return np.where(in_range, inside_value, np.minimum(self._cap(x, z, y), self._cap(u, z, b)))


def extrude(profile: Profile, height: float, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Extrude `profile` by `height` along `axis`, centred on `center`.

    Parameters
    ----------
    profile : Profile
        Region in the local (x, y) plane (see the module notes on the frame).
    height : float
        Full length along the axis.
    center : (3,) array_like
    axis : (3,) array_like

    Examples
    --------
    >>> from implicit.sweeps import extrude, rectangle
    >>> bar = extrude(rectangle((2, 1)), 4.0)
    >>> float(bar([[0.0, 0.0, 3.0]])[0])
    1.0
    """
    return Extrude(profile, height, center, axis)


def revolve(profile: Profile, angle_degrees: float = 360.0, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Revolve `profile` (in the ``(r, z)`` half-plane, ``r >= 0``) about `axis`.

    Parameters
    ----------
    profile : Profile
    angle_degrees : float
        Sweep angle in (0, 360]; a partial sweep starts at local +x.
    center : (3,) array_like
        A point of the axis, origin of ``z``.
    axis : (3,) array_like

    Examples
    --------
    >>> from implicit.sweeps import revolve, circle
    >>> ring = revolve(circle(0.25, center=(1.0, 0.0)))     # a torus
    >>> float(ring([[1.0, 0.0, 0.0]])[0])
    -0.25
    """
    if isinstance(angle_degrees, bool) or not isinstance(angle_degrees, (numbers.Real, np.floating)):
        raise TypeError(f"angle_degrees: expected a number, got {angle_degrees!r}")
    return Revolve(profile, angle_degrees, center, axis)
