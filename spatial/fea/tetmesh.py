"""Tetrahedral meshes of solids for finite-element analysis.

`tet_mesh` remeshes the solid's boundary (`surface_for_fea`), fills it with
TetGen's quality Delaunay refinement (the bulk from a lattice of interior
points clear of the surface, `interior_lattice`), removes the slivers TetGen leaves by
smoothing interior vertices (each candidate position is scored by the worst
dihedral angle of the elements around the vertex), then, for those left, by
boundary vertices sliding on the surface, flips and edge removal
(`sliver_flips.remove_slivers`): TetGen's output turns on the last bits of the
surface's coplanar points, and smoothing alone cannot lift an element whose
nodes all lie on the boundary.  It optionally adds mid-edge
nodes (10-node tetrahedra, boundary mid-nodes projected onto the true
surface), and names the boundary by the CSG facets that make it.

References
----------
H. Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator", ACM TOMS
41(2), 2015, doi:10.1145/2629697.
L. A. Freitag, C. Ollivier-Gooch, "Tetrahedral mesh improvement using swapping
and smoothing", IJNME 40, 1997 (optimisation-based smoothing).
"""

from __future__ import annotations

import os
import tempfile
import time
import warnings
from contextlib import contextmanager

import numpy as np

from implicit.solid import Solid, as_positive
from .facets import FacetField
from .surface import (_deviation, _is_closed_manifold, enclosed as _enclosed, mesh_faces, project_to_surface,
                      self_intersections, surface_for_fea)
from .cavities import cavity_points
from .curved import OFF_SURFACE, curve_boundary
from .boundary_repair import slide_boundary_nodes
from .graded_surface import CAP_FACTOR, QUALITY_CAPS, graded_surface, poor_element_nodes, surface_info
from .size_field import curvature_size
from .resolve import resolving_field
from .model import SIDE_NODES, TetMesh, _side_nodes  # noqa: F401
from .quality import radius_edge_ratio, tet_quality, tet_volumes
from .slivers import boundary_faces, improve, peel
from .sliver_flips import remove_slivers

__all__ = ["TetMesh", "tet_mesh", "MeshQualityError", "MeshQualityWarning", "SIDE_NODES"]


#: Volume of a regular tetrahedron of unit edge.
_REGULAR_VOLUME = 1.0 / (6.0 * np.sqrt(2.0))


#: Keep the remeshed surface as it is (TetGen -Y): its points stay on the true surface.
#: Without it TetGen splits boundary triangles and leaves flat slivers on the boundary
#: (274 elements under 5 degrees on a torus at size 0.08, none with it).
_KEEP_SURFACE = "Y"


@contextmanager
def _scratch_directory():
    """Run in a temporary working directory: TetGen drops files such as
    ``tetgen-tmpfile_skipped.node`` into the current one when it gives up on faces."""
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="implicad-tetgen-") as tmp:
        os.chdir(tmp)
        try:
            yield
        finally:
            os.chdir(old)


class MeshQualityError(ValueError):
    """The mesh misses the asked quality or volume (raised unless ``allow_poor=True``)."""


class MeshQualityWarning(UserWarning):
    """The mesher stopped short of the asked quality (e.g. at its Steiner-point cap)."""


# ---------------------------------------------------------------------------
# boundary, quadratic nodes, sets
# ---------------------------------------------------------------------------

def _name_sets(ff, points, boundary, boundary_side, boundary_element, tets):
    """Face sets (by deciding facet at each face centre) and node sets."""
    centres = points[boundary].mean(axis=1)
    onsurf = project_to_surface(ff.solid, centres, steps=2)
    _, dec, _ = ff(onsurf)
    face_sets = {"surface": np.arange(len(boundary))}
    node_sets = {}
    side_all = _side_nodes(tets, boundary_element, boundary_side)
    node_sets["surface"] = np.unique(side_all)
    # Facets sharing a name (coplanar faces a family named alike) make one set.
    named = np.array(ff.names, dtype=object)[dec]
    for name in sorted(set(named)):
        sel = np.nonzero(named == name)[0]
        face_sets[name] = sel
        node_sets[name] = np.unique(side_all[sel])
    return face_sets, node_sets


# ---------------------------------------------------------------------------
# the mesher
# ---------------------------------------------------------------------------

def tet_mesh(solid, *, size, order=1, min_dihedral=10.0, radius_edge=3.0, max_dihedral=165.0,
             surface=None, steiner_cap=None, volume_tolerance=0.005, allow_poor=False, seed=0,
             reference_volume=None, _graded=None) -> TetMesh:
    """Tetrahedral mesh of `solid` with elements of edge length about `size`.

    Parameters
    ----------
    solid : Solid
        A bounded solid.
    size : float
        Target edge length (surface and volume).
    order : {1, 2}
        4-node (linear) or 10-node (quadratic) tetrahedra; quadratic boundary
        mid-edge nodes lie on the true surface (on the feature curve for an
        edge along a sharp edge).
    min_dihedral, max_dihedral : float
        Dihedral angles (degrees) every element should keep within.
    radius_edge : float
        Largest circumradius-to-shortest-edge ratio (> 1), kept by the
        smoothing and checked on the result.  TetGen is asked for at most
        `TETGEN_RADIUS_EDGE`; elements whose shortest edge is an edge of the
        surface (which TetGen keeps) can stay above it, hence the default 3.
    surface : pyvista.PolyData, optional
        A closed boundary to fill; by default ``surface_for_fea(solid, size=size)``.
    steiner_cap : int, optional
        Most points TetGen may add (default: 20 times the expected node count).
    volume_tolerance : float
        Allowed relative difference between the mesh volume and the solid's
        volume (measured on its own meshes, see Notes).
    allow_poor : bool
        Warn (`MeshQualityWarning`) instead of raising `MeshQualityError`
        when a dihedral angle, radius-edge ratio or the volume misses what
        was asked.
    reference_volume : float, optional
        The solid's volume when known (skips measuring it).
    seed : int
        Seed of the smoothing's random trial positions.

    Returns
    -------
    TetMesh

    Raises
    ------
    TypeError
        When `solid` is not a Solid.
    ValueError
        On a bad option value or an inverted element.
    MeshQualityError
        (a ValueError) When the asked quality was not reached (TetGen
        stopped at its Steiner-point cap, dihedral angles or radius-edge
        ratios out of bounds) or the volume check fails, unless `allow_poor`.

    Warns
    -----
    MeshQualityWarning
        With `allow_poor`, for each check that failed.

    Notes
    -----
    The volume check compares the mesh volume (curved elements integrated
    for order 2) with the solid's own volume to ``ESTIMATE_SHARE *
    volume_tolerance``: the thin-shell corrected volume of the feature mesh the
    surface is clustered from, its error read from the shell's two quadratures
    and its tilt on that mesh (`spatial.analysis.mass_shell.volume_on_one_level`);
    where that error misses, with two coarser feature meshes as
    `spatial.analysis.mass_properties` measures for a tolerance
    (`spatial.analysis.mass_solid.volume_on_finest`, the error from the levels'
    steps), levels of their own where those cannot serve (`solid_volume`),
    the mass properties at 128 cells where even those miss.  Not a figure
    derived from the mesh's boundary: a boundary that cuts a corner or misses
    a concave edge shows up.  The tolerance is `volume_tolerance` plus the
    estimate's own error.  When the surface cannot be remeshed free of self-intersections
    at `size`, or its enclosed volume misses the solid's by more than that
    tolerance (times `order`: a part as thin as `size`), the surface is
    remeshed finer (`size` / 1.25, / 1.25^2 ...) and ``info["surface_size"]``
    says so.  For order 2, a flat boundary element in the way of a curved edge (its corners on a
    hole's rim) is removed so that every boundary mid-edge node lies on the surface with every
    Jacobian proven positive: ``info["removed_for_curving"]`` counts them, ``info["off_surface_nodes"]``
    the nodes still left on their chord.  ``info["lattice_points"]`` counts the interior lattice
    points given to TetGen (none with a graded size).  A graded part (gaps narrower than `size`)
    whose elements miss the quality is meshed again with its size field capped around them
    (`spatial.fea.graded_surface.QUALITY_CAPS` times at most; ``info["quality_caps"]``).
    ``info["seconds"]`` holds the wall-clock time of the stages (surface, tetgen, smoothing, checks).

    Examples
    --------
    >>> from implicit import sphere
    >>> m = tet_mesh(sphere(1.0), size=0.4)          # doctest: +SKIP
    >>> m.quality.min_dihedral >= 10.0               # doctest: +SKIP
    True
    """
    import pyvista as pv

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    size = as_positive(size, "size")
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order: expected 1 or 2, got {order!r}")
    min_dihedral = as_positive(min_dihedral, "min_dihedral", allow_zero=True)
    max_dihedral = as_positive(max_dihedral, "max_dihedral")
    if not 0 <= min_dihedral < 70.5:
        raise ValueError(f"min_dihedral: expected degrees in [0, 70.5), got {min_dihedral!r}")
    if not 70.6 < max_dihedral <= 180:
        raise ValueError(f"max_dihedral: expected degrees in (70.6, 180], got {max_dihedral!r}")
    radius_edge = as_positive(radius_edge, "radius_edge")
    if radius_edge <= 1.0:
        raise ValueError(f"radius_edge: expected a ratio > 1 (TetGen does not terminate below), got {radius_edge!r}")
    volume_tolerance = as_positive(volume_tolerance, "volume_tolerance")
    if surface is not None and not isinstance(surface, pv.PolyData):
        raise TypeError(f"surface: expected a pyvista.PolyData, got {type(surface).__name__}")
    if steiner_cap is not None and (isinstance(steiner_cap, bool) or not isinstance(steiner_cap, (int, np.integer)) or steiner_cap < 0):
        raise ValueError(f"steiner_cap: expected a non-negative integer, got {steiner_cap!r}")
    if not solid.is_bounded or solid.is_empty_bounds:
        raise ValueError("solid: expected a bounded, non-empty solid")
    field = None
    if surface is None:
        # A gap narrower than the size (between gear teeth) would be bridged: a size graded from
        # it (spatial.fea.graded), refused before any work where even that cannot follow it.
        field = resolving_field(solid, size) if _graded is None else _graded[0]

    import tetgen

    info = {}
    clock = [time.perf_counter()]
    estimate = None
    if surface is None:
        known = (reference_volume, 0.0) if _graded is None else _graded[2]
        # 10-node elements: edges short enough for their mid nodes to go onto curved faces
        surface, info["surface_size"], (estimate, est_err) = _surface_for(
            solid, size if order == 1 else curvature_size(solid, size), known, volume_tolerance, order, field)
        info.update(surface_info(surface))
        if "clusters" in surface.field_data:  # confined to the faces or free (surface_for_fea)
            info["surface_clusters"] = str(np.asarray(surface.field_data["clusters"]).reshape(-1)[0])
        sfaces = mesh_faces(surface)
    else:
        # TetGen aborts the whole process on such input: check it first.
        sfaces = mesh_faces(surface)
        if len(sfaces) == 0 or not _is_closed_manifold(sfaces):
            raise ValueError("surface: expected a closed, manifold triangle surface")
        crossing = self_intersections(surface)
        if crossing:
            raise ValueError(f"surface: {crossing} triangles intersect others; TetGen needs a surface "
                             "free of self-intersections")
    spts = np.asarray(surface.points, dtype=np.float64)
    enclosed = abs(_enclosed(surface))
    expected_nodes = int(enclosed / (_REGULAR_VOLUME * size**3) / 5.0) + len(spts)
    cap = int(steiner_cap) if steiner_cap is not None else 20 * expected_nodes + 1000
    clock.append(time.perf_counter())
    # TetGen's own refinement inserts its interior points one by one, rejecting those that encroach
    # on the kept surface: most of its time.  A lattice clear of the surface fills the bulk at once.
    inner = interior_lattice(solid, spts, size) if field is None or field.uniform else np.zeros((0, 3))
    if len(inner) < LATTICE_MIN_POINTS:
        inner = np.zeros((0, 3))  # a few points (a beam 10 thick at size 5: 19) do not pay for the change
    info["lattice_points"] = int(len(inner))
    tg = tetgen.TetGen(np.concatenate([spts, inner]), sfaces.astype(np.int32))
    # A void inside the part (an inner shell) would come back filled: TetGen floods only from outside.
    for hole in cavity_points(spts, sfaces):
        tg.add_hole(hole)
    # (Order 2 keeps the regular volume: with the larger one the benchmark part at 0.2 left a mid node off its surface.)
    volume = _REGULAR_VOLUME * size**3 * (LATTICE_VOLUME_FACTOR if len(inner) and order == 1 else 1.0)
    switches = (f"pq{min(radius_edge, TETGEN_RADIUS_EDGE):g}/{min(min_dihedral, TETGEN_MIN_DIHEDRAL):g}a{volume:.6g}"
                f"o/{max_dihedral:g}{TETGEN_OPTIMIZE}S{cap}{_KEEP_SURFACE}Q")
    try:
        with _scratch_directory(), _native_stdout_silenced():
            nodes, elems, *_ = tg.tetrahedralize(switches=switches)
    except RuntimeError as exc:
        raise ValueError(f"surface: TetGen could not mesh it ({exc}); is it closed and free of "
                         "self-intersections (see self_intersections)?") from exc
    nodes = np.asarray(nodes, dtype=np.float64)
    elems = np.asarray(elems, dtype=np.int64)
    if len(elems) == 0:
        raise ValueError("solid: TetGen made no elements (the surface may intersect itself)")
    vol = tet_volumes(nodes, elems)
    neg = vol < 0
    elems[neg] = elems[neg][:, [0, 2, 1, 3]]
    info.update({"tetgen_switches": switches, "steiner_cap": cap, "tetgen_points": int(len(nodes)),
                 "surface_points": int(len(spts))})
    cap_hit = len(nodes) - len(spts) >= cap
    # Boundary nodes stay; interior nodes are smoothed to remove slivers.
    bfaces, belem, bside = boundary_faces(elems)
    movable = np.ones(len(nodes), dtype=bool)
    movable[np.unique(bfaces)] = False
    # With -Y TetGen keeps the surface; count any point it still had to add on it.
    info["boundary_steiner_points"] = int(np.setdiff1d(np.unique(bfaces), np.arange(len(spts))).size)
    clock.append(time.perf_counter())
    # (The smoothing keeps every element's score up to date: the same figures as a pass of `element_score`.)
    nodes, scores = improve(nodes, elems, movable, min_dihedral, max_dihedral, seed=seed, radius_edge=radius_edge,
                            with_scores=True)
    if np.any(scores < min_dihedral):
        # Slivers lying on the boundary: let boundary vertices off the sharp edges slide on the surface.
        _, _, fv = FacetField(solid, split_sides=field is not None)(nodes)
        on_feature = (np.abs(fv) < 1e-7 * max(size, 1.0)).sum(axis=0) >= 2
        slide = ~movable & ~on_feature
        nodes = improve(nodes, elems, movable | slide, min_dihedral, max_dihedral, seed=seed + 1,
                         solid=solid, slide=slide, radius_edge=radius_edge, scores=scores)
        info["boundary_slid"] = True
        elems, peeled = peel(nodes, elems, min_dihedral, max_dihedral)
        if peeled:
            info["peeled"] = peeled
            bfaces, belem, bside = boundary_faces(elems)
        nodes, elems, counts = remove_slivers(nodes, elems, movable | slide, min_dihedral, max_dihedral,
                                              radius_edge=radius_edge, seed=seed + 2, solid=solid, slide=slide,
                                              rounds=SLIVER_ROUNDS)
        info.update({k: v for k, v in counts.items() if v})
        nodes, info["boundary_moves"] = slide_boundary_nodes(nodes, elems, solid, slide, min_dihedral, max_dihedral, radius_edge)
        if counts["flips"] or counts["inserted_points"]:
            bfaces, belem, bside = boundary_faces(elems)
    clock.append(time.perf_counter())
    if np.any(tet_volumes(nodes, elems) <= 0):
        raise ValueError("tet_mesh: an element is inverted after meshing (zero or negative volume)")
    tets = elems
    if order == 2:
        # A mid node that cannot go onto the surface without folding an element may take a flat
        # boundary element away with it (its two other sides become the boundary).
        nodes, tets, elems, removed = curve_boundary(solid, FacetField(solid), nodes, elems, bfaces, size)
        if removed:
            info["removed_for_curving"] = removed
            bfaces, belem, bside = boundary_faces(elems)
    ff = FacetField(solid)
    face_sets, node_sets = _name_sets(ff, nodes, bfaces, bside, belem, tets)
    quality = tet_quality(nodes, tets, min_dihedral=min_dihedral)
    if quality.min_scaled_jacobian <= 0:
        raise ValueError(f"tet_mesh: inverted element (scaled Jacobian {quality.min_scaled_jacobian:.3g})")
    # Volume check against the solid's own volume (not one derived from the mesh's boundary).
    if estimate is None:
        estimate, est_err = _solid_volume(solid, reference_volume, volume_tolerance)
    rel = abs(quality.volume - estimate) / max(abs(estimate), 1e-300)
    info.update(volume_estimate=estimate, volume_error=rel, volume_estimate_error=est_err, cap_hit=bool(cap_hit))
    bnodes = np.unique(bfaces)
    remap = np.zeros(len(nodes), dtype=np.int64)
    remap[bnodes] = np.arange(bnodes.size)
    dev = _deviation(solid, nodes[bnodes], remap[bfaces])
    # Mid-edge nodes left on their chord (moving them would fold an element) are counted, not hidden.
    on_boundary = node_sets["surface"]
    info["off_surface_nodes"] = int((np.abs(solid(nodes[on_boundary])) > OFF_SURFACE * size).sum())
    problems = []
    if cap_hit:
        problems.append(f"TetGen stopped at its Steiner-point cap ({cap} points); raise steiner_cap or size")
    if quality.min_dihedral < min_dihedral - 1e-9 or quality.max_dihedral > max_dihedral + 1e-9:
        problems.append(f"dihedral angles {quality.min_dihedral:.2f}..{quality.max_dihedral:.2f} deg outside the asked "
                        f"{min_dihedral:g}..{max_dihedral:g} ({quality.n_below} elements below)")
    if quality.max_radius_edge > radius_edge + 1e-9:
        n_over = int((radius_edge_ratio(nodes, tets) > radius_edge + 1e-9).sum())
        problems.append(f"radius-edge ratio up to {quality.max_radius_edge:.3f}, over the asked {radius_edge:g} "
                        f"({n_over} elements)")
    if rel > volume_tolerance + est_err:
        problems.append(f"mesh volume {quality.volume:.6g} differs from the solid's {estimate:.6g} (mass properties) "
                        f"by {100 * rel:.2f} percent; use a smaller size")
    info["problems"] = problems
    clock.append(time.perf_counter())
    # Wall-clock seconds of the stages (the surface includes the solid's volume when not given).
    info["seconds"] = dict(zip(("surface", "tetgen", "smoothing", "checks"), np.diff(clock).tolist()))
    caps = 0 if _graded is None else _graded[1]
    if problems and field is not None and caps < QUALITY_CAPS and not cap_hit and rel <= volume_tolerance + est_err:
        # A graded part: the field capped around the elements that miss the quality, meshed again.
        where = poor_element_nodes(nodes, tets, min_dihedral, max_dihedral, radius_edge)
        return tet_mesh(solid, size=size, order=order, min_dihedral=min_dihedral, radius_edge=radius_edge,
                        max_dihedral=max_dihedral, steiner_cap=steiner_cap, volume_tolerance=volume_tolerance,
                        allow_poor=allow_poor, seed=seed,
                        _graded=(field.refined(where, CAP_FACTOR * field(where)), caps + 1, (estimate, est_err)))
    info["quality_caps"] = caps
    if problems and not allow_poor:
        raise MeshQualityError("tet_mesh: " + "; ".join(problems) + " (allow_poor=True keeps such a mesh)")
    for msg in problems:
        warnings.warn(msg, MeshQualityWarning, stacklevel=2)
    return TetMesh(points=nodes, tets=tets, boundary=bfaces, boundary_element=belem, boundary_side=bside,
                   face_sets=face_sets, node_sets=node_sets, quality=quality, surface_deviation=dev, info=info)


#: TetGen's mesh optimisation (-O: flip level / operations) and vertex smoothing (-s: criterion /
#: iterations) switches.
TETGEN_OPTIMIZE = "O9/7"

#: The radius-edge ratio TetGen refines to at most.
TETGEN_RADIUS_EDGE = 1.5
#: The smallest dihedral angle TetGen is asked for at most: its refinement need not end for
#: bounds much above 10 to 18 degrees; the smoothing and the final check take care of the rest.
TETGEN_MIN_DIHEDRAL = 10.0

#: Rounds of flips and smoothing with fresh random trials for slivers left after the first smoothing
#: (each only while some are left).
SLIVER_ROUNDS = 3

#: Finer surface sizes tried, as factors of `size`, when the surface intersects itself at `size`.
SURFACE_RETRIES = (1.0, 0.8, 0.64, 0.512)


#: Spacing of the body-centred cubic lattice of interior points, as a factor of `size`.
LATTICE_SPACING = 1.0
#: Fewest lattice points worth giving TetGen; below it TetGen refines the volume on its own as before.
LATTICE_MIN_POINTS = 200
#: TetGen's volume bound beside the lattice, as a factor of the regular tetrahedron's of edge `size`: with
#: 1.5 the median edge is `size` (benchmark part at 0.08: 0.080, 19,070 elements; with 1: 0.077, 23,769;
#: TetGen's own refinement of the bulk: 0.074, 25,759).
LATTICE_VOLUME_FACTOR = 1.5
#: Least distance of a lattice point from the surface (field value and nearest surface vertex), times `size`.
LATTICE_CLEARANCE = 0.6


def interior_lattice(solid, surface_points, size):
    """Points of a body-centred cubic lattice of spacing ``LATTICE_SPACING * size`` inside `solid`,
    at least ``LATTICE_CLEARANCE * size`` from its boundary and from the `surface_points`.

    TetGen keeps them as nodes and fills the gap to the surface by its own refinement; the
    cube's sides and half diagonals make edges of 0.87 to 1 times `size`.

    Examples
    --------
    >>> from implicit import box
    >>> corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    >>> interior_lattice(box(2.0), corners, 1.0).tolist()
    [[0.0, 0.0, 0.0]]
    """
    from scipy.spatial import cKDTree

    step = LATTICE_SPACING * size
    lo, hi = surface_points.min(axis=0), surface_points.max(axis=0)
    axes = [np.arange(lo[i] + 0.5 * step, hi[i], step) for i in range(3)]
    cube = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    pts = np.concatenate([cube, cube + 0.5 * step])
    clear = LATTICE_CLEARANCE * size
    pts = pts[np.asarray(solid(pts)) < -clear]
    if len(pts):
        dist, _ = cKDTree(surface_points).query(pts, distance_upper_bound=clear)
        pts = pts[~np.isfinite(dist)]
    return pts


def _surface_for(solid, size, known, tolerance, order, field=None):
    """`surface_for_fea` at `size`, or at the first finer size of `SURFACE_RETRIES` whose surface
    is free of self-intersections (sharp features closer than `size` need more vertices) and
    encloses the solid's volume within ``(tolerance + its estimate's error) * order`` (a surface
    that cuts across a wall as thick as `size` misses a good part of it; order 2 adds the
    curvature the chords miss).  The last surface that intersects nothing is kept when none does
    both; the volume check of the mesh then reports it.  A graded `field` (`spatial.fea.graded`)
    is capped at `size` and scaled along.

    `known` is ``(volume, relative error)``, the volume None when it is to be measured: then on
    the first surface's feature mesh (`volume_on_one_level`, else `volume_on_finest`, else
    `_solid_volume`).  Returns the surface, its size and
    ``(volume, relative error)``.
    """
    from ..analysis.mass_shell import volume_on_one_level
    from ..analysis.mass_solid import volume_on_finest
    from ..meshing.boundary import mesh as _mesh_solid

    err = None
    kept = None
    for factor in SURFACE_RETRIES:
        feature = None
        if field is None:
            # The feature mesh `surface_for_fea` starts from, made here so that the volume is measured on it too.
            feature = _mesh_solid(solid, voxel_size=size * factor / 4.0, features=True, progress=False)
        try:
            if field is None:
                surface = surface_for_fea(solid, size=size * factor, feature_mesh=feature)
            else:
                # Snapping and relaxing move vertices by up to a fraction of the size: the smallest one.
                graded = field.capped(size).scaled(factor)
                surface = graded_surface(solid, graded)  # capped locally where it crosses itself
        except ValueError as exc:
            if "self-intersecting" not in str(exc):
                raise
            err = exc
            surface = None
        if known[0] is None:
            got = None
            # (a surface started from the feature mesh found it closed and manifold: `usable_start`)
            closed = surface is not None and surface_info(surface).get("surface_start") == "features"
            if feature is not None and (closed or _is_closed_manifold(mesh_faces(feature))):
                # The feature mesh alone where its shell vouches for it (7 field values a triangle), else
                # with two coarser levels (meshed after the surface, not on a thread beside it: the two
                # took turns at the interpreter's lock and both ran slower).
                h, share = size * factor / 4.0, ESTIMATE_SHARE * tolerance
                got = volume_on_one_level(solid, feature, h, tolerance=share)
                if got is None:
                    got = volume_on_finest(solid, feature, h, tolerance=share)
            # where the surface's feature mesh cannot give it: levels of their own
            known = got if got is not None else _solid_volume(solid, None, tolerance)
        if surface is None:
            continue
        volume, allowed = known[0], (tolerance + known[1]) * order
        kept = surface, size * factor, known
        if abs(abs(_enclosed(surface)) - volume) <= allowed * max(abs(volume), 1e-300):
            return kept
    if kept is not None:
        return kept
    raise err


#: Share of `tet_mesh`'s `volume_tolerance` the solid's volume estimate may take (the check allows
#: the tolerance plus the estimate's error): 1e-3 of the volume at the default tolerance.
ESTIMATE_SHARE = 0.2


def _solid_volume(solid, known=None, tolerance=0.005):
    """The solid's volume and its relative error estimate, within ``ESTIMATE_SHARE * tolerance``.

    Measured on the solid's feature meshes, thin-shell corrected, at the levels `mass_properties`
    takes for a tolerance, only the volume (`spatial.analysis.mass_solid.solid_volume`; `tet_mesh`
    first tries the surface's own feature mesh as the finest level, `volume_on_finest`).  Where
    that tolerance cannot be reached, the mass properties at 128 cells across and the error they reach.
    """
    if known is not None:
        return float(known), 0.0
    from ..analysis.mass import ToleranceError, mass_properties
    from ..analysis.mass_solid import solid_volume

    try:
        return solid_volume(solid, tolerance=ESTIMATE_SHARE * tolerance)
    except ToleranceError:
        mp = mass_properties(solid, resolution=128, mesher=_quiet_mesher)
        return float(mp.volume), float(mp.relative_error())


def _quiet_mesher(solid, h):
    from ..meshing.boundary import mesh

    return mesh(solid, voxel_size=h, progress=False, features=False)  # mass_properties' own plain mesher


@contextmanager
def _native_stdout_silenced():
    """Send file descriptor 1 to /dev/null: the TetGen wrapper prints from C++
    ("parsing switches", "success") even with its quiet switch."""
    import sys

    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):  # no real stdout (captured, closed)
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
