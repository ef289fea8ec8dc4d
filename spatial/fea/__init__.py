"""Meshes for finite-element analysis: one import for the FEA tools.

* `surface_for_fea`, `surface_quality`, `self_intersections`, `FacetField`
  (`spatial.fea_surface`): boundary surfaces fit for volume meshing, and the
  CSG faces that name boundary regions;
* `tet_mesh`, `TetMesh`, `MeshQualityWarning` (`spatial.tetmesh`): 4- and
  10-node tetrahedra with node and element-side sets;
* `tet_quality`, `TetQuality` (`spatial.tet_quality`): dihedral angles,
  radius-edge ratios, scaled Jacobians;
* `write_fea`, `FEA_FORMATS` (`spatial.fea_io`): Gmsh, Abaqus / CalculiX, VTU,
  Nastran, STL / PLY.

Examples
--------
>>> from implicit import sphere
>>> from spatial.fea import tet_mesh, write_fea
>>> mesh = tet_mesh(sphere(1.0), size=0.2, order=2)     # doctest: +SKIP
>>> write_fea(mesh, "ball.inp")                          # doctest: +SKIP
'ball.inp'
"""

from .fea_surface import FacetField, facet_field, project_to_surface, self_intersections, surface_for_fea, \
    surface_quality, SurfaceQuality
from .tet_quality import TetQuality, tet_quality, dihedral_angles, radius_edge_ratio, scaled_jacobian
from .tetmesh import MeshQualityWarning, TetMesh, tet_mesh
from .fea_io import FEA_FORMATS, write_fea, to_meshio

__all__ = [
    "FacetField", "facet_field", "project_to_surface", "self_intersections", "surface_for_fea",
    "surface_quality", "SurfaceQuality", "TetQuality", "tet_quality", "dihedral_angles",
    "radius_edge_ratio", "scaled_jacobian", "MeshQualityWarning", "TetMesh", "tet_mesh",
    "FEA_FORMATS", "write_fea", "to_meshio",
]
