"""Polyhedral primitives: the half-space method and polygon-based solids.

`convex_polyhedron` is the seed's half-space method: a solid given as the
intersection of half-spaces ``dot(p - point_i, normal_i) <= 0``.  Its finite
bounds come from the vertices of the intersection (found with
``scipy.spatial.HalfspaceIntersection`` from a Chebyshev centre computed by
a linear program); an unbounded or empty intersection is an error.

The field is exact: inside a convex polyhedron the distance to the boundary
is the distance to the nearest face plane (``-max_i`` of the plane
distances), outside it is the distance to the nearest boundary triangle.
`pyramid` and `wedge` are convex polyhedra with their own parameters;
`prism` extrudes any simple polygon (see `implicit.sweeps`).

References
----------
C. Ericson, *Real-Time Collision Detection*, 2005, section 5.1.5 (closest
point on a triangle).
"""

from __future__ import annotations

import numpy as np

from .primitives import _Primitive
from .solid import Solid, as_positive, as_vector, unit
from .profiles import as_polygon, polygon
from .sweeps import extrude, rotation_to_axis

__all__ = [
    "ConvexPolyhedron",
    "Pyramid",
    "Wedge",
    "convex_polyhedron",
    "pyramid",
    "wedge",
    "prism",
    "triangle_distance",
]


#: Most half-spaces of a convex polyhedron.
MAX_PLANES = 10000

#: Points per block in the (points x faces) distance computations.
_BLOCK = 2048


def triangle_distance(points: np.ndarray, tris: np.ndarray, edges: np.ndarray | None = None) -> np.ndarray:
    """Unsigned distance from each point to the nearest of many triangles.

    Parameters
    ----------
    points : (n, 3) float ndarray
    tris : (t, 3, 3) float ndarray
        Triangles as three vertices each.
    edges : (e, 2, 3) float ndarray, optional
        The segments to test when a projection falls outside every triangle
        (default: the three edges of every triangle).  A polyhedron passes
        its true edges only, without shared duplicates and face diagonals.

    Returns
    -------
    (n,) float64 ndarray

    Notes
    -----
    For every (point, triangle) pair at once: the distance to the triangle's
    plane when the projection falls inside (barycentric test); every other
    nearest point lies on an edge.
    """
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]              # (t, 3)
    ab, ac = b - a, c - a
    nrm = np.cross(ab, ac)
    nrm_len = np.linalg.norm(nrm, axis=1)
    unit = nrm / np.where(nrm_len > 0, nrm_len, 1.0)[:, None]
    d00 = np.einsum("ij,ij->i", ab, ab)
    d01 = np.einsum("ij,ij->i", ab, ac)
    d11 = np.einsum("ij,ij->i", ac, ac)
    denom = d00 * d11 - d01 * d01
    denom = np.where(denom > 0, denom, 1.0)
    # Dot products with the point minus vertex a, as p . x - a . x: (n, t) arrays only.
    d20 = points @ ab.T - np.einsum("ij,ij->i", a, ab)
    d21 = points @ ac.T - np.einsum("ij,ij->i", a, ac)
    v = (d11 * d20 - d01 * d21) / denom
    w = (d00 * d21 - d01 * d20) / denom
    # A little slack: a projection onto an edge shared by two coplanar
    # triangles (a face diagonal, not among `edges`) must count as inside.
    eps = 1e-10
    inside = (v >= -eps) & (w >= -eps) & (v + w <= 1 + eps) & (nrm_len > 0)
    plane = points @ unit.T - np.einsum("ij,ij->i", a, unit)
    best = np.where(inside, plane * plane, np.inf).min(axis=1)
    if edges is None:
        edges = np.concatenate([np.stack([a, b], 1), np.stack([b, c], 1), np.stack([c, a], 1)])
    p0 = edges[:, 0]
    e = edges[:, 1] - p0
    ee = np.einsum("ij,ij->i", e, e)
    pp = np.einsum("ij,ij->i", points, points)[:, None]
    t = np.clip((points @ e.T - np.einsum("ij,ij->i", p0, e)) / np.where(ee > 0, ee, 1.0), 0.0, 1.0)
    # |p - p0 - t e|^2 expanded: |p - p0|^2 - 2 t (p - p0).e + t^2 |e|^2.
    pq = pp - 2.0 * (points @ p0.T) + np.einsum("ij,ij->i", p0, p0)
    pe = points @ e.T - np.einsum("ij,ij->i", p0, e)
    seg = np.maximum(pq - 2.0 * t * pe + t * t * ee, 0.0)
    best = np.minimum(best, seg.min(axis=1))
    return np.sqrt(best)


def _hull_edges(hull) -> np.ndarray:
    """True edges ``(e, 2, 3)`` of a convex hull: each once, no face diagonals."""
    simplices, neighbors, eq = hull.simplices, hull.neighbors, hull.equations
    out = []
    for k in range(3):
        other = neighbors[:, k]
        keep = np.arange(len(simplices)) < other
        coplanar = np.all(np.isclose(eq, eq[other], rtol=0, atol=1e-10), axis=1)
        keep &= ~coplanar
        pair = np.delete(simplices, k, axis=1)[keep]
        out.append(pair)
    pairs = np.concatenate(out)
    return hull.points[pairs]


def _polytope(normals, offsets, name):
    """Bounds, vertices and boundary triangles of ``{p : normals @ p <= offsets}``."""
    from scipy.optimize import linprog
    from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError

    m = len(normals)
    # Chebyshev centre: maximise r with n_i . x + r <= d_i (unit normals).
    scale = max(1.0, float(np.abs(offsets).max()))
    a_ub = np.hstack([normals, np.ones((m, 1))])
    res = linprog(c=[0, 0, 0, -1.0], A_ub=a_ub, b_ub=offsets, bounds=[(None, None)] * 3 + [(None, None)],
                  method="highs")
    if res.status == 2:
        raise ValueError(f"{name}: the half-spaces have an empty intersection")
    if res.status == 3:
        raise ValueError(f"{name}: the half-spaces do not bound a finite solid (unbounded intersection)")
    if res.status != 0:
        raise ValueError(f"{name}: could not solve for an interior point ({res.message})")
    radius = -res.fun
    if radius < 0:
        raise ValueError(f"{name}: the half-spaces have an empty intersection")
    if radius <= 1e-9 * scale:
        raise ValueError(f"{name}: the half-spaces have an empty interior (largest inscribed ball radius {radius:g})")
    # Bounded?  Maximise / minimise each coordinate.
    for k in range(3):
        for sign in (1.0, -1.0):
            cost = np.zeros(3)
            cost[k] = -sign
            r = linprog(c=cost, A_ub=normals, b_ub=offsets, bounds=[(None, None)] * 3, method="highs")
            if r.status == 3:
                raise ValueError(f"{name}: the half-spaces do not bound a finite solid (unbounded along "
                                 f"{'+' if sign > 0 else '-'}{'xyz'[k]})")
    centre = res.x[:3]
    try:
        hs = HalfspaceIntersection(np.hstack([normals, -offsets[:, None]]), centre)
        verts = hs.intersections
        hull = ConvexHull(verts)
    except QhullError as exc:  # pragma: no cover - guarded by the LP checks
        raise ValueError(f"{name}: could not build the polyhedron ({str(exc).splitlines()[0]})") from None
    tris = hull.points[hull.simplices]
    edges = _hull_edges(hull)
    verts = verts[np.unique(hull.simplices)]
    return verts, tris, edges


class _Polytope(_Primitive):
    """Convex polyhedron from unit normals and plane offsets (exact field)."""

    __slots__ = ("_n", "_d", "_tris", "_verts", "_edges")

    def _setup(self, params, normals, offsets, name):
        verts, tris, edges = _polytope(normals, offsets, name)
        # Pad by rounding error so that the bounds stay conservative.
        pad = 1e-12 * max(1.0, float(np.abs(verts).max()))
        super().__init__(params, (verts.min(axis=0) - pad, verts.max(axis=0) + pad))
        object.__setattr__(self, "_n", normals)
        object.__setattr__(self, "_d", offsets)
        object.__setattr__(self, "_tris", tris)
        object.__setattr__(self, "_verts", verts)
        object.__setattr__(self, "_edges", edges)

    @property
    def vertices(self) -> np.ndarray:
        """Vertices ``(k, 3)`` of the polyhedron."""
        return self._verts.copy()

    @property
    def triangles(self) -> np.ndarray:
        """Boundary triangles ``(t, 3, 3)`` (outward orientation not guaranteed)."""
        return self._tris.copy()

    def _evaluate(self, p):
        planes = (p @ self._n.T - self._d).max(axis=1)
        out = planes.copy()
        idx = np.flatnonzero(planes > 0)
        # Blocks of points keep the (points x triangles) temporaries in cache.
        for start in range(0, idx.size, _BLOCK):
            sel = idx[start:start + _BLOCK]
            out[sel] = triangle_distance(p[sel], self._tris, self._edges)
        return out


def _as_planes(normals, points):
    for name, value in (("normals", normals), ("points", points)):
        if isinstance(value, (str, bytes)) or value is None:
            raise TypeError(f"{name}: expected an (m, 3) array of numbers, got {value!r}")
    try:
        n = np.asarray(normals, dtype=np.float64)
        q = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError("normals, points: expected (m, 3) arrays of numbers") from exc
    if n.ndim != 2 or n.shape[1] != 3 or n.shape[0] < 4:
        raise ValueError(f"normals: expected an (m, 3) array with m >= 4, got shape {n.shape}")
    if n.shape[0] > MAX_PLANES:
        raise ValueError(f"normals: expected at most {MAX_PLANES} planes, got {n.shape[0]}")
    if q.shape != n.shape:
        raise ValueError(f"points: expected the shape of normals {n.shape}, got {q.shape}")
    if not (np.isfinite(n).all() and np.isfinite(q).all()):
        raise ValueError("normals, points: expected finite numbers")
    length = np.linalg.norm(n, axis=1)
    if np.any(length == 0):
        raise ValueError(f"normals: normal {int(np.argmin(length))} is zero")
    n = np.where(np.abs(length - 1.0)[:, None] <= 4e-16, n, n / length[:, None])
    return n, q, np.einsum("ij,ij->i", n, q)


class ConvexPolyhedron(_Polytope):
    """Intersection of half-spaces ``dot(p - points[i], normals[i]) <= 0``."""

    kind = "convex_polyhedron"
    __slots__ = ()

    def __init__(self, normals, points):
        n, q, d = _as_planes(normals, points)
        self._setup({"normals": n.tolist(), "points": q.tolist()}, n, d, "convex_polyhedron")


def _polygon_planes(base, apex):
    """Unit normals and offsets of a pyramid over a convex CCW base at z=0."""
    m = len(base)
    p0 = np.column_stack([base, np.zeros(m)])
    p1 = np.roll(p0, -1, axis=0)
    normals = np.cross(p1 - p0, apex - p0)     # outward for a CCW base
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    normals = np.vstack([normals, [0.0, 0.0, -1.0]])
    offsets = np.append(np.einsum("ij,ij->i", normals[:-1], p0), 0.0)
    return normals, offsets


def _convex_ccw(base, name):
    v = as_polygon(base, name)
    e = np.roll(v, -1, axis=0) - v
    cross = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
    if np.all(cross <= 0):
        v = v[::-1]
        cross = -cross[::-1]
    if not np.all(cross >= 0):
        raise ValueError(f"{name}: expected a convex polygon")
    return v


class Pyramid(_Polytope):
    """Pyramid over a convex polygon: base at `center` in the local (x, y)
    plane, apex `height` along `axis` above the base's area centroid (exact)."""

    kind = "pyramid"
    __slots__ = ()

    def __init__(self, base, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)):
        v = _convex_ccw(base, "base")
        h = as_positive(height, "height")
        c = as_vector(center, "center")
        rot = rotation_to_axis(axis)
        x, y = v[:, 0], v[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        cr = x * yn - xn * y
        area = cr.sum() / 2
        centroid = np.array([((x + xn) * cr).sum(), ((y + yn) * cr).sum()]) / (6 * area)
        apex = np.array([centroid[0], centroid[1], h])
        n_loc, d_loc = _polygon_planes(v, apex)
        normals = n_loc @ rot.T
        offsets = d_loc + normals @ c
        self._setup({"base": v.tolist(), "height": h, "center": c.tolist(), "axis": unit(as_vector(axis, "axis")).tolist()},
                    normals, offsets, "pyramid")


class Wedge(_Polytope):
    """Right-angle wedge: the triangular prism
    ``0 <= x <= sx, 0 <= y <= sy, 0 <= z <= sz (1 - x / sx)`` moved to `corner`
    (exact)."""

    kind = "wedge"
    __slots__ = ()

    def __init__(self, size=(1.0, 1.0, 1.0), corner=(0.0, 0.0, 0.0)):
        s = as_vector(size, "size")
        if np.any(s <= 0):
            raise ValueError(f"size: expected positive edge lengths, got {s.tolist()}")
        c = as_vector(corner, "corner")
        slope = np.array([s[2], 0.0, s[0]])
        normals = np.array([[-1.0, 0, 0], [0, -1.0, 0], [0, 1.0, 0], [0, 0, -1.0], slope / np.linalg.norm(slope)])
        points = np.array([c, c, c + [0, s[1], 0], c, c + [s[0], 0, 0]])
        self._setup({"size": s.tolist(), "corner": c.tolist()}, normals,
                    np.einsum("ij,ij->i", normals, points), "wedge")


def convex_polyhedron(normals, points) -> Solid:
    """Intersection of half-spaces (the half-space method), exact field.

    Parameters
    ----------
    normals : (m, 3) array_like
        Outward normals (any length but zero), ``m >= 4``.
    points : (m, 3) array_like
        A point on each plane.

    Raises
    ------
    ValueError
        When the intersection is empty, flat or unbounded.

    Examples
    --------
    >>> from implicit import convex_polyhedron
    >>> cube = convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
    ...                          [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    >>> cube.bounds[1].round(9).tolist()
    [1.0, 1.0, 1.0]
    """
    return ConvexPolyhedron(normals, points)


def pyramid(base, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """Pyramid over a convex `base` polygon ``(m, 2)`` with apex `height` above
    its centroid (exact).

    Examples
    --------
    >>> from implicit import pyramid
    >>> p = pyramid([(-1, -1), (1, -1), (1, 1), (-1, 1)], 2.0)
    >>> float(p([[0, 0, 3.0]])[0])
    1.0
    """
    return Pyramid(base, height, center, axis)


def wedge(size=(1.0, 1.0, 1.0), corner=(0.0, 0.0, 0.0)) -> Solid:
    """Right-angle wedge (a triangular prism), legs along x and z, extruded
    along y; `corner` is its right-angle corner (exact).

    Examples
    --------
    >>> from implicit import wedge
    >>> float(wedge((1, 1, 1))([[0.5, 0.5, -1.0]])[0])
    1.0
    """
    return Wedge(size, corner)


def prism(polygon_2d, height, center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)) -> Solid:
    """A simple polygon ``(m, 2)`` extruded by `height` along `axis` (exact).

    The polygon lies in the local (x, y) plane (the identity frame for the
    default axis +z) and the prism is centred on `center` along the axis.

    Examples
    --------
    >>> from implicit import prism
    >>> tri = prism([(0, 0), (1, 0), (0, 1)], 2.0)
    >>> float(tri([[0.25, 0.25, 2.0]])[0])
    1.0
    """
    return extrude(polygon(polygon_2d), height, center, axis)
