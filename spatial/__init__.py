"""implicad's spatial side: cells, grids, meshes, analysis, files and the command line."""

from .octree import EMPTY, FULL, BOUNDARY, Octree  # noqa: F401
from .grid import OccupancyGrid  # noqa: F401
from .boundary import mesh  # noqa: F401
from .io import save_mesh, load_mesh, mesh_to_solid, save_vdb, load_vdb  # noqa: F401
from .mass import MassProperties, mass_properties  # noqa: E402,F401
from .analysis import Topology, ValidityReport, topology, check  # noqa: F401
# (the functions `section` and `interference` stay in their modules, whose names they share)
from .section import Section  # noqa: F401
from .interference import Interference, check_assembly  # noqa: F401
from .fea import surface_for_fea, surface_quality, tet_mesh, TetMesh, TetQuality, write_fea  # noqa: F401
from .convert import (  # noqa: F401
    fit_section_curve, loft_sections, fit_star_surface, surface_to_mesh, curve_to_polydata, isoparametric_polydata,
)
