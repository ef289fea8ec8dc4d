"""Measures of triangle surfaces: triangles of a mesh, angles, normals, edges, closedness,
self-intersections, deviation from a solid, and the quality figures of a surface
(`surface_quality`) that `surface_for_fea` aims at."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from implicit.solid import Solid

__all__ = ["SurfaceQuality", "surface_quality", "self_intersections", "folded_triangles", "mesh_faces"]

#: A triangle whose unit normal meets the solid's outward gradient at its centre with a cosine under this
#: is turned over (a flat face folded onto itself, which `self_intersections` does not see).
FOLD_COSINE = -0.9

# ---------------------------------------------------------------------------
# mesh helpers
# ---------------------------------------------------------------------------

def mesh_faces(mesh) -> np.ndarray:
    """Triangles of a pyvista mesh as an ``(m, 3)`` int array (triangulating if needed).

    Read from the cells' connectivity (`regular_faces`): the legacy ``faces`` array is a copy that
    VTK builds each time (1.6 ms for the benchmark part's feature mesh of 77,000 triangles, read
    three times per surface).
    """
    if not mesh.is_all_triangles:
        mesh = mesh.triangulate()
    return np.asarray(mesh.regular_faces).astype(np.int64)


def enclosed(mesh) -> float:
    """``mesh.volume`` (VTK's mass properties) of a triangle mesh without VTK's pipeline, the same bits
    (`spatial.fea.surface_kernels.enclosed_volume`: 9 -> 2.5 ms for 77,000 triangles)."""
    from .surface_kernels import enclosed_volume

    return enclosed_volume(np.asarray(mesh.points, dtype=np.float64), mesh_faces(mesh))


def _triangle_angles(points, faces):
    """Interior angles (degrees) ``(m, 3)``, at vertex 0, 1, 2."""
    a, b, c = (points[faces[:, i]] for i in range(3))

    def ang(u, v):
        nu = np.linalg.norm(u, axis=1)
        nv = np.linalg.norm(v, axis=1)
        cos = np.einsum("ij,ij->i", u, v) / np.maximum(nu * nv, 1e-300)
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))

    return np.stack([ang(b - a, c - a), ang(a - b, c - b), ang(a - c, b - c)], axis=1)


def _normals(points, faces):
    """``(b - a) x (c - a)`` of each triangle, ``(m, 3)``: `np.cross`'s products and differences
    written out (the same bits, without its temporaries: 9 ms -> 2 ms for 77,000 triangles)."""
    a = points[faces[:, 0]]
    u = points[faces[:, 1]] - a
    v = points[faces[:, 2]] - a
    out = np.empty_like(u)
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out


def _edges(faces):
    """Unique edges ``(e, 2)``, lower index first, sorted (one integer key per edge: `np.unique` over
    rows sorts structured records, several times slower)."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    lo, hi = np.minimum(e[:, 0], e[:, 1]), np.maximum(e[:, 0], e[:, 1])
    n = int(hi.max(initial=0)) + 1
    key = np.unique(lo * n + hi)
    return np.stack([key // n, key % n], axis=1)


def _polydata(points, faces):
    import pyvista as pv

    return pv.PolyData.from_regular_faces(np.asarray(points, dtype=np.float64), np.asarray(faces, dtype=np.int64))


def _is_closed_manifold(faces) -> bool:
    """Every edge in exactly two triangles (one compiled pass over each vertex's few edges; a sort
    of all edge keys took 11 ms for the benchmark part's feature mesh of 77,000 triangles)."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    if faces.size == 0:
        return True
    try:
        from ..files.kernels import edges_twice
    except ImportError:  # pragma: no cover - numba missing
        return _is_closed_manifold_sorted(faces)
    return bool(edges_twice(faces, int(faces.max()) + 1))


def _is_closed_manifold_sorted(faces) -> bool:
    """`_is_closed_manifold` by sorting the edges as one integer key each (sorting rows is slower)."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    n = int(faces.max()) + 1
    key = np.sort(np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1]))
    first, second = key[0::2], key[1::2]
    return bool(first.shape == second.shape and np.all(first == second) and np.all(first[1:] != first[:-1]))


def self_intersections(mesh) -> int:
    """Number of triangles of `mesh` that intersect another one (pymeshfix's test).

    Triangles that only share a vertex or an edge do not count.  A surface that
    `spatial.fea.crossing_kernel.surely_apart` proves free of crossings (every pair apart by a
    margin) is 0 without pymeshfix, which counts the others.

    Examples
    --------
    >>> import pyvista as pv
    >>> self_intersections(pv.Sphere().triangulate())
    0
    """
    points = np.ascontiguousarray(mesh.points, dtype=np.float64)
    faces = mesh_faces(mesh)
    try:
        from .crossing_kernel import surely_apart
    except ImportError:  # pragma: no cover - numba missing
        surely_apart = None
    # A compiled proof that nothing crosses (pymeshfix's loading alone took 11-17 ms of the benchmark
    # part's surface); any pair it cannot separate with a margin leaves the count to pymeshfix.
    if surely_apart is not None and surely_apart(points, np.ascontiguousarray(faces)):
        return 0
    try:
        import pymeshfix
    except ImportError as exc:  # pragma: no cover - dependency missing
        raise ImportError("self_intersections needs pymeshfix: pip install pymeshfix") from exc
    tm = pymeshfix.PyTMesh()
    tm.set_quiet(True)
    tm.load_array(points, np.ascontiguousarray(faces, dtype=np.int32))
    return int(len(tm.select_intersecting_triangles(justproper=True)))


def folded_triangles(solid, points, faces) -> int:
    """Number of triangles facing into `solid`: normal against the field's gradient at their centre.

    Two triangles of one flat face that overlap, one turned over, do not cross each other in
    pymeshfix's test; TetGen fills them with flat elements.

    Examples
    --------
    >>> import pyvista as pv
    >>> from implicit import sphere
    >>> s = pv.Sphere(radius=1.0).triangulate()
    >>> p, f = np.asarray(s.points), mesh_faces(s)
    >>> folded_triangles(sphere(1.0), p, f), folded_triangles(sphere(1.0), p, f[:, ::-1])
    (0, 1680)
    """
    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if faces.shape[0] == 0:
        return 0
    n = _normals(points, faces)
    g = solid.gradient(points[faces].mean(axis=1))
    cos = np.einsum("ij,ij->i", n, g) / np.maximum(np.linalg.norm(n, axis=1) * np.linalg.norm(g, axis=1), 1e-300)
    return int((cos < FOLD_COSINE).sum())


def _deviation(solid, pts, faces):
    centres = pts[faces].mean(axis=1)
    return float(max(np.abs(solid(pts)).max(initial=0.0), np.abs(solid(centres)).max(initial=0.0)))


# ---------------------------------------------------------------------------
# quality
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SurfaceQuality:
    """Quality figures of a triangle surface.

    Attributes
    ----------
    n_points, n_triangles : int
    min_angle : float
        Smallest interior angle, degrees.
    angle_p1, angle_p5 : float
        1st and 5th percentile of every triangle's smallest angle, degrees.
    max_angle : float
        Largest interior angle, degrees.
    max_aspect : float
        Largest aspect ratio (longest edge over the height onto it, scaled so
        an equilateral triangle has 1).
    mean_edge : float
        Mean edge length.
    closed : bool
        Every edge has exactly two triangles.
    max_deviation : float or None
        Largest ``|f|`` of the solid at vertices and face centres.
    """

    n_points: int
    n_triangles: int
    min_angle: float
    angle_p1: float
    angle_p5: float
    max_angle: float
    max_aspect: float
    mean_edge: float
    closed: bool
    max_deviation: float | None

    def summary(self) -> str:
        """One line of text."""
        dev = "" if self.max_deviation is None else f", deviation {self.max_deviation:.2e}"
        return (f"{self.n_triangles} triangles, min angle {self.min_angle:.1f} deg "
                f"(p1 {self.angle_p1:.1f}), max {self.max_angle:.1f}, aspect {self.max_aspect:.2f}{dev}")


def surface_quality(mesh, solid=None) -> SurfaceQuality:
    """Angles, aspect ratios and deviation from `solid` of a triangle mesh.

    Parameters
    ----------
    mesh : pyvista.PolyData
    solid : Solid, optional

    Returns
    -------
    SurfaceQuality

    Examples
    --------
    >>> import pyvista as pv
    >>> q = surface_quality(pv.Icosphere(radius=1.0, nsub=2))
    >>> bool(q.min_angle > 50), q.closed
    (True, True)
    """
    import pyvista as pv

    if not isinstance(mesh, pv.PolyData):
        raise TypeError(f"mesh: expected a pyvista.PolyData, got {type(mesh).__name__}")
    if solid is not None and not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    pts = np.asarray(mesh.points, dtype=np.float64)
    faces = mesh_faces(mesh)
    if len(faces) == 0:
        raise ValueError("mesh: expected triangles, got none")
    ang = _triangle_angles(pts, faces)
    mins = ang.min(axis=1)
    e = np.stack([np.linalg.norm(pts[faces[:, (i + 1) % 3]] - pts[faces[:, i]], axis=1) for i in range(3)], axis=1)
    area2 = np.linalg.norm(_normals(pts, faces), axis=1)
    longest = e.max(axis=1)
    # height onto the longest edge = 2A / longest; equilateral: sqrt(3)/2 * l.
    aspect = longest * longest / np.maximum(area2, 1e-300) * (np.sqrt(3) / 2)
    dev = _deviation(solid, pts, faces) if solid is not None else None
    return SurfaceQuality(
        n_points=int(pts.shape[0]), n_triangles=int(len(faces)),
        min_angle=float(mins.min()), angle_p1=float(np.percentile(mins, 1)),
        angle_p5=float(np.percentile(mins, 5)), max_angle=float(ang.max()),
        max_aspect=float(aspect.max()), mean_edge=float(e.mean()),
        closed=_is_closed_manifold(faces), max_deviation=dev,
    )
