"""The mesh `surface_for_fea` clusters: the feature mesh of the solid, one marching-cubes run.

The feature mesh (`spatial.mesh(..., features=True)`) has a vertex on every
sharp edge and corner of the CSG faces, and lists them (``feature_rank``,
``feature_facets``; `spatial.feature_edges`): the clustering starts from it,
and the same mesh gives the corners that become nodes
(`spatial.fea.surface_corners`).  A single mesh replaces the plain mesh of the
slightly grown solid plus a feature mesh for the corners.

The plain mesh of the solid grown by a twentieth of a voxel remains the start
where the feature mesh is no use: when it is not closed and manifold, or
lists no faces (a tree without facets: a sampled field, a mesh turned solid).
"""

from __future__ import annotations

import numpy as np

from .surface_quality import _is_closed_manifold, mesh_faces

__all__ = ["start_mesh"]

#: Growth of the solid, in voxels, for the plain fallback: faces of a union that touch are 0
#: inside the part, which the plain mesh would show as a crack.
PLAIN_GROWTH = 0.05


def start_mesh(solid, voxel_size, start="features", feature=None):
    """The mesh to cluster and the mesh whose corners become nodes, ``(start, corners, kind)``.

    Parameters
    ----------
    solid : Solid
        A bounded, non-empty solid.
    voxel_size : float
        Voxel of the marching-cubes mesh.
    start : {"features", "plain"}
        The mesh asked for; ``"plain"`` clusters the plain mesh of the grown solid.
    feature : pyvista.PolyData, optional
        The solid's feature mesh at `voxel_size` when made already.

    Returns
    -------
    start : pyvista.PolyData
        The feature mesh, or the plain mesh of the grown solid (see the module).
    corners : pyvista.PolyData
        The feature mesh (the same object as `start` when that is used).
    kind : str
        ``"features"`` or ``"plain"`` (the plain mesh also where the feature mesh cannot start).

    Examples
    --------
    >>> from implicit import box
    >>> start, corners, kind = start_mesh(box(1.0), 0.1)
    >>> kind, start is corners, int((start.point_data["feature_rank"] == 3).sum())
    ('features', True, 8)
    """
    from ..meshing.boundary import mesh as _mesh_solid

    if feature is None:
        feature = _mesh_solid(solid, voxel_size=voxel_size, features=True, progress=False)
    if start == "features" and usable_start(feature):
        return feature, feature, "features"
    from implicit.modifiers import offset as _offset

    plain = _mesh_solid(_offset(solid, PLAIN_GROWTH * voxel_size), voxel_size=voxel_size, features=False,
                        progress=False)
    return plain, feature, "plain"


def usable_start(mesh) -> bool:
    """Whether a feature mesh can start the clustering: triangles, closed and manifold, faces named.

    Examples
    --------
    >>> import pyvista as pv
    >>> usable_start(pv.Sphere())
    False
    """
    if mesh.n_cells == 0 or "feature_rank" not in mesh.point_data or "facet_names" not in mesh.field_data:
        return False
    if len(np.asarray(mesh.field_data["facet_names"]).reshape(-1)) == 0:
        return False
    return _is_closed_manifold(mesh_faces(mesh))
