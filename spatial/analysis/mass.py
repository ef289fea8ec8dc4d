"""Mass properties with known error: `mass_properties` of a mesh, grid, octree or solid.

The integrals, results and error bounds are in `spatial.analysis.mass_core`;
grids and octrees in `mass_cells`, solids in `mass_solid`.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..meshing.arrays import faces_array as _faces_array
from .mass_core import (DEFAULT_TOLERANCE, MAX_CELLS, MIN_CELLS, SAFETY, UNITS, MassError, MassProperties,  # noqa: F401
                        OpenMeshError, ToleranceError, _check_closed, _check_density_units, _finish, _Raw,
                        mesh_moments)

__all__ = ["MassProperties", "MassError", "mass_properties", "mesh_moments", "UNITS", "OpenMeshError",
           "ToleranceError"]


def _kind(obj) -> str:
    from implicit import Solid

    if isinstance(obj, Solid):
        return "solid"
    name = type(obj).__name__
    mod = type(obj).__module__ or ""
    if mod.startswith("pyvista") or name == "PolyData":
        return "mesh"
    if all(hasattr(obj, a) for a in ("lo", "size", "state")):
        return "octree"
    if all(hasattr(obj, a) for a in ("origin", "voxel_size", "distance")):
        return "grid"
    return ""


def mass_properties(obj, *, density: float = 1.0, units: str = "m",
                    tolerance: float | None = None, voxel_size: float | None = None,
                    resolution: int | None = None, solid=None, mesher=None,
                    min_wall: float | None = None, moments=None, progress=None) -> MassProperties:
    """Volume, mass, area, centroid and inertia of a solid, with error bounds.

    Parameters
    ----------
    obj : pyvista.PolyData, OccupancyGrid, Octree or Solid
        A closed outward-oriented triangle mesh (integrated exactly), an
        occupancy grid or octree (FULL cells exactly, BOUNDARY cells by
        fractional occupancy), or a solid (meshed and extrapolated, see Notes).
    density : float
        kg / m^3 (default 1: then `mass` is the volume in m^3 times 1 kg/m^3).
    units : {'m', 'cm', 'mm', 'in', 'ft'}
        Length unit of the model's coordinates.
    tolerance : float, optional
        Solids only: relative volume error to reach (default 1e-4 when
        neither `voxel_size` nor `resolution` is given).
    voxel_size : float, optional
        Solids only: cell size of the finest mesh.
    resolution : int, optional
        Solids only: cells across the largest extent of the finest mesh.
    solid : Solid, optional
        Octrees only: the field whose distances weigh the BOUNDARY cells
        (default the octree's own ``solid`` attribute when it has one).
    mesher : callable, optional
        ``mesher(solid, h) -> PolyData``; default `spatial.meshing.mesh`
        with sharp edges rebuilt when the levels follow a tolerance of at
        least `mass_solid.FEATURE_FLOOR`, plain otherwise (see Notes).
    min_wall : float, optional
        Solids only: the thinnest wall the meshes must hold (default
        `spatial.cells.thickness.min_feature_size` of the tree); the
        coarsest level gets at least 1.2 cells across it.
    moments : callable, optional
        Solids only: ``moments(solid, h, center) -> (14,)`` raw moments of a
        level's corrected mesh (`mass_solid.level_moments`), computed
        elsewhere -- `spatial.distributed` sums them over bricks on a cluster.
    progress : bool or None
        Solids only: the default meshers' progress bar (None: only on a
        terminal), as `spatial.meshing.mesh`'s.

    Returns
    -------
    MassProperties

    Notes
    -----
    For a solid, meshes at ``N/4``, ``N/2`` and ``N`` cells get the thin-shell
    correction of `spatial.analysis.mass_solid.shell_correction`.

    With only a tolerance (the default), ``N`` starts from the part's size and
    its thinnest wall and doubles until the estimate meets it; the meshes have
    their sharp edges rebuilt (`mass_solid.feature_mesher`), whose corrected
    volume converges as h^3 on sharp parts and h^4 on smooth ones, and the
    finest level is reported with ``max(4 |d1| / (r - 1), sqrt(|d1 d2|))``
    per raw moment (``d1 = Q_N - Q_{N/2}``, ``d2 = Q_{N/2} - Q_{N/4}``, ``r``
    their ratio taken between 2 and 4), the volume's at least
    `mass_solid.FEATURE_FLOOR` of it: a 100 x 100 x 1 plate meets 1e-4
    at 480 cells, where the plain mesh's bevels are refused.  A thin part's
    levels may go beyond `MAX_CELLS` while a level's estimated triangles fit
    `mass_solid.FEATURE_TRIANGLES`.

    With a `resolution` or `voxel_size`, a `mesher`, `moments` (a cluster's
    bricks, never fused for the feature pass) or a tolerance below
    `mass_solid.FEATURE_FLOOR`, the meshes are plain marching
    cubes (fourth order on smooth surfaces, second order at sharp edges with
    the correction) and the raw moments are extrapolated,
    ``(4 Q_N - Q_{N/2}) / 3``, with the estimate
    ``max(4 |R_N - R_{N/2}|, |Q_N - Q_{N/2}| / 12)`` per raw moment.

    Either estimate is propagated to every quantity; it is an estimate, not a
    proof, and held against the closed forms of the reference parts, and of
    random boxes and plates up to 100:1, in the tests.

    Examples
    --------
    >>> import pyvista as pv
    >>> from spatial.analysis.mass import mass_properties
    >>> props = mass_properties(pv.Box((0, 2, 0, 1, 0, 1)).triangulate())
    >>> round(props.volume, 12), props.centroid.tolist()
    (2.0, [1.0, 0.5, 0.5])
    """
    _check_density_units(density, units)
    kind = _kind(obj)
    if not kind:
        raise TypeError(f"obj: expected a pyvista.PolyData, OccupancyGrid, Octree or Solid, got {type(obj).__name__}")
    given = [k for k, v in (("tolerance", tolerance), ("voxel_size", voxel_size), ("resolution", resolution))
             if v is not None]
    if len(given) > 1:
        raise ValueError(f"give at most one of tolerance, voxel_size, resolution; got {', '.join(given)}")
    if kind != "solid" and given:
        raise ValueError(f"{given[0]}: only applies to a Solid; a {kind} is integrated as it is")
    if kind == "mesh":
        pts, tri = _faces_array(obj)
        raw = mesh_moments(pts, tri)
        return _finish(raw, density, units, 0.0, "mesh (divergence theorem)")
    if kind == "grid":
        from .mass_cells import _grid_raw

        raw, h = _grid_raw(obj)
        return _finish(raw, density, units, h, "grid (fractional occupancy)")
    if kind == "octree":
        from .mass_cells import _octree_raw

        sol = solid if solid is not None else getattr(obj, "solid", None)
        raw, h = _octree_raw(obj, sol)
        return _finish(raw, density, units, h, "octree (exact FULL cells, fractional BOUNDARY cells)")
    if progress is not None and not isinstance(progress, (bool, np.bool_)):
        raise TypeError(f"progress: expected True, False or None, got {progress!r}")
    if progress is not None and kind != "solid":
        raise ValueError(f"progress: only applies to a Solid; a {kind} is integrated as it is")
    if min_wall is not None:
        if kind != "solid":
            raise ValueError(f"min_wall: only applies to a Solid; a {kind} is integrated as it is")
        from implicit.solid import as_positive

        min_wall = as_positive(min_wall, "min_wall")
    return _solid_mass(obj, density, units, tolerance, voxel_size, resolution, mesher, min_wall, moments,
                       progress)


def _solid_mass(solid, density, units, tolerance, voxel_size, resolution, mesher, min_wall=None, moments=None,
                progress=None):
    if not solid.is_bounded:
        raise ValueError("solid: expected a bounded solid, got infinite bounds (intersect it with a box)")
    if solid.is_empty_bounds:
        raise ValueError("solid: its bounds are empty (the solid holds nothing)")
    lo, hi = solid.bounds
    extent = float(np.max(hi - lo))
    cells = None
    if resolution is not None:
        if isinstance(resolution, bool) or not isinstance(resolution, (numbers.Integral,)):
            raise TypeError(f"resolution: expected an integer number of cells, got {resolution!r}")
        if resolution < 8:
            raise ValueError(f"resolution: expected at least 8 cells, got {resolution}")
        cells = int(resolution)
    elif voxel_size is not None:
        from implicit.solid import as_positive

        h = as_positive(voxel_size, "voxel_size")
        cells = max(int(round(extent / h)), 8)
    else:
        from implicit.solid import as_positive

        tol = DEFAULT_TOLERANCE if tolerance is None else as_positive(tolerance, "tolerance")
        if tol >= 1:
            raise ValueError(f"tolerance: expected a relative error below 1, got {tol:g}")
        tolerance = tol
    from .mass_solid import FEATURE_FLOOR, _solid_raw, default_mesher, feature_mesher

    # The levels it chooses itself are meshed with their sharp edges rebuilt, unless the tolerance lies
    # below what their estimate claims; a resolution, a mesher or a cluster's moments keep the plain
    # meshes' extrapolation.
    features = cells is None and mesher is None and moments is None and tolerance >= FEATURE_FLOOR
    if mesher is None:
        mesher = feature_mesher(progress) if features else default_mesher(progress)
    raw, h, n, note = _solid_raw(solid, cells=cells, tolerance=tolerance, mesher=mesher, wall=min_wall,
                                 moments=moments, features=features)
    how = ("meshes with sharp edges rebuilt", "the finest level, error from the steps") if features else \
        ("marching cubes", "Richardson")
    return _finish(raw, density, units, h, f"solid: corrected {how[0]} at {n // 4}, {n // 2}, {n} "
                                           f"cells + {how[1]}{note}")


def _default_mesher():
    """``mesher(solid, h) -> PolyData``: `spatial.meshing.mesh` at cell size h."""
    from .mass_solid import default_mesher

    return default_mesher()
