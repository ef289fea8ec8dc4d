"""Measurements of solids and meshes: mass properties, sections, interference, validity.

`mass_properties` with error bounds for meshes, grids, octrees and solids
(`mass`, over `mass_core`, `mass_cells`, `mass_solid`), planar sections
(`section`), interference of assemblies (`interference`), the topology and
validity of meshes (`validity`: bodies, genus, Euler-Poincare, `check`) and
the bill of materials of an assembly, shared by drawings' parts lists (`bom`).
Above `meshing`, `cells` and `files`.

Examples
--------
>>> from implicit import box
>>> from spatial.analysis import mass_properties
>>> round(mass_properties(box(2.0), resolution=16).volume, 6)
8.0
"""

from .mass import (MassError, MassProperties, OpenMeshError, ToleranceError, UNITS, mass_properties,  # noqa: F401
                   mesh_moments)
from .validity import Topology, ValidityReport, check, topology, triangle_defects  # noqa: F401
# (the functions `section` and `interference` stay in their modules, whose names they share)
from .section import Section, parse_plane  # noqa: F401
from .interference import Interference, box_pairs, check_assembly  # noqa: F401
from .bom import MATERIALS, BillOfMaterials, BomItem, bill_of_materials  # noqa: F401

__all__ = ["MassProperties", "MassError", "OpenMeshError", "ToleranceError", "UNITS", "mass_properties", "mesh_moments",
           "Topology", "ValidityReport", "check", "topology", "triangle_defects", "Section", "parse_plane", "Interference",
           "box_pairs", "check_assembly", "MATERIALS", "BillOfMaterials", "BomItem", "bill_of_materials"]
