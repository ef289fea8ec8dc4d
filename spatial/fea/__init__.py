"""Meshes for finite-element analysis: surfaces, tetrahedra, their quality and solver files.

* `surface_for_fea`, `surface_quality`, `self_intersections`, `FacetField`
  (`surface`, over `facets`): boundary surfaces fit for volume meshing, and the
  CSG faces that name boundary regions;
* `tet_mesh`, `TetMesh`, `MeshQualityWarning` (`tetmesh`, `model`): 4- and
  10-node tetrahedra with node and element-side sets;
* `tet_quality`, `TetQuality` (`quality`): dihedral angles,
  radius-edge ratios, scaled Jacobians;
* `write_fea`, `FEA_FORMATS` (`files`): Gmsh, Abaqus / CalculiX, VTU,
  Nastran, STL / PLY.

Examples
--------
>>> from implicit import sphere
>>> from spatial.fea import tet_mesh, write_fea
>>> mesh = tet_mesh(sphere(1.0), size=0.2, order=2)     # doctest: +SKIP
>>> write_fea(mesh, "ball.inp")                          # doctest: +SKIP
'ball.inp'
"""

from .surface import FacetField, facet_field, project_to_surface, self_intersections, surface_for_fea, \
    surface_quality, SurfaceQuality
from .quality import TetQuality, tet_quality, dihedral_angles, radius_edge_ratio, scaled_jacobian
from .tetmesh import MeshQualityWarning, TetMesh, tet_mesh
from .files import FEA_FORMATS, write_fea, to_meshio

__all__ = [
    "FacetField", "facet_field", "project_to_surface", "self_intersections", "surface_for_fea",
    "surface_quality", "SurfaceQuality", "TetQuality", "tet_quality", "dihedral_angles",
    "radius_edge_ratio", "scaled_jacobian", "MeshQualityWarning", "TetMesh", "tet_mesh",
    "FEA_FORMATS", "write_fea", "to_meshio",
]
