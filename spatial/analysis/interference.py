"""Interference and clearance between solids, and across whole assemblies.

`interference(a, b)` says whether two solids share volume, how much (the
mass properties of ``a & b``, with their error estimate), where (the bounds
of the overlap), and when they do not overlap, their minimum clearance with
a guaranteed bracket.  Two solids that only touch (contact of zero volume)
are reported as touching, not interfering.

`check_assembly(parts)` finds every interfering pair of an assembly.  A
sort-and-sweep over the parts' bounding boxes keeps the full checks to the
pairs whose boxes overlap, so a hundred scattered parts cost a handful of
checks instead of 4,950.

Clearance
---------
Both boundaries are meshed with vertices on the true surfaces.  The field of
`a` at `b`'s vertices (and of `b` at `a`'s) gives candidates; the best are
refined by alternating projection between the two surfaces (Newton steps
``q -= f(q) grad f / |grad f|^2``) to a pair of surface points ``(p, q)``.
The reported clearance is ``|p - q|``, an upper bound of the true one; the
lower bound is ``min_v f_a(v) - sqrt(3) h`` (every surface point lies
within a cell diagonal of a vertex, and a field that is an exact distance or
a bound never exceeds the distance).  `clearance_error` is the width of that
bracket.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Interference", "AssemblyReport", "interference", "check_assembly", "box_pairs"]

#: Default cells across the pair's common bounds.
DEFAULT_RESOLUTION = 64
#: Candidate vertices refined by alternating projection.
CANDIDATES = 16
#: Alternating-projection rounds.
PROJECTION_STEPS = 12


@dataclass(frozen=True)
class Interference:
    """The result of `interference`.

    Attributes
    ----------
    interferes : bool
        The solids share volume: the boundary mesh of ``a & b`` at the cell
        size encloses a positive volume.
    touching : bool
        They meet without sharing volume (clearance within `contact_tolerance`).
    volume, volume_error : float
        Shared volume and its absolute error estimate.
    overlap_bounds : (lo, hi) of (3,) float, or None
        Axis-aligned bounds of the shared volume's boundary mesh.
    clearance : float
        Minimum distance between the solids (0 when they touch or interfere);
        an upper bound, exact to `clearance_error`.
    clearance_error : float
        Width of the guaranteed bracket of the clearance.
    closest_points : (2, 3) float or None
        A point on each surface realising `clearance`.
    voxel_size : float
        Cell size used.
    possible_contact : bool
        No shared volume was found, but the clearance's lower bound is 0:
        an overlap or contact thinner than a cell cannot be excluded;
        `volume_error` then bounds the volume it may have (the cells the
        octree of ``a & b`` could not prove empty).
    """

    interferes: bool
    touching: bool
    volume: float
    volume_error: float
    overlap_bounds: tuple | None
    clearance: float
    clearance_error: float
    closest_points: np.ndarray | None
    voxel_size: float
    possible_contact: bool = False

    def to_dict(self) -> dict:
        """Plain-Python form for JSON."""
        return {
            "interferes": self.interferes, "touching": self.touching, "volume": self.volume,
            "volume_error": self.volume_error,
            "overlap_bounds": None if self.overlap_bounds is None else [b.tolist() for b in self.overlap_bounds],
            "clearance": self.clearance, "clearance_error": self.clearance_error,
            "closest_points": None if self.closest_points is None else self.closest_points.tolist(),
            "voxel_size": self.voxel_size, "possible_contact": self.possible_contact,
        }


def _check_solid(x, name):
    from implicit import Solid

    if not isinstance(x, Solid):
        raise TypeError(f"{name}: expected a Solid, got {type(x).__name__}")
    if not x.is_bounded:
        raise ValueError(f"{name}: expected a bounded solid, got infinite bounds")
    if x.is_empty_bounds:
        raise ValueError(f"{name}: the solid is empty")
    return x


def _cell_size(a, b, resolution, voxel_size):
    from implicit.solid import as_positive

    if voxel_size is not None and resolution is not None:
        raise ValueError("give at most one of voxel_size, resolution")
    if voxel_size is not None:
        return as_positive(voxel_size, "voxel_size")
    n = DEFAULT_RESOLUTION if resolution is None else resolution
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 8:
        raise ValueError(f"resolution: expected an integer of at least 8, got {n!r}")
    lo = np.minimum(a.bounds[0], b.bounds[0])
    hi = np.maximum(a.bounds[1], b.bounds[1])
    # cells across the smaller part, so a small part is not lost in a big one
    ext = min(float(np.max(a.bounds[1] - a.bounds[0])), float(np.max(b.bounds[1] - b.bounds[0])))
    return min(ext, float(np.max(hi - lo))) / n


def _surface_points(solid, h, mesher):
    m = mesher(solid, h)
    return np.asarray(m.points, dtype=np.float64) if m.n_points else np.zeros((0, 3))


def _project(solid, q):
    """One Newton step of `q` onto the zero set of `solid`."""
    g = solid.gradient(q)
    f = solid(q)
    gg = np.einsum("ij,ij->i", g, g)
    return q - (f / np.where(gg > 1e-20, gg, 1.0))[:, None] * g


def clearance(a, b, h, mesher):
    """Bracket of the minimum distance between two disjoint solids.

    Returns
    -------
    upper, lower : float
    points : (2, 3) float
        Closest points found on `a` and on `b`.
    """
    pa = _surface_points(a, h, mesher)
    pb = _surface_points(b, h, mesher)
    if not (len(pa) and len(pb)):
        raise ValueError("clearance: a solid has no boundary at this voxel_size (refine it)")
    fa_b = a(pb)             # distance-like from a, at b's surface
    fb_a = b(pa)
    lower = max(float(fa_b.min()), float(fb_a.min())) - np.sqrt(3.0) * h
    k = min(CANDIDATES, len(pb))
    qb = pb[np.argpartition(fa_b, k - 1)[:k]]
    k = min(CANDIDATES, len(pa))
    qa = pa[np.argpartition(fb_a, k - 1)[:k]]
    # candidates: start on b (project onto a), and start on a (project onto b)
    on_b = np.concatenate([qb, _project(b, qa)])
    for _ in range(PROJECTION_STEPS):
        on_a = _project(a, on_b)
        on_b = _project(b, on_a)
    on_a = _project(a, _project(a, on_b))
    on_b = _project(b, _project(b, on_b))
    d = np.linalg.norm(on_a - on_b, axis=1)
    # guard: keep only pairs that really sit on both surfaces
    ok = (np.abs(a(on_a)) < 1e-6 * max(h, 1e-12) + 1e-12) & (np.abs(b(on_b)) < 1e-6 * max(h, 1e-12) + 1e-12)
    if ok.any():
        i = int(np.argmin(np.where(ok, d, np.inf)))
        upper = float(d[i])
        pts = np.array([on_a[i], on_b[i]])
    else:  # fall back to the vertices themselves
        i = int(np.argmin(fa_b))
        upper = float(fa_b[i]) + np.sqrt(3.0) * h
        pts = np.array([pb[i], pb[i]])
    return upper, min(max(lower, 0.0), upper), pts


def interference(a, b, *, resolution: int | None = None, voxel_size: float | None = None,
                 tolerance: float | None = None, contact_tolerance: float | None = None,
                 mesher=None) -> Interference:
    """Whether two solids interfere, by how much, and their clearance if not.

    Parameters
    ----------
    a, b : Solid
        Bounded solids.
    resolution : int, optional
        Cells across the smaller part (default 64).
    voxel_size : float, optional
        Cell size (instead of `resolution`).
    tolerance : float, optional
        Relative error wanted on the shared volume (meshes refine until met).
    contact_tolerance : float, optional
        Clearances at most this are contact (default ``1e-6 h``).
    mesher : callable, optional
        ``mesher(solid, h) -> PolyData``; default `spatial.meshing.mesh`.

    Returns
    -------
    Interference

    Examples
    --------
    >>> from implicit import sphere
    >>> r = interference(sphere(1.0), sphere(1.0, center=(3, 0, 0)), resolution=32)
    >>> r.interferes, round(r.clearance, 6)
    (False, 1.0)
    """
    from .mass import _default_mesher, mass_properties

    a = _check_solid(a, "a")
    b = _check_solid(b, "b")
    h = _cell_size(a, b, resolution, voxel_size)
    mesher = mesher or _default_mesher()
    tol = h * 1e-6 if contact_tolerance is None else float(contact_tolerance)
    both = a & b
    lo, hi = both.bounds
    volume = err = 0.0
    overlap = None
    if np.all(lo < hi):
        m = _overlap_mesh(both, h, mesher)
        if m is not None and m.n_cells:
            from ..meshing.arrays import faces_array as _faces_array
            from .mass_core import mesh_moments

            pts, tri = _faces_array(m)
            overlap = (pts.min(axis=0), pts.max(axis=0))
            volume = mesh_moments(pts, tri).volume
            err = abs(volume)
            if volume > 0:
                # the requested cell size, over the overlap; the overlap's own
                # thinnest wall (an annulus of a pin in a hole is thinner than
                # either part) from the deepest sample inside it
                from implicit import box

                # bounds of the overlap itself (a & b's box can be far larger), two cells of margin
                olo, ohi = overlap[0] - 2 * h, overlap[1] + 2 * h
                tight = both & box(ohi - olo, center=0.5 * (olo + ohi))
                cells = max(int(round(float(np.max(ohi - olo)) / h)), 8)
                kw = {"tolerance": tolerance} if tolerance is not None else {"resolution": cells}
                try:
                    props = mass_properties(tight, mesher=mesher, min_wall=_overlap_wall(both, overlap, h),
                                            **kw)
                except ValueError:      # the extrapolation's coarse levels lost the overlap
                    props = None
                if props is not None and props.volume > 0:
                    volume, err = props.volume, props.error.volume
    if volume > 0:
        return Interference(True, False, float(volume), float(err), overlap, 0.0, 0.0, None, float(h))
    upper, lower, pts = clearance(a, b, h, mesher)
    touching = upper <= tol
    possible = bool(not touching and lower <= 0.0)
    if touching or possible:
        # no volume seen, but one thinner than a cell is not excluded: bound it
        err = max(float(err), _unresolved_volume(both, h))
    return Interference(False, bool(touching), float(max(volume, 0.0)), float(err), overlap if touching else None,
                        0.0 if touching else upper, upper - lower, pts, float(h), possible)


def _overlap_wall(both, overlap, h):
    """Half the thickness of the overlap's thickest wall seen on samples of cell `h`
    (twice the deepest value inside), capped by the tree's own estimate."""
    from ..cells.thickness import min_feature_size

    lo, hi = overlap
    axes = [np.arange(lo[i], hi[i] + 0.5 * h, 0.5 * h) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    deepest = float(-np.min(both(grid))) if grid.size else 0.0
    tree = min_feature_size(both)
    # half of it: the coarsest level of the extrapolation then holds 2.4 cells
    # across the wall, enough for its volume to be in the asymptotic range
    return 0.5 * (min(tree, 2.0 * deepest) if deepest > 0 else min(tree, h))


def _unresolved_volume(both, h):
    """Volume of the cells of edge `h` the octree of ``a & b`` cannot prove
    empty: any shared volume lies in them."""
    from ..cells import EMPTY, Octree

    lo, hi = both.bounds
    if not np.all(lo < hi):
        return 0.0
    tree = Octree.from_solid(both, voxel_size=h, progress=False)
    keep = tree.state != EMPTY
    return float(np.sum(np.asarray(tree.size[keep], dtype=np.float64) ** 3))


def _overlap_mesh(both, h, mesher):
    """Boundary mesh of ``a & b``, or None when no sample of the cells that
    may hold its boundary is inside (a mesher may refuse a solid whose
    samples never change sign)."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return mesher(both, h)
    except ValueError:
        from implicit.solid import box_corners

        from ..cells import BOUNDARY, FULL, Octree

        tree = Octree.from_solid(both, voxel_size=h, progress=False)
        if np.any(tree.state == FULL):
            raise
        cells = tree.state == BOUNDARY
        lo = tree.lo[cells]
        hi = lo + tree.size[cells, None]
        probe = np.concatenate([box_corners(lo, hi).reshape(-1, 3), 0.5 * (lo + hi)])
        if probe.shape[0] and float(both(probe).min()) <= 0.0:
            raise
        return None


def box_pairs(lo, hi, *, margin: float = 0.0) -> np.ndarray:
    """Index pairs ``(i, j)``, ``i < j``, of boxes that overlap (sort and sweep).

    Parameters
    ----------
    lo, hi : (n, 3) float
        Box corners.
    margin : float
        Boxes closer than this also count as overlapping.

    Returns
    -------
    (k, 2) int
    """
    lo = np.asarray(lo, dtype=np.float64) - 0.5 * margin
    hi = np.asarray(hi, dtype=np.float64) + 0.5 * margin
    n = lo.shape[0]
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    order = np.argsort(lo[:, 0], kind="stable")
    slo, shi = lo[order], hi[order]
    # for each box in x order, the boxes starting before it ends follow it
    end = np.searchsorted(slo[:, 0], shi[:, 0], side="right")
    count = np.maximum(end - np.arange(n) - 1, 0)
    first = np.repeat(np.arange(n), count)
    offs = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    second = first + 1 + offs
    keep = np.all((slo[second] <= shi[first]) & (slo[first] <= shi[second]), axis=1)
    pairs = np.column_stack([order[first[keep]], order[second[keep]]])
    return np.sort(pairs, axis=1)


@dataclass(frozen=True)
class AssemblyReport:
    """Every interfering pair of an assembly.

    Attributes
    ----------
    parts : int
    pairs_possible : int
        ``n (n - 1) / 2``.
    candidates : int
        Pairs whose bounding boxes overlap.
    full_checks : int
        Pairs checked with `interference` (equal to `candidates`).
    interfering : list of (str, str, Interference)
    touching : list of (str, str, Interference)
    possible_contact : list of (str, str, Interference)
        Pairs whose overlap or contact is below the cell size: neither proven
        nor excluded (see `Interference.possible_contact`).
    """

    parts: int
    pairs_possible: int
    candidates: int
    full_checks: int
    interfering: list = field(default_factory=list)
    touching: list = field(default_factory=list)
    possible_contact: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """Plain-Python form for JSON."""
        return {
            "parts": self.parts, "pairs_possible": self.pairs_possible, "candidates": self.candidates,
            "full_checks": self.full_checks,
            "interfering": [{"a": a, "b": b, **r.to_dict()} for a, b, r in self.interfering],
            "touching": [{"a": a, "b": b, **r.to_dict()} for a, b, r in self.touching],
            "possible_contact": [{"a": a, "b": b, **r.to_dict()} for a, b, r in self.possible_contact],
        }


def check_assembly(parts: dict, *, resolution: int | None = None, voxel_size: float | None = None,
                   mesher=None) -> AssemblyReport:
    """Find every pair of interfering (and touching) parts of an assembly.

    Parameters
    ----------
    parts : dict of str -> Solid
    resolution, voxel_size :
        As for `interference`.

    Returns
    -------
    AssemblyReport

    Examples
    --------
    >>> from implicit import box
    >>> parts = {"a": box(1.0), "b": box(1.0, center=(0.5, 0, 0)), "c": box(1.0, center=(5, 0, 0))}
    >>> report = check_assembly(parts, resolution=16)
    >>> [(a, b) for a, b, _ in report.interfering], report.full_checks
    ([('a', 'b')], 1)
    """
    if not isinstance(parts, dict):
        raise TypeError(f"parts: expected a dict of name -> Solid, got {type(parts).__name__}")
    names = list(parts)
    for name in names:
        _check_solid(parts[name], f"parts[{name!r}]")
    lo = np.array([parts[k].bounds[0] for k in names]).reshape(-1, 3)
    hi = np.array([parts[k].bounds[1] for k in names]).reshape(-1, 3)
    # boxes less than a cell apart are checked too: a gap below the cell
    # size is a possible contact, not a clearance
    if voxel_size is not None:
        margin = float(voxel_size)
    else:
        n_cells = DEFAULT_RESOLUTION if resolution is None else resolution
        margin = float(np.max(hi - lo, axis=1).max()) / max(int(n_cells), 1)
    pairs = box_pairs(lo, hi, margin=margin)
    inter, touch, maybe = [], [], []
    for i, j in pairs:  # one full check per candidate pair (each meshes a solid)
        r = interference(parts[names[i]], parts[names[j]], resolution=resolution, voxel_size=voxel_size,
                         mesher=mesher)
        if r.interferes:
            inter.append((names[i], names[j], r))
        elif r.touching:
            touch.append((names[i], names[j], r))
        elif r.possible_contact:
            maybe.append((names[i], names[j], r))
    n = len(names)
    return AssemblyReport(n, n * (n - 1) // 2, int(len(pairs)), int(len(pairs)), inter, touch, maybe)
