"""Solids from parametric curves, surfaces and volumes.

Curve-based solids (`revolve_curve`, `extrude_curve`, `sweep`, `curve_profile`)
live in `implicit.curve_sweeps` and are re-exported here.  This module adds

* `thicken`: a shell of given thickness around a surface patch (the exact
  unsigned distance to the patch minus half the thickness);
* `surface_solid`: the solid bounded by a closed surface or a set of patches
  (distance by closest-point projection, sign from the outward normal at the
  closest point, or from the generalized winding number of a tessellation
  where the normal is ambiguous);
* `volume_solid`: the region of a trivariate B-spline / NURBS volume
  (inside test by inverting the map with Newton steps, distance to its
  boundary faces).

Closest points follow The NURBS Book, section 6.1: a kd-tree of surface
samples (built once per node) seeds vectorized Newton steps on
``(S_u . r, S_v . r) = 0``, clamped to the domain, with a halving step when a
step moves away; the distance kept is never larger than the seed's.

Surfaces and volumes are stored in node parameters as plain JSON values
(`surface_to_dict`, `volume_to_dict`), so the nodes round-trip through
`implicit.serialize`.

References
----------
L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997, section 6.1.
A. Jacobson, L. Kavan and O. Sorkine-Hornung, "Robust inside-outside
segmentation using generalized winding numbers", ACM Trans. Graph. 32(4),
2013, doi:10.1145/2461912.2461916.
"""

from __future__ import annotations

import numpy as np

from parametric.surfaces import Surface
from parametric.volumes import BSplineVolume

from .curve_sweeps import (  # noqa: F401  (re-exports)
    CurveProfile, Sweep, curve_profile, curve_from_dict, curve_to_dict, extrude_curve,
    revolve_curve, rotation_minimizing_frames, sweep,
)
from .solid import Solid, as_positive
from .surface_projection import (  # noqa: F401  (re-exports)
    SurfaceProjector, _control_box, _dot, _signed_volume, _tessellation, surface_from_dict,
    surface_to_dict, volume_from_dict, volume_to_dict, winding_number,
)

__all__ = [
    "CurveProfile", "Sweep", "Thicken", "SurfaceSolid", "VolumeSolid",
    "curve_profile", "revolve_curve", "extrude_curve", "sweep",
    "thicken", "surface_solid", "volume_solid",
    "surface_to_dict", "surface_from_dict", "volume_to_dict", "volume_from_dict",
    "SurfaceProjector", "winding_number",
]

#: Relative residual below which a volume inversion counts as converged.
INVERSION_TOL = 1e-9


# ---------------------------------------------------------------------------
# nodes
# ---------------------------------------------------------------------------

class Thicken(Solid):
    """The set of points within `thickness` / 2 of a surface patch.

    The field ``dist(p, S) - thickness / 2`` uses the exact distance to the
    patch (closest-point projection, clamped to the domain so that points
    beyond an edge measure to the edge), so it is an exact signed distance
    of the shell (rounded along the patch's border).
    """

    kind = "thicken_surface"
    __slots__ = ("_surface", "_proj", "_half")

    def __init__(self, surface, thickness):
        s = surface_from_dict(surface)
        if s.dim != 3:
            raise ValueError(f"surface: expected a 3D surface, got dimension {s.dim}")
        t = as_positive(thickness, "thickness")
        proj = SurfaceProjector(s)
        lo, hi = _control_box(s, proj.points)
        super().__init__((), {"surface": surface_to_dict(s), "thickness": t},
                         (lo - t / 2, hi + t / 2), exact=True)
        object.__setattr__(self, "_surface", s)
        object.__setattr__(self, "_proj", proj)
        object.__setattr__(self, "_half", t / 2)

    @classmethod
    def from_params(cls, children, params):
        return cls(**params)

    @property
    def surface(self) -> Surface:
        return self._surface

    def _label(self) -> str:
        return f"thicken_surface({self._surface!r}, thickness={2 * self._half:g})"

    def _evaluate(self, p):
        return self._proj.project(p)[2] - self._half


def thicken(surface_patch, thickness) -> Solid:
    """A shell of `thickness` around a surface patch (half on each side).

    Parameters
    ----------
    surface_patch : BezierSurface, BSplineSurface, NURBSSurface or BicubicPatch
    thickness : float

    Returns
    -------
    Thicken
        Exact signed distance ``dist(p, patch) - thickness / 2``.

    Examples
    --------
    >>> from parametric.tensor import BezierSurface
    >>> plate = BezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]])
    >>> slab = thicken(plate, 0.2)
    >>> round(float(slab([[0.5, 0.5, 0.5]])[0]), 12)
    0.4
    """
    return Thicken(surface_patch, thickness)


def _as_surface_list(surfaces):
    if isinstance(surfaces, (Surface, dict)):
        surfaces = [surfaces]
    if not isinstance(surfaces, (list, tuple)) or not surfaces:
        raise TypeError(f"closed_surface: expected a surface or a non-empty list of surfaces, "
                        f"got {type(surfaces).__name__}")
    return [surface_from_dict(s, f"closed_surface[{i}]") for i, s in enumerate(surfaces)]


#: Samples along each boundary curve of a patch in the closedness check.
_EDGE_SAMPLES = 129


def _boundary_curves(surfaces):
    """The four boundary curves of every patch, sampled: a list of (n, 3)."""
    curves = []
    for s in surfaces:
        (au, bu), (av, bv) = s.domain_u, s.domain_v
        us = np.linspace(au, bu, _EDGE_SAMPLES)
        vs = np.linspace(av, bv, _EDGE_SAMPLES)
        curves += [s.grid(np.array([au]), vs)[0], s.grid(np.array([bu]), vs)[0],
                   s.grid(us, np.array([av]))[:, 0], s.grid(us, np.array([bv]))[:, 0]]
    return curves


def _open_boundary(surfaces, size):
    """Index of a boundary curve no other boundary covers (the surface is
    open there), or -1.  A curve collapsed to a point (a pole) needs no
    partner; a periodic seam is covered by the patch's opposite side."""
    curves = _boundary_curves(surfaces)
    tol = 2e-3 * size
    for i, c in enumerate(curves):
        if float(np.linalg.norm(np.diff(c, axis=0), axis=1).sum()) <= tol:
            continue
        others = [curves[j] for j in range(len(curves)) if j != i
                  and float(np.linalg.norm(np.diff(curves[j], axis=0), axis=1).sum()) > tol]
        if not others:
            return i
        a = np.concatenate([o[:-1] for o in others])
        b = np.concatenate([o[1:] for o in others])
        ab = b - a
        ll = np.einsum("ij,ij->i", ab, ab)
        t = np.einsum("kij,ij->ki", c[:, None, :] - a[None], ab) / np.where(ll > 0, ll, 1.0)
        t = np.clip(t, 0.0, 1.0)
        d = np.linalg.norm(c[:, None, :] - (a[None] + t[..., None] * ab[None]), axis=2).min(axis=1)
        if float(d.max()) > tol:
            return i
    return -1


class SurfaceSolid(Solid):
    """The solid bounded by a closed surface (one patch or several).

    Distance: the smallest closest-point distance over the patches.  Sign:
    the side of the normal at the closest point; where several patches are
    equally close (a shared edge or corner) their unit normals are summed
    (a pseudo-normal).  The patches must be oriented consistently, all
    outward or all inward: the orientation is fixed once from the signed
    volume of a tessellation.  Where the vote is still undecided, the
    generalized winding number of the tessellation decides.  The field is the
    exact signed distance up to the Newton tolerance.
    """

    kind = "surface_solid"
    __slots__ = ("_surfaces", "_projs", "_orient", "_tris")

    def __init__(self, surfaces):
        ss = _as_surface_list(surfaces)
        for i, s in enumerate(ss):
            if s.dim != 3:
                raise ValueError(f"closed_surface[{i}]: expected a 3D surface, got dimension {s.dim}")
        projs = [SurfaceProjector(s) for s in ss]
        tris = _tessellation(ss)
        vol = _signed_volume(tris)
        boxes = [_control_box(s, pr.points) for s, pr in zip(ss, projs)]
        lo = np.min([b[0] for b in boxes], axis=0)
        hi = np.max([b[1] for b in boxes], axis=0)
        size = float(np.max(hi - lo))
        if not abs(vol) > 1e-9 * size ** 3:
            raise ValueError("closed_surface: the surface encloses no volume (is it closed?)")
        # an open surface has no inside: its closest-point sign would call
        # points outside the part inside, so it is refused
        edge = _open_boundary(ss, size)
        if edge >= 0:
            side = ("u = start", "u = end", "v = start", "v = end")[edge % 4]
            raise ValueError(f"closed_surface: the surface is open: the boundary {side} of patch {edge // 4} "
                             "meets no other boundary (close it with more patches, e.g. end caps)")
        orient = 1.0 if vol > 0 else -1.0
        super().__init__((), {"surfaces": [surface_to_dict(s) for s in ss]}, (lo, hi), exact=True)
        object.__setattr__(self, "_surfaces", tuple(ss))
        object.__setattr__(self, "_projs", tuple(projs))
        object.__setattr__(self, "_orient", orient)
        object.__setattr__(self, "_tris", tris if orient > 0 else tris[:, ::-1])

    @classmethod
    def from_params(cls, children, params):
        return cls(**params)

    @property
    def surfaces(self) -> tuple:
        return self._surfaces

    def _label(self) -> str:
        return f"surface_solid({len(self._surfaces)} patch{'es' if len(self._surfaces) > 1 else ''})"

    def _evaluate(self, p):
        results = [pr.project(p) for pr in self._projs]
        D = np.stack([r[2] for r in results])                 # (k, n)
        best = D.min(axis=0)
        # side of every patch within a hair of the minimum: on a shared edge or
        # corner the unit normals of the patches meeting there are summed (an
        # edge pseudo-normal), which decides convex and concave edges alike
        near = D <= best + 1e-9 * (1.0 + best)
        vote = np.zeros(p.shape[0])
        for k, (pr, (uvk, Ck, _)) in enumerate(zip(self._projs, results)):
            sel = np.flatnonzero(near[k])
            if sel.size:
                n = pr.normals(uvk[sel])
                nn = np.linalg.norm(n, axis=1)
                vote[sel] += _dot(n, p[sel] - Ck[sel]) / np.where(nn > 0, nn, 1.0)
        side = np.where(np.abs(vote) > 1e-3 * best, np.sign(vote), 0.0) * self._orient
        amb = (side == 0) & (best > 0)
        if np.any(amb):
            side[amb] = np.where(winding_number(p[amb], self._tris) > 0.5, -1.0, 1.0)
        return side * best


def surface_solid(closed_surface) -> Solid:
    """The solid bounded by a closed surface.

    Parameters
    ----------
    closed_surface : surface or list of surfaces
        Tensor-product surfaces (Bezier, B-spline, NURBS, bicubic) that
        together close (e.g. `parametric.tensor.sphere`, `torus`, or the six
        faces of a box).

    Returns
    -------
    SurfaceSolid

    Examples
    --------
    >>> from parametric.tensor import sphere as nurbs_sphere
    >>> ball = surface_solid(nurbs_sphere(2.0))
    >>> np.round(ball([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]]), 9)
    array([-2.,  1.])
    """
    return SurfaceSolid(closed_surface)


def _face_area(tris):
    return float(np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1).sum() / 2)


class VolumeSolid(Solid):
    """The region of a trivariate B-spline / NURBS volume ``x = p(u, v, w)``.

    Inside test: Newton steps on ``p(u, v, w) = x`` (``J du = x - p``) from
    the nearest of a grid of samples, clamped to the parameter box; a point
    is inside when the residual vanishes.  Distance: the smallest distance
    to the boundary faces, leaving out faces that collapse (zero area) and
    pairs of opposite faces that coincide (the seam of a closed direction),
    which lie inside the region.  The map must be injective (positive
    Jacobian determinant) for the inside test to be right.
    """

    kind = "volume_solid"
    __slots__ = ("_volume", "_projs", "_tree", "_uvw", "_size", "_closed")

    def __init__(self, volume):
        vol = volume_from_dict(volume)
        doms = vol.domains
        faces = vol.boundary_surfaces()
        grids = {}
        for key, s in faces.items():
            pts, tri = s.tessellate(16, 16, merge_seams=False)
            grids[key] = (pts, pts[tri])
        ctrl = np.asarray(vol.control_points).reshape(-1, 3)
        lo, hi = ctrl.min(axis=0), ctrl.max(axis=0)
        size = float(np.max(hi - lo))
        keep, closed = [], []
        for ax in "uvw":
            p0, t0 = grids[ax + "0"]
            p1, t1 = grids[ax + "1"]
            seam = np.max(np.linalg.norm(p0 - p1, axis=1)) <= 1e-9 * size
            closed.append(bool(seam))
            for key, tris in ((ax + "0", t0), (ax + "1", t1)):
                if not seam and _face_area(tris) > 1e-12 * size ** 2:
                    keep.append(key)
        if not keep:
            raise ValueError("volume: no boundary face left (degenerate volume)")
        n = [int(np.clip(4 * k, 8, 32)) for k in np.asarray(vol.control_points).shape[:3]]
        axes = [np.linspace(a, b, k) for (a, b), k in zip(doms, n)]
        UVW = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
        X = vol(UVW[:, 0], UVW[:, 1], UVW[:, 2])
        super().__init__((), {"volume": volume_to_dict(vol)}, (lo, hi), exact=True)
        object.__setattr__(self, "_volume", vol)
        object.__setattr__(self, "_projs", tuple(SurfaceProjector(faces[k]) for k in keep))
        from scipy.spatial import cKDTree  # local: scipy.spatial costs 0.25 s to import

        object.__setattr__(self, "_tree", cKDTree(X))
        object.__setattr__(self, "_uvw", UVW)
        object.__setattr__(self, "_size", size)
        object.__setattr__(self, "_closed", np.array(closed))

    @classmethod
    def from_params(cls, children, params):
        return cls(**params)

    @property
    def volume(self) -> BSplineVolume:
        return self._volume

    def _label(self) -> str:
        return f"volume_solid({type(self._volume).__name__} {np.asarray(self._volume.control_points).shape[:3]})"

    def invert(self, points, iterations: int = 20):
        """Parameters ``(n, 3)`` of points and a mask of converged (inside) points."""
        P = np.asarray(points, dtype=float).reshape(-1, 3)
        vol = self._volume
        lo = np.array([d[0] for d in vol.domains])
        hi = np.array([d[1] for d in vol.domains])
        _, idx = self._tree.query(P)
        t = self._uvw[idx].copy()
        res = np.full(P.shape[0], np.inf)
        active = np.arange(P.shape[0])
        for _ in range(int(iterations)):
            if active.size == 0:
                break
            ta = t[active]
            r = P[active] - vol(ta[:, 0], ta[:, 1], ta[:, 2])
            res[active] = np.linalg.norm(r, axis=1)
            J = vol.jacobian(ta[:, 0], ta[:, 1], ta[:, 2])
            ok = np.abs(np.linalg.det(J)) > 1e-300
            step = np.zeros_like(ta)
            if np.any(ok):
                step[ok] = np.linalg.solve(J[ok], r[ok][:, :, None])[:, :, 0]
            tn = np.clip(ta + step, lo, hi)
            if self._closed.any():  # a closed direction wraps around its seam
                wrapped = lo + np.mod(ta + step - lo, hi - lo)
                tn = np.where(self._closed, wrapped, tn)
            t[active] = tn
            moved = np.abs(t[active] - ta) / (hi - lo)
            moved = np.max(np.where(self._closed, np.minimum(moved, 1.0 - moved), moved), axis=1)
            active = active[(moved > 1e-13) & (res[active] > 1e-14 * self._size)]
        r = P - vol(t[:, 0], t[:, 1], t[:, 2])
        res = np.linalg.norm(r, axis=1)
        return t, res <= INVERSION_TOL * self._size

    def _evaluate(self, p):
        best = np.full(p.shape[0], np.inf)
        for pr in self._projs:
            best = np.minimum(best, pr.project(p)[2])
        lo, hi = self.bounds
        boxed = np.flatnonzero(np.all((p >= lo) & (p <= hi), axis=1))  # outside the hull box: outside
        inside = np.zeros(p.shape[0], dtype=bool)
        if boxed.size:
            inside[boxed] = self.invert(p[boxed])[1]
        return np.where(inside, -best, best)


def volume_solid(bspline_volume) -> Solid:
    """The region of a parametric (trivariate) volume as a solid.

    Parameters
    ----------
    bspline_volume : BSplineVolume, NURBSVolume or BezierVolume
        An injective map of its parameter box.

    Returns
    -------
    VolumeSolid

    Examples
    --------
    >>> from parametric.volumes import NURBSVolume
    >>> tube = volume_solid(NURBSVolume.revolve_rectangle(0.5, 1.0, 0.0, 1.0))
    >>> np.round(tube([[0.75, 0.0, 0.5], [0.0, 0.0, 0.5]]), 9)
    array([-0.25,  0.5 ])
    """
    return VolumeSolid(bspline_volume)

