"""Mass properties of solids: corrected meshes at three levels, and their error.

Each level meshes the solid (`spatial.meshing.mesh`), integrates the mesh
exactly (divergence theorem) and adds the thin shell between the mesh and the
true surface (`shell_correction`).  Levels at ``N/4``, ``N/2`` and ``N`` cells
chosen for a tolerance are meshed with sharp edges rebuilt (`feature_mesher`)
and the finest is reported with an estimate from the steps between them
(`_feature_estimate`); plain marching-cubes levels (a given resolution, a
cluster's bricks) are Richardson-extrapolated and the spread of the
extrapolations gives the error estimate (`_extrapolate`).
`spatial.analysis.mass.mass_properties` is the entry point.
"""

from __future__ import annotations

import numpy as np

from .mass_area import true_area
from .mass_core import (_EPS, MAX_CELLS, MAX_WALL_CELLS, MIN_CELLS, SAFETY, WALL_CELLS, ToleranceError,
                        _check_closed, _corners, _faces_array, _moments_of, _Raw)

__all__ = ["shell_correction", "default_mesher", "feature_mesher", "level_moments", "volume_moments", "solid_volume",
           "volume_on_finest"]

#: Safety factor of the feature meshes' error estimate (`_feature_estimate`).
FEATURE_SAFETY = 4.0

#: Most triangles (estimated from the area) of a feature level finer than `MAX_CELLS`: a thin part's
#: levels start where its wall asks (538 cells for a 100 x 100 x 1 plate turned), and one level further
#: (1076 cells: 6.3 M triangles, 2.0 GB resident, 59 s wall on 2 cores at a load of 14) may still fit
#: where a stout part's would not.
FEATURE_TRIANGLES = 8_000_000

#: Least relative volume error the feature meshes' estimate claims: their error does not vanish as h
#: does -- the rebuilt edges leave 2e-7 to 7e-6 of a thin plate's volume at any level (5e-6 at 380, 538
#: and 760 cells of a 100 x 100 x 1 plate turned 30 degrees about x and y) -- so two levels may agree
#: below it by chance.  Three times the worst measured.
FEATURE_FLOOR = 2e-5


def default_mesher(progress=None):
    """``mesher(solid, h) -> PolyData``: the plain `spatial.meshing.mesh` at cell size h.

    Plain (``features=False``), not the feature mesh users get by default: the
    extrapolation and its error estimate follow the marching-cubes mesh's error
    as h halves (the shell correction makes it fourth order on smooth faces and a
    clean second order at edges), the cluster integrates bricks that are never
    fused (the feature pass needs the whole mesh) and must agree with this path
    to rounding, and the plain mesh costs less.
    """
    from ..meshing.boundary import mesh

    def mesher(solid, h):
        return mesh(solid, voxel_size=h, progress=progress, features=False)
    return mesher


def feature_mesher(progress=None):
    """``mesher(solid, h) -> PolyData``: `spatial.meshing.mesh` with its sharp edges and corners rebuilt.

    The mesher of `mass_properties` when it chooses its own levels: with the
    edges rebuilt the thin-shell corrected volume converges as h^3 on parts
    with sharp edges (h^4 on smooth ones) where the plain mesh's bevels leave
    an uneven h^2 (a 100 x 100 x 1 plate: 1.1e-6 against 1.6e-4 at 480
    cells), so a thin plate meets 1e-4 at the cells its wall asks for.  Its
    error follows no single power of h (the chord terms of curved faces and
    the rebuilt edges mix), hence its own estimate, `_feature_estimate`.
    """
    from ..meshing.boundary import mesh

    def mesher(solid, h):
        return mesh(solid, voxel_size=h, progress=progress, features=True)
    return mesher


def shell_correction(solid, points, triangles, *, center) -> np.ndarray:
    """Moments of the thin shell between a triangle mesh and the true surface.

    The surface lies at height ``t = -f`` (the field's value, an exact
    distance or a bound of it) outward of each point of the mesh; the shell
    adds ``int_T t dA`` to the volume, ``int_T t x dA`` to the first moment
    and ``int_T t x x^T dA`` to the second, each integrated over a triangle
    by the edge-midpoint rule ``A/3 (g(m_ab) + g(m_bc) + g(m_ca))`` (exact
    for quadratic ``g``).  With vertices on the surface this lifts the
    volume of a marching-cubes mesh of a smooth part from second to fourth
    order, and sharp edges keep a clean second order.

    Parameters
    ----------
    solid : Solid
    points : (n, 3) float
    triangles : (m, 3) int
    center : (3,) float
        Reference point of the moments.

    Returns
    -------
    (13,) float
        Corrections of ``(V, m1, M2.ravel())``.
    """
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    c0 = np.asarray(center, dtype=np.float64)
    a, b, c, _, area = _corners(pts, tri, c0)
    return _shell_of(solid, a, b, c, area, c0)


def _shell_of(solid, a, b, c, area, c0):
    # every triangle's three edge midpoints, relative to c0, as (3, 3m) rows
    # (a shared edge is evaluated twice: cheaper than sorting the edges)
    x = np.concatenate([a + b, b + c, c + a], axis=1)
    x *= 0.5
    w = np.tile(area / 3.0, 3) * -solid((x.T + c0))
    wx = x * w
    return np.concatenate([[w.sum()], wx.sum(axis=1), (wx @ x.T).ravel()])


def _solid_level(solid, h, c0, mesher, correct=True, check=False, area=True) -> np.ndarray:
    """Raw moments (14,) of the corrected mesh of `solid` at cell size `h`."""
    mesh = mesher(solid, h)
    if mesh.n_cells == 0:     # a feature thinner than this level's cells
        return np.zeros(14)
    pts, tri = _faces_array(mesh)
    if check:
        _check_closed(tri, pts.shape[0])
    return level_moments(solid, pts, tri, c0, voxel_size=h, correct=correct, area=area)


def level_moments(solid, pts, tri, c0, *, voxel_size, correct=True, vertex_normals=None, area=True) -> np.ndarray:
    """Raw moments (14,) of the triangles `tri` of `pts` about `c0`: thin-shell corrected, with the true area.

    The moments are sums over the triangles, so those of a mesh cut in parts
    are the sum of the parts' (`spatial.distributed` adds them up brick by
    brick).  The true area weighs each triangle with the normals of its
    vertices, which a part only knows from its own triangles: a part passes
    the whole mesh's (`vertex_normals`, see `mass_area.true_area`) to get
    the whole mesh's weights.  Without `area` the last moment is the mesh's
    own area (the true area costs ten times the rest; a volume needs none of it).
    """
    h = voxel_size
    kernels = _kernels()
    if kernels is not None:
        level, shell = kernels
        vec, mids, weights = level(np.ascontiguousarray(pts), np.ascontiguousarray(tri), c0)
        if correct:
            vec[:13] += shell(mids, weights * -solid(mids), c0)
    else:
        a, b, c, cross, area = _corners(pts, tri, c0)
        vec = _moments_of(a, b, c, cross, area, c0).vector()
        if correct:
            vec[:13] += _shell_of(solid, a, b, c, area, c0)
    if correct and area:
        # the true surface's area over the mesh, not the mesh's own (bevelled at every sharp edge)
        vec[13] = true_area(solid, pts, tri, voxel_size=h, vertex_normals=vertex_normals)
    return vec


_KERNELS: list = []


def _kernels():
    """numba versions of the per-triangle sums (one pass, no temporaries),
    or None without numba (the numpy path computes the same sums)."""
    if _KERNELS:
        return _KERNELS[0]
    try:
        from .mass_kernels import level, shell
    except ImportError:  # pragma: no cover - numba is a dependency
        _KERNELS.append(None)
        return None
    _KERNELS.append((level, shell))
    return _KERNELS[0]


def _solid_raw(solid, *, cells=None, tolerance=None, mesher=None, wall=None, moments=None, features=False):
    """Raw moments of a solid from three levels of meshes, with an error estimate.

    With `cells` fixed, meshes at ``cells/4``, ``cells/2`` and ``cells``.
    With `tolerance`, starts at `MIN_CELLS` and doubles until the estimated
    volume error is below ``tolerance * volume``; `ToleranceError` when the
    finest level allowed does not get there.  Either way the coarsest level
    gets at least `WALL_CELLS` cells across the thinnest wall
    (`spatial.cells.thickness.min_feature_size`): coarser levels would lose
    the wall and wreck the extrapolation, so the levels are refined.

    Returns
    -------
    (_Raw, float, int, str)
        Moments and errors, the finest cell size, its cells across and a
        note on the levels (why they were refined, or "").

    `moments(solid, h, c0)`, when given, computes a level's raw moments in
    place of meshing it here.  With `features` the levels are meshed with
    their sharp edges rebuilt (`feature_mesher`, unless `mesher` or
    `moments` is given) and estimated by `_feature_estimate` in place of
    Richardson's extrapolation; the levels asked are the same.
    """
    from ..cells.thickness import min_feature_size

    mesher = mesher or (feature_mesher() if features else default_mesher())
    extrapolate = _feature_estimate if features else _extrapolate
    if moments is None:
        def moments(solid, h, c0):
            return _solid_level(solid, h, c0, mesher)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    extent = float(np.max(hi - lo))
    c0 = 0.5 * (lo + hi)
    wall = min_feature_size(solid) if wall is None else float(wall)
    need = int(np.ceil(4 * WALL_CELLS * extent / wall))
    note = ""
    if need > MAX_WALL_CELLS:
        raise ValueError(f"solid: its thinnest wall ({wall:.3g}) needs at least {need} cells across its "
                         f"extent {extent:.3g} for the coarsest extrapolation level to hold it (at most "
                         f"{MAX_WALL_CELLS}); measure a mesh of it instead, or thicken the wall")
    if cells is not None:
        if cells < need:
            note = f"; cells raised from {cells} to {need} for the thinnest wall {wall:.3g}"
            cells = need
        levels = [max(int(round(cells / 4)), 2), max(int(round(cells / 2)), 4), int(cells)]
    else:
        finest = max(MIN_CELLS, need)
        if finest > MIN_CELLS:
            note = f"; levels from {finest} cells for the thinnest wall {wall:.3g}"
        levels = [max(finest // 4, 2), max(finest // 2, 4), finest]
    last = max(MAX_CELLS, levels[-1])
    vecs = [_coarse_level(solid, extent / n, c0, moments) for n in levels[:-1]]
    vecs.append(moments(solid, extent / levels[-1], c0))
    while True:
        est, err = extrapolate(vecs)
        err = _honest(est, err, lo, hi, c0)
        if cells is not None or err[0] <= tolerance * abs(est[0]):
            break
        if levels[-1] >= last and not (features and _fits(est[13], extent / (2 * levels[-1]))):
            rel = err[0] / max(abs(est[0]), 1e-300)
            raise ToleranceError(f"mass_properties: tolerance {tolerance:g} not reached: estimated relative "
                                 f"volume error {rel:.2g} at {levels[-1]} cells, the finest allowed (ask for "
                                 f"a larger tolerance, or a resolution to accept its error)",
                                 tolerance=tolerance, estimate=rel, cells=levels[-1])
        levels.append(levels[-1] * 2)
        vecs.append(moments(solid, extent / levels[-1], c0))
    return _Raw.from_vector(c0, est, err), extent / levels[-1], levels[-1], note


def _fits(area, h):
    """Whether a feature level of cell size h fits `FEATURE_TRIANGLES` (3.5 triangles per h^2 of
    surface: 3.35 measured on a plate turned 30 degrees, 2.0 on one in the lattice planes)."""
    return 3.5 * abs(area) / (h * h) <= FEATURE_TRIANGLES


def _honest(est, err, lo, hi, c0):
    """Floors under the per-moment error estimates.

    An error of volume ``dV`` anywhere in the box moves the first moment by
    up to ``dV |x - c0|`` and the second by ``dV |x - c0|^2``: the moments'
    estimates may not claim less than that (their own extrapolations can
    agree by chance, e.g. on a symmetric part, while the volume's do not).
    Round-off of the sums is a floor for all.
    """
    half = 0.5 * (hi - lo)
    out = err.copy()
    ev = max(err[0], 64 * _EPS * abs(est[0]))
    out[0] = ev
    out[1:4] = np.maximum(err[1:4], ev * half)
    out[4:13] = np.maximum(err[4:13], ev * np.outer(half, half).ravel())
    scale = np.concatenate([[abs(est[0])], abs(est[0]) * half, abs(est[0]) * np.outer(half, half).ravel(),
                            [abs(est[13])]])
    return np.maximum(out, 64 * _EPS * scale)


def _feature_estimate(vecs):
    """The finest level's moments, unextrapolated, and an error estimate that
    holds for any rate of convergence from h^0.5 to h^4.

    With ``d1 = Q_N - Q_{N/2}`` and ``d2 = Q_{N/2} - Q_{N/4}``, a clean law
    ``e = C h^p`` gives ``e_N = d1 / (2^p - 1)``: the rate is read from
    ``d2 / d1`` but taken between 1 and 2 (an apparent h^3 or h^4 claims no
    more than h^2), times `FEATURE_SAFETY`.  Under it stands
    ``sqrt(|d1 d2|) = e_N (2^p - 1) 2^(p/2)``, at least ``e_N`` for any
    p >= 0.5, for where the finest two levels agree by chance: a plate's
    rebuilt edges fall differently on each lattice, and its error does not
    always shrink from one level to the next (-1.6e-6, -1.1e-6 of the
    100 x 100 x 1 plate's volume at 240 and 480 cells).  The volume's never
    claims less than `FEATURE_FLOOR` of the volume: below it the rebuilt
    edges leave an error that no longer shrinks with h.
    """
    q4, q2, q1 = vecs[-3], vecs[-2], vecs[-1]
    d1, d2 = q1 - q2, q2 - q4
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(d1 * d2 > 0, d2 / d1, 2.0)
    ratio = np.clip(np.nan_to_num(ratio, nan=2.0, posinf=4.0), 2.0, 4.0)
    err = np.maximum(FEATURE_SAFETY * np.abs(d1) / (ratio - 1.0), np.sqrt(np.abs(d1 * d2)))
    err[0] = max(err[0], FEATURE_FLOOR * abs(q1[0]))      # the moments follow it in `_honest`
    est = q1.copy()
    # the area as in `_extrapolate`: the finest level's, three times its step or the step below
    err[13] = max(3.0 * abs(d1[13]), abs(d2[13]))
    return est, err


def _coarse_level(solid, h, c0, moments):
    """A coarse level of the extrapolation: cells too big to resolve a thin
    part may leave no boundary (or make the mesher give up); such a level
    counts as empty, which the error estimate then reflects."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return moments(solid, h, c0)
    except ValueError:
        return np.zeros(14)


def _extrapolate(vecs):
    """Richardson ``(4 Q_N - Q_{N/2}) / 3`` with an error estimate from the
    previous level's extrapolation."""
    q4, q2, q1 = vecs[-3], vecs[-2], vecs[-1]
    r1 = (4.0 * q1 - q2) / 3.0
    r2 = (4.0 * q2 - q4) / 3.0
    plain = np.abs(q1 - q2) / 3.0
    err = np.maximum(SAFETY * np.abs(r1 - r2), plain / 4.0)
    # (the floor: extrapolation gains at least 4x over the plain estimate; two
    # extrapolations may agree by chance, see examples/bracket.py at 64 cells)
    # The area is the true surface's over each mesh (`mass_area`); what it
    # leaves at sharp edges shrinks about as h, unevenly (where an edge falls
    # between nodes changes from level to level): no extrapolation, the
    # finest level's value, bounded by three times its difference to the
    # level below (the error when the rate is 1.5 or better) or the
    # difference below that, whichever is larger.
    d1, d2 = abs(q1[13] - q2[13]), abs(q2[13] - q4[13])
    r1[13] = q1[13]
    err[13] = max(3.0 * d1, d2)
    return r1, err


def volume_moments(features=True, progress=False):
    """``moments(solid, h, c0) -> (14,)``: a level's corrected raw moments as `_solid_raw` takes them,
    from the feature mesh (`feature_mesher`; plain with ``features=False``), without the true area.

    The last moment is the mesh's own area: a check of the volume needs no area, and the true area
    (`mass_area.true_area`) costs ten times the rest of a level's sums.  `_solid_raw` only reads it to
    bound a thin part's finest level (`_fits`), which the mesh's area, a little smaller, does too.
    """
    mesher = feature_mesher(progress) if features else default_mesher(progress)

    def moments(solid, h, c0):
        return _solid_level(solid, h, c0, mesher, area=False)
    return moments


def solid_volume(solid, *, tolerance, finest=None, voxel_size=None, progress=False):
    """The volume of `solid` and its relative error estimate, to `tolerance`, at the least cost.

    The levels and the estimate are those of `mass_properties` for a tolerance (feature meshes,
    `_feature_estimate`; plain meshes and Richardson's below `FEATURE_FLOOR`), with only the volume
    wanted: no true area (`volume_moments`).  `finest`, a closed feature mesh of the solid made
    already at `voxel_size` (the start of `spatial.fea`'s surfaces), is taken as the finest level
    where `volume_on_finest` can (the coarsest level holds the thinnest wall and the estimate
    meets `tolerance`); else the levels `mass_properties` would choose.

    Parameters
    ----------
    solid : Solid
        A bounded, non-empty solid.
    tolerance : float
        Relative volume error to reach, in (0, 1).
    finest : pyvista.PolyData, optional
        ``spatial.mesh(solid, voxel_size=voxel_size, features=True)``, closed, when made already.
    voxel_size : float, optional
        Its voxel (needed with `finest`).
    progress : bool
        The meshers' progress bars.

    Returns
    -------
    (float, float)
        The volume and its estimated relative error (at most `tolerance`).

    Raises
    ------
    ToleranceError
        When the finest level allowed does not reach `tolerance` (as `mass_properties`).

    Examples
    --------
    >>> from implicit import box
    >>> v, err = solid_volume(box(2.0), tolerance=1e-3)
    >>> round(v, 6), err <= 1e-3
    (8.0, True)
    """
    tolerance = _relative_tolerance(tolerance)
    if finest is not None:
        if voxel_size is None:
            raise ValueError("voxel_size: needed with finest (the voxel it was meshed at)")
        got = volume_on_finest(solid, finest, voxel_size, tolerance=tolerance, progress=progress)
        if got is not None:
            return got
    features = tolerance >= FEATURE_FLOOR
    raw, _, _, _ = _solid_raw(solid, tolerance=tolerance, moments=volume_moments(features, progress),
                              features=features)
    return float(raw.volume), float(raw.e_volume / abs(raw.volume)) if raw.volume else float("inf")


def volume_on_finest(solid, finest, voxel_size, *, tolerance, progress=False):
    """The volume of `solid` and its relative error from its feature mesh `finest` at `voxel_size`
    and the feature meshes at twice and four times that voxel (`_feature_estimate`, volume only),
    or None when the coarsest of them would not hold the thinnest wall (`WALL_CELLS` across it),
    the estimate misses `tolerance` or the tolerance lies below `FEATURE_FLOOR`.

    It changes no global state (no warnings filters, unlike `_coarse_level`): it may run in a
    thread beside other work.

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing.boundary import mesh
    >>> fine = mesh(box(2.0), voxel_size=0.1, features=True, progress=False)
    >>> v, err = volume_on_finest(box(2.0), fine, 0.1, tolerance=1e-3)
    >>> round(v, 6), err <= 1e-3
    (8.0, True)
    """
    from ..cells.thickness import min_feature_size

    tolerance = _relative_tolerance(tolerance)
    h = float(voxel_size)
    if tolerance < FEATURE_FLOOR or finest.n_cells == 0 or 4 * h * WALL_CELLS > min_feature_size(solid):
        return None
    moments = volume_moments(True, progress)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    c0 = 0.5 * (lo + hi)
    vecs = []
    for coarse in (4 * h, 2 * h):
        try:
            vecs.append(moments(solid, coarse, c0))
        except ValueError:  # the mesher gave up at these cells: an empty level, as `_coarse_level` counts it
            vecs.append(np.zeros(14))
    pts, tri = _faces_array(finest)
    vecs.append(level_moments(solid, pts, tri, c0, voxel_size=h, area=False))
    est, err = _feature_estimate(vecs)
    err = _honest(est, err, lo, hi, c0)
    if not err[0] <= tolerance * abs(est[0]):
        return None
    return float(est[0]), float(err[0] / abs(est[0]))


def _relative_tolerance(tolerance):
    from implicit.solid import as_positive

    tolerance = as_positive(tolerance, "tolerance")
    if tolerance >= 1:
        raise ValueError(f"tolerance: expected a relative error below 1, got {tolerance:g}")
    return tolerance


# ---------------------------------------------------------------------------


_default_mesher = default_mesher
