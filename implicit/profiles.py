"""2D profiles: small immutable signed distance fields in the plane.

A `Profile` maps points ``(..., 2)`` to signed distances ``(...)`` (negative
inside) and knows its bounds; profiles combine with ``| & -`` and `offset`,
and are swept into solids by `implicit.sweeps.extrude` and
`implicit.sweeps.revolve`.  `circle`, `rectangle` and `polygon` (any simple
polygon, either orientation) are exact; the booleans and offsets are bounds.

References
----------
I. Quilez, "2D distance functions" (polygon, box).
"""

from __future__ import annotations

import numpy as np

from .solid import _fmt, as_finite, as_positive, as_vector, load_all_kinds

__all__ = [
    "Profile",
    "Circle",
    "Rectangle",
    "Polygon",
    "ProfileUnion",
    "ProfileIntersection",
    "ProfileDifference",
    "ProfileOffset",
    "circle",
    "rectangle",
    "polygon",
    "polygon_distance",
    "as_polygon",
    "as_profile",
    "MAX_POLYGON_VERTICES",
]

#: Points per block in the (points x edges) polygon distance.
_BLOCK = 2048
#: Polygons with at least this many edges are measured by the compiled loop (`polygon_kernel`).
POLYGON_KERNEL_EDGES = 48

#: Most vertices of a polygon profile (its validation checks all edge pairs).
MAX_POLYGON_VERTICES = 20000

#: Nesting limit of a profile read from a dict.
MAX_PROFILE_DEPTH = 100


# ---------------------------------------------------------------------------
# 2D distances
# ---------------------------------------------------------------------------

def polygon_distance(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Exact signed distance from 2D points to a simple polygon.

    Parameters
    ----------
    points : (n, 2) float ndarray
    vertices : (m, 2) float ndarray
        The polygon, either orientation, not repeating the first vertex.

    Returns
    -------
    (n,) float64 ndarray
        Negative inside (even-odd rule), zero on the edges.

    Notes
    -----
    Distances to all ``m`` edges at once (an ``(n, m)`` array), the sign from
    the crossing parity of a ray in +x (Quilez's ``sdPolygon``, vectorized).
    Polygons of many edges (a gear's outline) go through a compiled loop over
    the same arithmetic instead (`POLYGON_KERNEL_EDGES`): no ``(n, m)``
    temporaries, about twenty times faster at 200 edges.

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    >>> polygon_distance(np.array([[0.5, 0.5], [2.0, 0.5]]), sq).tolist()
    [-0.5, 1.0]
    """
    if len(vertices) >= POLYGON_KERNEL_EDGES and len(points) >= 64:
        out = np.empty(len(points))
        from .polygon_kernel import polygon_kernel

        polygon_kernel()(np.ascontiguousarray(points[:, 0], dtype=np.float64),
                          np.ascontiguousarray(points[:, 1], dtype=np.float64),
                          np.ascontiguousarray(vertices[:, 0], dtype=np.float64),
                          np.ascontiguousarray(vertices[:, 1], dtype=np.float64), out)
        return out
    v0 = vertices
    v1 = np.roll(vertices, -1, axis=0)
    e = v1 - v0                                     # (m, 2)
    wx = points[:, None, 0] - v0[None, :, 0]        # (n, m)
    wy = points[:, None, 1] - v0[None, :, 1]
    ee = np.einsum("ij,ij->i", e, e)
    t = np.clip((wx * e[:, 0] + wy * e[:, 1]) / ee, 0.0, 1.0)
    bx = wx - t * e[:, 0]
    by = wy - t * e[:, 1]
    d2 = (bx * bx + by * by).min(axis=1)
    py = points[:, None, 1]
    c1 = py >= v0[None, :, 1]
    c2 = py < v1[None, :, 1]
    c3 = e[:, 0] * wy > e[:, 1] * wx
    flips = (c1 & c2 & c3) | (~c1 & ~c2 & ~c3)
    inside = np.count_nonzero(flips, axis=1) % 2 == 1
    d = np.sqrt(d2)
    return np.where(inside, -d, d)


def _segments_cross(vertices: np.ndarray) -> bool:
    """True when two non-adjacent edges of the closed polygon intersect.

    Sort and sweep: edges sorted by their lowest x; only pairs whose x
    ranges overlap are tested (a handful per edge for ordinary outlines),
    in batches of pairs so that memory stays bounded.
    """
    m = len(vertices)
    a = vertices
    b = np.roll(vertices, -1, axis=0)
    lo = np.minimum(a, b)
    hi = np.maximum(a, b)
    order = np.argsort(lo[:, 0], kind="stable")
    lo_sorted = lo[order, 0]
    # Edge order[k] can only meet edges order[k+1 : end[k]].
    end = np.searchsorted(lo_sorted, hi[order, 0], side="right")
    counts = np.maximum(end - np.arange(m) - 1, 0)

    def orient(p, q, r):
        return np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])
                       - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))

    def on_segment(p, q, r, o):  # r on segment pq, given collinear
        return (o == 0) & (np.minimum(p[:, 0], q[:, 0]) <= r[:, 0]) & (r[:, 0] <= np.maximum(p[:, 0], q[:, 0])) \
            & (np.minimum(p[:, 1], q[:, 1]) <= r[:, 1]) & (r[:, 1] <= np.maximum(p[:, 1], q[:, 1]))

    budget = 2_000_000
    start = 0
    cum = np.concatenate([[0], np.cumsum(counts)])
    while start < m:
        stop = int(np.searchsorted(cum, cum[start] + budget, side="right")) - 1
        stop = min(max(stop, start + 1), m)
        ks = np.arange(start, stop)
        c = counts[ks]
        total = int(c.sum())
        start = stop
        if total == 0:
            continue
        k_rep = np.repeat(ks, c)
        offset = np.arange(total) - np.repeat(np.cumsum(c) - c, c)
        i, j = order[k_rep], order[k_rep + 1 + offset]
        near = (np.abs(i - j) > 1) & (np.abs(i - j) != m - 1)
        near &= (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])
        i, j = i[near], j[near]
        if i.size == 0:
            continue
        p1, p2, q1, q2 = a[i], b[i], a[j], b[j]
        o1, o2 = orient(p1, p2, q1), orient(p1, p2, q2)
        o3, o4 = orient(q1, q2, p1), orient(q1, q2, p2)
        proper = (o1 * o2 < 0) & (o3 * o4 < 0)
        touch = on_segment(p1, p2, q1, o1) | on_segment(p1, p2, q2, o2) | on_segment(q1, q2, p1, o3) \
            | on_segment(q1, q2, p2, o4)
        if np.any(proper | touch):
            return True
    return False


def as_polygon(vertices, name: str = "vertices") -> np.ndarray:
    """Validate a simple 2D polygon: ``(m, 2)`` finite, ``m >= 3``, nonzero
    area, no repeated vertices, no crossing edges."""
    if isinstance(vertices, (str, bytes)) or vertices is None:
        raise TypeError(f"{name}: expected an (m, 2) array of numbers, got {vertices!r}")
    try:
        v = np.asarray(vertices, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected an (m, 2) array of numbers") from exc
    if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
        raise ValueError(f"{name}: expected an (m, 2) array with m >= 3, got shape {v.shape}")
    if v.shape[0] > MAX_POLYGON_VERTICES:
        raise ValueError(f"{name}: expected at most {MAX_POLYGON_VERTICES} vertices, got {v.shape[0]}")
    if not np.isfinite(v).all():
        raise ValueError(f"{name}: expected finite numbers")
    if np.allclose(v[0], v[-1], rtol=0, atol=0) and len(v) > 3:
        v = v[:-1]
    step = np.linalg.norm(np.roll(v, -1, axis=0) - v, axis=1)
    if np.any(step == 0):
        raise ValueError(f"{name}: expected distinct consecutive vertices (vertex {int(np.argmin(step))} repeats)")
    area = 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
    scale = np.ptp(v, axis=0).max()
    if abs(area) <= 1e-12 * scale * scale:
        raise ValueError(f"{name}: the polygon has zero area")
    if _segments_cross(v):
        raise ValueError(f"{name}: expected a simple polygon, but its edges cross")
    return v


# ---------------------------------------------------------------------------
# profiles
# ---------------------------------------------------------------------------

class Profile:
    """An immutable 2D region given by a signed distance field.

    Evaluate with ``profile(points)``: `points` ``(..., 2)`` -> ``(...)``,
    negative inside.  `bounds` is ``(lo, hi)`` of shape (2,) each; `exact`
    says whether the field is an exact distance or a conservative bound.

    Examples
    --------
    >>> from implicit.sweeps import circle, rectangle
    >>> ring = circle(1.0) - circle(0.5)
    >>> float(ring([[0.75, 0.0]])[0])
    -0.25
    """

    kind = "profile"
    __slots__ = ("_children", "_params", "_bounds", "_exact")
    registry: dict = {}

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        kind = cls.__dict__.get("kind")
        if kind is not None:
            Profile.registry[kind] = cls

    def __init__(self, children, params, bounds, exact):
        for i, c in enumerate(children):
            if not isinstance(c, Profile):
                raise TypeError(f"{self.kind}: operand {i} must be a Profile, got {type(c).__name__}")
        lo, hi = (np.array(b, dtype=np.float64).reshape(2) for b in bounds)
        lo.flags.writeable = False
        hi.flags.writeable = False
        object.__setattr__(self, "_children", tuple(children))
        object.__setattr__(self, "_params", dict(params))
        object.__setattr__(self, "_bounds", (lo, hi))
        object.__setattr__(self, "_exact", bool(exact))

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is immutable; operations return new profiles")

    def __bool__(self):
        raise TypeError("the truth value of a Profile is ambiguous; evaluate it on points instead")

    def __eq__(self, other):
        raise TypeError("Profiles are not compared with ==; compare their dicts")

    __hash__ = object.__hash__

    @property
    def children(self) -> tuple:
        return self._children

    @property
    def params(self) -> dict:
        return dict(self._params)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Conservative bounds ``(lo, hi)`` (2,) of the region."""
        return self._bounds

    @property
    def exact(self) -> bool:
        return self._exact

    def __call__(self, points) -> np.ndarray:
        """Signed distances at `points` ``(..., 2)``, shape ``(...)``."""
        try:
            arr = np.asarray(points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError("points: expected an array of shape (..., 2) of numbers") from exc
        if arr.ndim == 0 or arr.shape[-1] != 2:
            raise ValueError(f"points: expected an array of shape (..., 2), got shape {arr.shape}")
        if np.isnan(arr).any():
            raise ValueError("points: expected numbers, got NaN")
        flat = np.ascontiguousarray(arr.reshape(-1, 2))
        return np.asarray(self._evaluate(flat), dtype=np.float64).reshape(arr.shape[:-1])

    def _evaluate(self, p):  # pragma: no cover - abstract
        raise NotImplementedError

    def __or__(self, other):
        return ProfileUnion(self, other)

    def __and__(self, other):
        return ProfileIntersection(self, other)

    def __sub__(self, other):
        return ProfileDifference(self, other)

    @staticmethod
    def _need(children, name):
        for i, c in enumerate(children):
            if not isinstance(c, Profile):
                raise TypeError(f"{name}: operand {i} must be a Profile, got {type(c).__name__}")

    def symmetric(self) -> bool:
        """True when the region is its own mirror image in the line u = 0."""
        return False

    def meridian(self) -> "Profile | None":
        """The section of the solid of revolution in the (r, z) plane: this
        region joined with its mirror image in r = 0, or None when it cannot
        be built exactly.

        A profile in ``r >= 0`` that meets the axis only at points, or a
        symmetric one, is its own meridian (its distance at ``r >= 0`` is the
        distance to the joined region).  A rectangle or polygon with an edge
        on the axis is joined with its mirror image, so that the axis is not
        taken for a boundary.
        """
        lo, hi = self._bounds
        if self.symmetric() or lo[0] > 0.0:
            return self
        return None

    def offset(self, distance) -> "Profile":
        """The region grown by `distance` (shrunk when negative)."""
        return ProfileOffset(self, distance)

    # -- plain-data form --------------------------------------------------------
    def to_dict(self) -> dict:
        """``{"kind": ..., <params>, "children": [...]}`` of plain values."""
        out = {"kind": self.kind}
        out.update(self._params)
        if self._children:
            out["children"] = [c.to_dict() for c in self._children]
        return out

    @staticmethod
    def from_dict(data, path: str = "profile", _depth: int = 0) -> "Profile":
        """Rebuild a profile from `to_dict` output; errors name the location."""
        if _depth > MAX_PROFILE_DEPTH:
            raise ValueError(f"{path}: profile nested deeper than {MAX_PROFILE_DEPTH}")
        if not isinstance(data, dict):
            raise TypeError(f"{path}: expected a profile object, got {type(data).__name__}")
        kind = data.get("kind")
        cls = Profile.registry.get(kind) if isinstance(kind, str) else None
        if cls is None and isinstance(kind, str):
            load_all_kinds()  # the kinds `import implicit` left for later (curve profiles)
            cls = Profile.registry.get(kind)
        if cls is None:
            raise ValueError(f"{path}.kind: unknown profile kind {kind!r}; known: {', '.join(sorted(Profile.registry))}")
        params = {k: v for k, v in data.items() if k not in ("kind", "children")}
        raw_children = data.get("children", [])
        if not isinstance(raw_children, list):
            raise TypeError(f"{path}.children: expected a list, got {type(raw_children).__name__}")
        children = [Profile.from_dict(c, f"{path}.children[{i}]", _depth + 1) for i, c in enumerate(raw_children)]
        try:
            return cls(*children, **params)
        except (TypeError, ValueError) as exc:
            msg = str(exc)
            key = msg.split(":", 1)[0]
            raise type(exc)(f"{path}.{msg}" if key in params else f"{path}: {msg}") from None

    def __repr__(self) -> str:
        inner = [repr(c) for c in self._children] + [f"{k}={_fmt(v)}" for k, v in self._params.items()]
        return f"{self.kind}({', '.join(inner)})"


def _as_center2(center) -> np.ndarray:
    return as_vector(center, "center", size=2)


class Circle(Profile):
    """Disc of `radius` about `center` (exact)."""

    kind = "circle"
    __slots__ = ()

    def __init__(self, radius=1.0, center=(0.0, 0.0)):
        r = as_positive(radius, "radius")
        c = _as_center2(center)
        super().__init__((), {"radius": r, "center": c.tolist()}, (c - r, c + r), True)

    def _evaluate(self, p):
        c = np.asarray(self._params["center"])
        return np.hypot(p[:, 0] - c[0], p[:, 1] - c[1]) - self._params["radius"]

    def symmetric(self) -> bool:
        return self._params["center"][0] == 0.0

    def meridian(self):
        # A disc in r >= 0 meets the axis at one point at most.
        return self if self.symmetric() or self._bounds[0][0] >= 0.0 else None


class Rectangle(Profile):
    """Axis-aligned rectangle of full side lengths `size` about `center` (exact)."""

    kind = "rectangle"
    __slots__ = ()

    def __init__(self, size=(1.0, 1.0), center=(0.0, 0.0)):
        if np.ndim(size) == 0:
            size = [as_positive(size, "size")] * 2
        s = as_vector(size, "size", size=2)
        if np.any(s <= 0):
            raise ValueError(f"size: expected positive side lengths, got {s.tolist()}")
        c = _as_center2(center)
        super().__init__((), {"size": s.tolist(), "center": c.tolist()}, (c - s / 2, c + s / 2), True)

    def _evaluate(self, p):
        c = np.asarray(self._params["center"])
        h = np.asarray(self._params["size"]) / 2
        q = np.abs(p - c) - h
        out = np.hypot(np.maximum(q[:, 0], 0), np.maximum(q[:, 1], 0))
        return out + np.minimum(np.maximum(q[:, 0], q[:, 1]), 0.0)

    def symmetric(self) -> bool:
        return self._params["center"][0] == 0.0

    def meridian(self):
        lo, hi = self._bounds
        if self.symmetric() or lo[0] > 0.0:
            return self
        if lo[0] == 0.0:
            return Rectangle((2.0 * hi[0], self._params["size"][1]), (0.0, self._params["center"][1]))
        return None


class Polygon(Profile):
    """A simple polygon (any orientation, convex or not), exact distance."""

    kind = "polygon"
    __slots__ = ("_v",)

    def __init__(self, vertices):
        v = as_polygon(vertices, "vertices")
        super().__init__((), {"vertices": v.tolist()}, (v.min(axis=0), v.max(axis=0)), True)
        object.__setattr__(self, "_v", v)

    def _evaluate(self, p):
        if len(p) <= _BLOCK:
            return polygon_distance(p, self._v)
        # Blocks of points keep the (points x edges) temporaries in cache.
        return np.concatenate([polygon_distance(p[i:i + _BLOCK], self._v) for i in range(0, len(p), _BLOCK)])

    def symmetric(self) -> bool:
        v = self._v
        scale = max(1.0, float(np.abs(v).max()))
        a = v[np.lexsort((v[:, 1], v[:, 0]))]
        m = v * [-1.0, 1.0]
        b = m[np.lexsort((m[:, 1], m[:, 0]))]
        return bool(np.allclose(a, b, rtol=0, atol=1e-12 * scale))

    def meridian(self):
        v = self._v
        lo = v[:, 0].min()
        if self.symmetric() or lo > 0.0:
            return self
        if lo < 0.0:
            return None
        on_axis = v[:, 0] == 0.0
        edges = np.flatnonzero(on_axis & np.roll(on_axis, -1))     # edge i -> i+1 on the axis
        if edges.size == 0:
            return self                                            # touches at vertices only
        if edges.size > 1 or on_axis.sum() != 2:
            return None
        # Walk from the far end of the axis edge round to its near end, then back mirrored.
        path = np.roll(v, -(edges[0] + 1), axis=0)                 # path[0], path[-1] on the axis
        mirrored = path[-2:0:-1] * [-1.0, 1.0]
        return Polygon(np.vstack([path, mirrored]))


class _ProfileBoolean(Profile):
    """Shared behaviour of the profile booleans under revolution."""

    __slots__ = ()

    def symmetric(self) -> bool:
        return all(c.symmetric() for c in self._children)

    def meridian(self):
        # Joining with the mirror image distributes over these operations for
        # operands in r >= 0 (and symmetric operands are their own image).
        parts = [c.meridian() for c in self._children]
        if any(m is None for m in parts):
            return None
        if all(m is c for m, c in zip(parts, self._children)):
            return self
        return type(self)(*parts)


class ProfileUnion(_ProfileBoolean):
    """Union of profiles: ``min`` (a bound; exact outside)."""

    kind = "profile_union"
    __slots__ = ()

    def __init__(self, *children):
        if not children:
            raise ValueError("profile_union: expected at least one profile")
        Profile._need(children, "profile_union")
        super().__init__(children, {}, (np.min([c.bounds[0] for c in children], axis=0),
                                         np.max([c.bounds[1] for c in children], axis=0)), False)

    def _evaluate(self, p):
        return np.min([c._evaluate(p) for c in self._children], axis=0)


class ProfileIntersection(_ProfileBoolean):
    """Intersection of profiles: ``max`` (a bound)."""

    kind = "profile_intersection"
    __slots__ = ()

    def __init__(self, *children):
        if not children:
            raise ValueError("profile_intersection: expected at least one profile")
        Profile._need(children, "profile_intersection")
        super().__init__(children, {}, (np.max([c.bounds[0] for c in children], axis=0),
                                         np.min([c.bounds[1] for c in children], axis=0)), False)

    def _evaluate(self, p):
        return np.max([c._evaluate(p) for c in self._children], axis=0)


class ProfileDifference(_ProfileBoolean):
    """The first profile minus the others: ``max(a, -b, ...)`` (a bound)."""

    kind = "profile_difference"
    __slots__ = ()

    def __init__(self, base, *tools):
        if not tools:
            raise ValueError("profile_difference: expected a base profile and at least one to subtract")
        Profile._need((base,) + tools, "profile_difference")
        super().__init__((base,) + tools, {}, base.bounds, False)

    def _evaluate(self, p):
        out = self._children[0]._evaluate(p)
        for c in self._children[1:]:
            out = np.maximum(out, -c._evaluate(p))
        return out


class ProfileOffset(Profile):
    """A profile grown by `distance` (shrunk when negative): a bound."""

    kind = "profile_offset"
    __slots__ = ()

    def __init__(self, profile, distance):
        if not isinstance(profile, Profile):
            raise TypeError(f"profile_offset: profile must be a Profile, got {type(profile).__name__}")
        d = as_finite(distance, "distance")
        lo, hi = profile.bounds
        pad = max(d, 0.0)
        super().__init__((profile,), {"distance": d}, (lo - pad, hi + pad), profile.exact and d == 0)

    def _evaluate(self, p):
        return self._children[0]._evaluate(p) - self._params["distance"]

    def symmetric(self) -> bool:
        return self._children[0].symmetric()


def circle(radius=1.0, center=(0.0, 0.0)) -> Profile:
    """Disc profile.

    Examples
    --------
    >>> float(circle(1.0)([[2.0, 0.0]])[0])
    1.0
    """
    return Circle(radius, center)


def rectangle(size=(1.0, 1.0), center=(0.0, 0.0)) -> Profile:
    """Rectangle profile of full side lengths `size` (a number for a square).

    Examples
    --------
    >>> float(rectangle((2, 1))([[0.0, 1.5]])[0])
    1.0
    """
    return Rectangle(size, center)


def polygon(vertices) -> Profile:
    """Simple polygon profile, `vertices` ``(m, 2)`` in either orientation.

    Examples
    --------
    >>> tri = polygon([(0, 0), (1, 0), (0, 1)])
    >>> float(tri([[0.0, -1.0]])[0])
    1.0
    """
    return Polygon(vertices)


def as_profile(profile, name="profile") -> Profile:
    """`profile` itself, or the profile rebuilt from its dict form."""
    if isinstance(profile, Profile):
        return profile
    if isinstance(profile, dict):
        return Profile.from_dict(profile, name)
    raise TypeError(f"{name}: expected a Profile, got {type(profile).__name__}")
