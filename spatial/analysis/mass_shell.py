"""A solid's volume from one corrected feature mesh, its error read from the shell itself.

The thin-shell corrected volume of a feature mesh (`mass_solid.level_moments`) adds, over each
triangle, the height t = -f of the true surface above it by the edge-midpoint rule q2 (exact for
heights quadratic over the triangle).  Its error has two parts, both measurable on the same mesh:

- the rule's own error, where the height is not quadratic over a triangle (a bevelled edge, a
  corner, a face curving fast at the cell size): the difference to the rule exact for cubics,
  ``q3 = A (sum t(v) / 20 + 2/15 sum t(m) + 9/20 t(c))`` (vertices, edge midpoints, centroid);
- the tilt of the shell: its height is measured along the field's gradient, not the triangle's
  normal, and the prisms over neighbouring triangles overlap or leave wedges; both are second
  order in the angle between triangle and surface, about 4 t / e for a height t over an edge e,
  hence ``8 |q2| (t_max / e)^2`` (on a sphere: the measured error of the corrected level, 0.1
  to 1 times this term, at 10 to 40 cells across).

`volume_on_one_level` sums both over the triangles without letting them cancel, times
`FEATURE_SAFETY`, with `FEATURE_FLOOR` of the volume under it: 7 field values per triangle and
no coarser mesh, where `volume_on_finest` meshes the solid twice more (levels at 2 and 4 times
the voxel).  Its claims, on feature meshes of the benchmark part, a sphere, a torus, a cylinder,
a beam and the gear example at 10 to 200 cells across, on their plain (bevelled) meshes and on
meshes scaled by 1.001 and 1.01: 2.1 to 1,700 times the actual error, never under it; the
benchmark part's mesh at the voxel of its FEA surface at size 0.08: 2.1e-5 against an actual
7.9e-6 (the three levels: 1.1e-4).  A mesh off the surface (scaled by 1.01) claims 1 to 94 % and
is refused at 1e-3, but the sphere's at 10 cells across (7.7e-4; its actual error 9.5e-5).
"""

from __future__ import annotations

import numpy as np

from .mass_core import _EPS, WALL_CELLS
from .mass_solid import FEATURE_FLOOR, FEATURE_SAFETY, _kernels, _relative_tolerance

__all__ = ["volume_on_one_level"]


def volume_on_one_level(solid, mesh, voxel_size, *, tolerance):
    """The volume of `solid` from its closed feature mesh `mesh` at `voxel_size` alone, and its
    relative error from the shell's two quadratures and its tilt (see the module), or None when
    that error misses `tolerance`, the tolerance lies below `FEATURE_FLOOR`, the mesh is empty or
    its voxel would not hold the thinnest wall (`WALL_CELLS` across it).

    The volume is the thin-shell corrected volume of `mesh`, the value
    ``level_moments(solid, pts, tri, c0, voxel_size=voxel_size, area=False)[0]`` to the bit (`c0`
    the centre of the solid's bounds), as `volume_on_finest` reports it.

    Examples
    --------
    >>> from implicit import sphere
    >>> from spatial.meshing.boundary import mesh
    >>> fine = mesh(sphere(1.0), voxel_size=0.05, features=True, progress=False)
    >>> v, err = volume_on_one_level(sphere(1.0), fine, 0.05, tolerance=1e-3)
    >>> abs(v / (4 / 3 * np.pi) - 1) < err <= 1e-4
    True
    """
    from ..cells.thickness import min_feature_size

    tolerance = _relative_tolerance(tolerance)
    kernels = _kernels()
    h = float(voxel_size)
    if kernels is None or tolerance < FEATURE_FLOOR or mesh.n_cells == 0 or h * WALL_CELLS > min_feature_size(solid):
        return None
    from .mass_kernels import centroids, shell_error

    level, shell = kernels
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    c0 = 0.5 * (lo + hi)
    pts, tri = _triangles(mesh)
    # the level as `level_moments` sums it (the same operations: the same bits)
    vec, mids, weights = level(pts, tri, c0)
    t_mid = -np.asarray(solid(mids), dtype=np.float64)
    vec[:13] += shell(mids, weights * t_mid, c0)
    volume = float(vec[0])
    t_vert = -np.asarray(solid(pts), dtype=np.float64)
    t_cen = -np.asarray(solid(centroids(pts, tri)), dtype=np.float64)
    quad, tilt = shell_error(pts, tri, weights, t_mid, t_vert, t_cen)
    err = max(FEATURE_SAFETY * (quad + tilt), FEATURE_FLOOR * abs(volume), 64 * _EPS * abs(volume))
    if not volume or not np.isfinite(err) or not err <= tolerance * abs(volume):
        return None
    return volume, float(err / abs(volume))


def _triangles(mesh):
    """Points and triangles of `mesh` as `mass_core._faces_array` gives them (the same arrays), the
    triangles read from the cells' connectivity rather than the legacy ``faces`` copy VTK builds."""
    if mesh.n_points == 0 or mesh.n_lines or mesh.n_verts or mesh.n_strips or not mesh.is_all_triangles:
        raise ValueError("mesh: expected a closed triangle mesh")
    pts = np.ascontiguousarray(mesh.points, dtype=np.float64)
    return pts, np.ascontiguousarray(np.asarray(mesh.regular_faces).astype(np.int64))
