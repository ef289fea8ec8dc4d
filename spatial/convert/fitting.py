"""Grids and solids <-> parametric curves and surfaces; surfaces and curves -> meshes.

From solids (or occupancy grids, through their trilinear `to_solid`):

* `fit_section_curve`: a planar section's contour (scikit-image
  `find_contours` on a sampled plane, points moved onto the true boundary by
  `spatial.analysis.section`), fitted by a closed periodic least-squares B-spline with a
  chosen control count or a tolerance, and its maximum deviation;
* `loft_sections`: a stack of such sections, fitted with one control count
  (so their knot vectors agree), skinned into a B-spline surface (The NURBS
  Book, section 10.3);
* `fit_star_surface`: the boundary of a star-shaped solid as a closed B-spline
  surface ``r(theta, phi)`` (radii found by sampling and bisecting the field
  along rays from the centre; periodic seam in theta, poles collapsed to
  single points), with a scalar radial B-spline and a `StarSolid` made from it.

To meshes: `surface_to_mesh` (triangles), `curve_to_polydata` (a polyline),
`isoparametric_polydata` (the curves at ``u`` and ``v`` steps of 0.1).

References
----------
L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997: A9.7 (least
squares), section 10.3 (skinning).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from implicit.solid import Solid
from implicit.star_solids import StarSolid, fit_radial_function
from parametric.curves import BSpline, Curve
from parametric.fitting import fit_curve, fit_periodic_surface, loft
from parametric.surfaces import Surface

from ..analysis.section import section
from ..cells.grid import OccupancyGrid

__all__ = [
    "SectionCurve", "LoftResult", "StarFit",
    "fit_section_curve", "loft_sections", "star_radii", "fit_star_surface",
    "surface_to_mesh", "curve_to_polydata", "isoparametric_polydata",
]

#: Samples along each ray before bisection (per ray).
RAY_SAMPLES = 96
#: Bisection steps of the ray-boundary intersection.
RAY_BISECTIONS = 40
#: Samples per control point used to measure a fit against the solid.
CHECK_SAMPLES = 16


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------

def _as_solid(obj, name="solid_or_grid") -> Solid:
    if isinstance(obj, Solid):
        return obj
    if isinstance(obj, OccupancyGrid):
        return obj.to_solid()
    raise TypeError(f"{name}: expected a Solid or an OccupancyGrid, got {type(obj).__name__}")


def _count(value, name, minimum):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an int, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name}: expected at least {minimum}, got {value}")
    return int(value)


def _positive(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number, got {value!r}")
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name}: expected a positive number, got {value!r}")
    return float(value)


def _start_on_first_axis(loop):
    """Rotate a closed loop (k, 2) to start where it crosses the ray from its
    centroid along +e1, so stacked sections start at matching points."""
    c = loop.mean(axis=0)
    ang = np.mod(np.arctan2(loop[:, 1] - c[1], loop[:, 0] - c[0]), 2 * np.pi)
    return np.roll(loop, -int(np.argmin(ang)), axis=0)


# ---------------------------------------------------------------------------
# sections
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SectionCurve:
    """A fitted section contour.

    Attributes
    ----------
    curve : BSpline
        Closed periodic B-spline in space (3D), domain [0, 1].
    curve2d : BSpline
        The same in plane coordinates ``(u, v)`` along ``frame[0], frame[1]``.
    points : (k, 2) float
        The contour data (on the boundary), plane coordinates.
    point, frame : (3,), (3, 3) float
        The plane (origin and rows ``e1, e2, normal``).
    hole : bool
        True when the loop bounds a hole of the section.
    max_deviation : float
        ``max(data deviation, max |f| on the curve)``: how far the curve
        strays from the contour points (at their parameters) and from the
        solid's boundary (``|f|`` sampled along the curve; a lower bound of the
        distance for a conservative field, the distance for an exact one).
    n_control : int
        Distinct control points of the periodic fit.
    """

    curve: BSpline
    curve2d: BSpline
    points: np.ndarray
    point: np.ndarray
    frame: np.ndarray
    hole: bool
    max_deviation: float
    n_control: int


def _fit_loop(solid, loop, point, frame, hole, n_control, tolerance, degree):
    data = _start_on_first_axis(loop)
    p = degree
    if data.shape[0] < p + 2:
        raise ValueError(f"the section loop has only {data.shape[0]} points; raise the resolution")
    if n_control is not None:
        n_control = min(n_control, data.shape[0])
    c2, dev = fit_curve(data, degree=p, n_control=n_control, tolerance=tolerance, closed=True)
    P2 = np.asarray(c2.control_points)
    c3 = BSpline(point + P2 @ frame[:2], c2.degree, c2.knots)
    n = P2.shape[0] - c2.degree
    t = np.linspace(0.0, 1.0, max(CHECK_SAMPLES * n, 256), endpoint=False)
    off = float(np.max(np.abs(solid(c3(t)))))
    return SectionCurve(c3, c2, data, point, frame, bool(hole), max(float(dev), off), int(n))


def fit_section_curve(solid_or_grid, plane="z=0", *, n_control=None, tolerance=None, degree=3,
                      resolution=256, loop=None):
    """Fit a closed B-spline to a planar section contour of a solid or grid.

    Parameters
    ----------
    solid_or_grid : Solid or OccupancyGrid
        A grid is read through its trilinear interpolant.
    plane : str or (point, normal)
        ``"z=0.5"`` or a point and normal (see `spatial.analysis.section.section`).
    n_control : int, optional
        Distinct control points of the periodic fit.
    tolerance : float, optional
        Largest deviation from the contour points: the control count grows
        until it is met (default with neither: half the contour points).
    degree : int
    resolution : int
        Samples across the section's bounding rectangle.
    loop : int or "all", optional
        Which contour: by default the one enclosing the largest area; an
        index into the section's loops; or ``"all"`` for a list of every loop.

    Returns
    -------
    SectionCurve (or a list of them for ``loop="all"``)

    Raises
    ------
    ValueError
        When the plane misses the solid.

    Examples
    --------
    >>> from implicit import sphere
    >>> fit = fit_section_curve(sphere(1.0), "z=0.6", tolerance=1e-4)
    >>> fit.max_deviation < 1e-4
    True
    """
    solid = _as_solid(solid_or_grid)
    if n_control is not None:
        n_control = _count(n_control, "n_control", int(degree) + 1)
    if tolerance is not None:
        tolerance = _positive(tolerance, "tolerance")
    degree = _count(degree, "degree", 1)
    sec = section(solid, plane, resolution=resolution)
    if not sec.loops:
        raise ValueError(f"plane: the plane {plane!r} does not cut the solid")
    if loop == "all":
        chosen = list(range(len(sec.loops)))
    elif loop is None:
        areas = [abs(_area(lp)) for lp in sec.loops]
        chosen = [int(np.argmax(areas))]
    else:
        i = _count(loop, "loop", 0)
        if i >= len(sec.loops):
            raise ValueError(f"loop: the section has {len(sec.loops)} loops, got index {i}")
        chosen = [i]
    fits = [_fit_loop(solid, sec.loops[i], sec.point, sec.frame, sec.holes[i], n_control, tolerance, degree)
            for i in chosen]
    return fits if loop == "all" else fits[0]


def _area(loop):
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


@dataclass(frozen=True)
class LoftResult:
    """A skinned surface through fitted sections.

    Attributes
    ----------
    surface : BSplineSurface
        ``u`` along the sections (closed), ``v`` across them; ``S(u, v_k)`` is
        section ``k``.
    sections : list of SectionCurve
    levels : (k,) float
        Plane positions along the axis.
    max_deviation : float
        Largest section deviation, and ``|f|`` sampled on the surface between
        the sections.
    """

    surface: object
    sections: list
    levels: np.ndarray
    max_deviation: float


def loft_sections(solid, axis="z", levels=8, *, n_control=None, tolerance=None, degree=3, degree_v=3,
                  resolution=256, margin=0.05):
    """Loft (skin) a B-spline surface through a stack of fitted sections.

    Parameters
    ----------
    solid : Solid or OccupancyGrid
    axis : {"x", "y", "z"}
        Normal of the section planes.
    levels : int or (k,) array_like
        Plane positions, or their count spread evenly over the solid's extent
        along `axis` (leaving `margin` of it free at both ends).
    n_control : int, optional
        Control points of every section (one count for all, so that their
        knot vectors agree).
    tolerance : float, optional
        Each section is fitted to `tolerance`; all are then refitted with the
        largest control count needed.
    degree, degree_v : int
        Degree around the sections and across them.
    resolution : int
        Section sampling.
    margin : float
        Fraction of the extent left out at each end when `levels` is a count.

    Returns
    -------
    LoftResult

    Examples
    --------
    >>> from implicit import cylinder
    >>> res = loft_sections(cylinder(1.0, 2.0), "z", 4, n_control=12)
    >>> res.surface.degree_v
    3
    """
    s = _as_solid(solid, "solid")
    if axis not in ("x", "y", "z"):
        raise ValueError(f"axis: expected 'x', 'y' or 'z', got {axis!r}")
    k = "xyz".index(axis)
    if isinstance(levels, numbers.Integral) and not isinstance(levels, bool):
        count = _count(levels, "levels", 2)
        lo, hi = s.bounds
        ext = hi[k] - lo[k]
        lv = np.linspace(lo[k] + margin * ext, hi[k] - margin * ext, count)
    else:
        try:
            lv = np.asarray(levels, dtype=float).ravel()
        except (TypeError, ValueError):
            raise TypeError(f"levels: expected an int or a sequence of numbers, got {levels!r}") from None
        if lv.size < 2 or not np.all(np.diff(lv) > 0):
            raise ValueError("levels: expected at least 2 increasing positions")
    planes = [f"{axis}={x!r}" for x in lv.tolist()]
    for pl in planes:
        sec = section(s, pl, resolution=resolution)
        outer = len(sec.loops) - sum(sec.holes)
        if sum(sec.holes) or outer > 1:
            what = f"{sum(sec.holes)} hole(s)" if sum(sec.holes) else f"{outer} separate loops"
            raise ValueError(f"solid: the section {pl} has {what}; a loft skins one outer loop per level "
                             "and would drop the rest silently (loft the parts separately, or fit the "
                             "sections with fit_section_curve)")
    fits = [fit_section_curve(s, pl, n_control=n_control, tolerance=tolerance, degree=degree,
                              resolution=resolution) for pl in planes]
    counts = {f.n_control for f in fits}
    if len(counts) > 1:
        n = max(counts)
        fits = [fit_section_curve(s, pl, n_control=n, degree=degree, resolution=resolution) for pl in planes]
    surf = loft([f.curve for f in fits], degree_v=degree_v)
    (au, bu), (av, bv) = surf.domain_u, surf.domain_v
    grid = surf.grid(np.linspace(au, bu, 128), np.linspace(av, bv, 8 * len(fits)))
    between = float(np.max(np.abs(s(grid.reshape(-1, 3)))))
    dev = max(max(f.max_deviation for f in fits), between)
    return LoftResult(surf, fits, lv, dev)


# ---------------------------------------------------------------------------
# star-shaped boundaries
# ---------------------------------------------------------------------------

def _sphere_grid(samples):
    nt, nph = samples
    th = 2 * np.pi * np.arange(nt) / nt
    ph = np.linspace(0.0, np.pi, nph)
    T, PH = np.meshgrid(th, ph, indexing="ij")
    return np.stack([np.sin(PH) * np.cos(T), np.sin(PH) * np.sin(T), np.cos(PH)], axis=-1)


def _default_center(solid):
    lo, hi = solid.bounds
    c = 0.5 * (lo + hi)
    if solid(c[None])[0] < 0:
        return c
    axes = [np.linspace(lo[i], hi[i], 24) for i in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    inside = pts[solid(pts) < 0]
    if inside.shape[0] == 0:
        raise ValueError("solid: no interior found to place the centre; pass center=")
    c = inside.mean(axis=0)
    # the mean of a ring's (torus's) interior lies in its hole: no centre at all
    if not solid(c[None])[0] < 0:
        raise ValueError(f"center: the default centre {np.round(c, 9).tolist()} (the bounds' centre, then the "
                         "mean of the interior samples) is outside the solid, which is then not star-shaped "
                         "about it; pass center= a point inside from which every ray leaves the solid once")
    return c


def star_radii(solid, center, samples=(64, 33)):
    """Distances from `center` to the boundary along a grid of rays.

    Parameters
    ----------
    solid : Solid
        Star-shaped about `center` (every ray leaves the solid once).
    center : (3,) float
        A point inside.
    samples : (2,) int
        Rays at ``theta_i = 2 pi i / n_theta``, ``phi_j = pi j / (n_phi - 1)``.

    Returns
    -------
    (n_theta, n_phi) float

    Notes
    -----
    Each ray is sampled at `RAY_SAMPLES` points out to the bounding box; the
    first sign change is refined by `RAY_BISECTIONS` bisection steps (all rays
    at once).  A star-shaped solid has one crossing per ray.
    """
    dirs = _sphere_grid(samples).reshape(-1, 3)
    lo, hi = solid.bounds
    far = float(np.max(np.linalg.norm(np.array([lo, hi]) - center, axis=1))) * np.sqrt(3.0) + 1e-9
    far = max(far, float(np.linalg.norm(hi - lo)))
    rs = np.linspace(0.0, far, RAY_SAMPLES + 1)[1:]
    f = solid((center + rs[None, :, None] * dirs[:, None, :]).reshape(-1, 3)).reshape(dirs.shape[0], -1)
    out = f > 0
    if not np.all(out.any(axis=1)):
        raise ValueError("solid: some rays from the centre never leave the solid (unbounded?)")
    first = np.argmax(out, axis=1)
    a = np.where(first > 0, rs[np.maximum(first - 1, 0)], 0.0)
    b = rs[first]
    for _ in range(RAY_BISECTIONS):
        m = 0.5 * (a + b)
        inside = solid(center + m[:, None] * dirs) <= 0
        a = np.where(inside, m, a)
        b = np.where(inside, b, m)
    return (0.5 * (a + b)).reshape(samples)


@dataclass(frozen=True)
class StarFit:
    """A star-shaped boundary fitted by B-splines.

    Attributes
    ----------
    surface : BSplineSurface
        Closed 3D surface: periodic in ``u = theta / 2 pi``, ``v = 1 - phi / pi``
        (south pole at ``v = 0``, normals ``Su x Sv`` outward), poles collapsed.
    radial : BSplineSurface
        Scalar radial function on the same parameters (for `solid`).
    center : (3,) float
    radii : (n_theta, n_phi) float
        The ray data.
    max_deviation : float
        Largest distance between a data point and the 3D surface at its
        parameters, and ``|f|`` of the source sampled on the surface.
    solid : StarSolid
        A conservative solid from `radial`.
    """

    surface: object
    radial: object
    center: np.ndarray
    radii: np.ndarray
    max_deviation: float
    solid: StarSolid


def fit_star_surface(solid, center=None, *, n_control=(16, 8), degree=(3, 3), samples=(64, 33)):
    """Fit a closed B-spline surface to a star-shaped solid's boundary.

    Parameters
    ----------
    solid : Solid or OccupancyGrid
        Star-shaped about `center`.
    center : (3,) array_like, optional
        Default: the middle of the bounds if inside, else the mean of interior
        samples.
    n_control : (2,) int
        Distinct control points around (theta) and pole to pole (phi).
    degree : (2,) int
    samples : (2,) int
        Rays ``(n_theta, n_phi)`` (poles included).

    Returns
    -------
    StarFit

    Examples
    --------
    >>> from implicit import sphere
    >>> fit = fit_star_surface(sphere(1.0), samples=(32, 17), n_control=(12, 8))
    >>> fit.max_deviation < 1e-3
    True
    """
    s = _as_solid(solid, "solid")
    if not s.is_bounded:
        raise ValueError("solid: expected a bounded solid, got infinite bounds")
    try:
        nt, nph = (int(x) for x in samples)
        nu, nv = (int(x) for x in n_control)
    except (TypeError, ValueError):
        raise TypeError("samples and n_control: expected pairs of ints") from None
    if nt < 8 or nph < 5:
        raise ValueError(f"samples: expected at least (8, 5) rays, got {(nt, nph)}")
    if center is None:
        c = _default_center(s)
    else:
        from implicit.solid import as_vector

        c = as_vector(center, "center")
        if not s(c[None])[0] < 0:
            raise ValueError(f"center: expected a point inside the solid, got {c.tolist()}")
    R = star_radii(s, c, (nt, nph))
    surf, dev = fit_periodic_surface(R, center=c, n_control=(nu, nv), degree=degree)
    radial, _ = fit_radial_function(R, n_control=(nu, nv), degree=degree)
    g = surf.grid(np.linspace(0, 1, 4 * nt), np.linspace(0, 1, 4 * nph))
    off = float(np.max(np.abs(s(g.reshape(-1, 3)))))
    return StarFit(surf, radial, c, R, max(float(dev), off), StarSolid(radial, c))


# ---------------------------------------------------------------------------
# meshes and polylines
# ---------------------------------------------------------------------------

def _pyvista():
    try:
        import pyvista as pv
    except ImportError as exc:  # pragma: no cover - a declared dependency
        raise ImportError("surface and curve meshes need pyvista: pip install pyvista") from exc
    return pv


def surface_to_mesh(surface, nu=64, nv=64):
    """Triangulate a parametric surface on a regular ``nu x nv`` parameter grid.

    Parameters
    ----------
    surface : parametric Surface (3D)
    nu, nv : int
        Samples along ``u`` and ``v`` (at least 2).

    Returns
    -------
    pyvista.PolyData
        Triangles winding counter-clockwise about ``Su x Sv``; point data
        ``"uv"`` holds the parameters.  Coincident seam and pole points are
        kept (the mesh is not welded).

    Examples
    --------
    >>> from parametric.tensor import sphere
    >>> m = surface_to_mesh(sphere(1.0), 16, 8)
    >>> m.n_points, m.n_cells
    (128, 210)
    """
    if not isinstance(surface, Surface):
        raise TypeError(f"surface: expected a parametric Surface, got {type(surface).__name__}")
    if surface.dim != 3:
        raise ValueError(f"surface: expected a 3D surface, got dimension {surface.dim}")
    nu, nv = _count(nu, "nu", 2), _count(nv, "nv", 2)
    pv = _pyvista()
    pts, tri = surface.tessellate(nu, nv, merge_seams=False)
    faces = np.hstack([np.full((tri.shape[0], 1), 3), tri]).ravel()
    mesh = pv.PolyData(pts, faces)
    (au, bu), (av, bv) = surface.domain_u, surface.domain_v
    U, V = np.meshgrid(np.linspace(au, bu, nu), np.linspace(av, bv, nv), indexing="ij")
    mesh.point_data["uv"] = np.stack([U.ravel(), V.ravel()], axis=1)
    return mesh


def _polylines(lines):
    """PolyData of polylines from a list of (k, 3) arrays."""
    pv = _pyvista()
    pts = np.concatenate(lines)
    sizes = [ln.shape[0] for ln in lines]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    cells = np.concatenate([np.concatenate([[k], s + np.arange(k)]) for k, s in zip(sizes, starts)])
    return pv.PolyData(pts, lines=cells)


def curve_to_polydata(curve, n=200):
    """A curve as a pyvista polyline of `n` points (2D curves get z = 0).

    Examples
    --------
    >>> from parametric.conics import circle
    >>> curve_to_polydata(circle(1.0), 50).n_lines
    1
    """
    if not isinstance(curve, Curve):
        raise TypeError(f"curve: expected a parametric Curve, got {type(curve).__name__}")
    n = _count(n, "n", 2)
    pts = curve.sample(n)
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(n)])
    elif pts.shape[1] != 3:
        raise ValueError(f"curve: expected a 2D or 3D curve, got dimension {pts.shape[1]}")
    poly = _polylines([pts])
    poly.point_data["u"] = np.linspace(*curve.domain, n)
    return poly


def isoparametric_polydata(surface, step=0.1, samples=50):
    """The isoparametric curves of a surface at ``u`` and ``v`` steps of `step`.

    Parameters
    ----------
    surface : parametric Surface (3D)
    step : float
        Fraction of each domain between lines (0.1: 11 lines each way).
    samples : int
        Points along each line.

    Returns
    -------
    pyvista.PolyData
        Polylines; cell data ``"direction"`` is 0 for curves of constant
        ``u`` and 1 for constant ``v``.

    Examples
    --------
    >>> from parametric.tensor import torus
    >>> isoparametric_polydata(torus(2.0, 0.5)).n_lines
    22
    """
    if not isinstance(surface, Surface):
        raise TypeError(f"surface: expected a parametric Surface, got {type(surface).__name__}")
    u_lines, v_lines = surface.isoparametric_lines(step, samples)
    poly = _polylines(list(u_lines) + list(v_lines))
    poly.cell_data["direction"] = np.repeat([0, 1], [len(u_lines), len(v_lines)])
    return poly
