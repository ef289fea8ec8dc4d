"""implicad's spatial side: cells, grids, meshes, analysis, files and the command line.

The package is a house of rooms in layers (docs/ARCHITECTURE.md); a room
imports only from itself and the rooms below it:

==============  ==========================================================
``files``       mesh files, atomic writes, progress bars (bottom)
``cells``       lattice, octree, occupancy grid, OpenVDB level sets
``meshing``     boundary marching cubes, stitching, vertex refinement
``analysis``    mass properties, sections, interference, validity
``convert``     grids and meshes <-> parametric curves and patches
``fea``         FEA surfaces, tetrahedra, quality, solver files
``drafting``    pictures and drawings
``manufacturing`` layer slices, 2.5D milling tool paths, G-code, verification
``inspection``  scans against designs, tolerance stack-up
``distributed`` meshing and mass properties as Dask tasks on a cluster
``compare``     representations compared on one part, the full report
``cli``         the ``implicad`` command (top)
==============  ==========================================================

This module re-exports the public names, so ``spatial.mesh``,
``spatial.mass_properties`` and the rest work as before.
"""

from .cells import EMPTY, FULL, BOUNDARY, Octree, OccupancyGrid  # noqa: F401
from .cells import mesh_to_solid, save_vdb, load_vdb  # noqa: F401
from .cells import min_feature_size  # noqa: F401
from .files import save_mesh, load_mesh  # noqa: F401
from .meshing import mesh as _mesh_here, feature_edges, FeatureCurves  # noqa: F401
from .analysis import MassProperties, ToleranceError, mass_properties as _mass_here  # noqa: F401
from .analysis import Topology, ValidityReport, topology, check, triangle_defects  # noqa: F401
# (the functions `section` and `interference` stay in their modules, whose names they share)
from .analysis import Section  # noqa: F401
from .analysis import Interference, check_assembly  # noqa: F401
from .analysis import BillOfMaterials, bill_of_materials  # noqa: F401
# (`spatial.manufacturing.slice` keeps its room's name: it would hide the built-in here)
from .manufacturing import Slices, ToolPath, Verification, toolpath  # noqa: F401
from .inspection import Inspection, StackUp, Tolerance, stackup  # noqa: F401
from .fea import surface_for_fea, surface_quality, tet_mesh, TetMesh, TetQuality, write_fea  # noqa: F401
from .fea import write_static_deck, run_calculix, read_frd  # noqa: F401
from .convert import (  # noqa: F401
    fit_section_curve, loft_sections, fit_star_surface, surface_to_mesh, curve_to_polydata, isoparametric_polydata,
)
from .drafting import part_drawing, assembly_drawing, write_drawing  # noqa: F401
# (the function `compare` stays in its room, whose name it shares: spatial.compare.compare)
from .compare import brep, half_space_form, Comparison, BRep  # noqa: F401
from .compare.report import report  # noqa: F401
