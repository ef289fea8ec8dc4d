"""Meshes for finite-element analysis: surfaces, tetrahedra, their quality and solver files.

* `surface_for_fea`, `surface_quality`, `self_intersections`, `FacetField`
  (`surface`, over `facets`): boundary surfaces fit for volume meshing, and the
  CSG faces that name boundary regions;
* `tet_mesh`, `TetMesh`, `MeshQualityWarning` (`tetmesh`, `model`): 4- and
  10-node tetrahedra with node and element-side sets;
* `tet_quality`, `TetQuality` (`quality`): dihedral angles,
  radius-edge ratios, scaled Jacobians;
* `write_fea`, `FEA_FORMATS`, `set_names` (`files`, over `abaqus` and
  `nastran`): Gmsh 4.1 / 2.2, Abaqus / CalculiX, VTU, Nastran, MED, STL / PLY;
* `narrowest_gap`, `check_resolvable` (`resolve`): sizes that cannot follow a
  part's narrowest gap, refused before meshing;
* `surface_size`, `narrow_widths` (`size_field`): gaps and walls measured by
  rays on the solid's field, and the surface size that follows them;
* `write_static_deck`, `Material`, `MATERIALS`, `parse_material`,
  `parse_load` (`deck`): ready-to-run linear-static CalculiX / Abaqus decks;
* `run_calculix`, `StaticResult` (`solve`) and `read_frd` (`frd`): CalculiX
  runs and its results read back into pyvista.

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
from .files import FEA_FORMATS, set_names, write_fea, to_meshio
from .deck import MATERIALS, Material, face_nodal_loads, parse_load, parse_material, static_deck_text, \
    write_static_deck
from .frd import read_frd, von_mises
from .solve import StaticResult, calculix_path, run_calculix
from .resolve import check_resolvable, narrowest_gap
from .size_field import narrow_widths, surface_size
from .jacobian_bounds import jacobian_sign

__all__ = [
    "FacetField", "facet_field", "project_to_surface", "self_intersections", "surface_for_fea",
    "surface_quality", "SurfaceQuality", "TetQuality", "tet_quality", "dihedral_angles",
    "radius_edge_ratio", "scaled_jacobian", "MeshQualityWarning", "TetMesh", "tet_mesh",
    "FEA_FORMATS", "set_names", "write_fea", "to_meshio", "MATERIALS", "Material", "face_nodal_loads", "parse_load", "static_deck_text",
    "parse_material", "write_static_deck", "read_frd", "von_mises", "StaticResult", "calculix_path",
    "run_calculix", "check_resolvable", "narrowest_gap", "jacobian_sign", "narrow_widths", "surface_size",
]
