"""The names the comparison uses from the rooms below it (one place to import them)."""

from ..octree import BOUNDARY, EMPTY, FULL, Octree  # noqa: F401
from ..grid import OccupancyGrid  # noqa: F401
from ..boundary import mesh  # noqa: F401
from ..mass import mass_properties  # noqa: F401
from ..analysis import check, topology  # noqa: F401
from ..io import _atomic_write as atomic_write, save_mesh, save_vdb, load_vdb, import_openvdb  # noqa: F401
from ..progress import progress_bar  # noqa: F401
from ..convert import fit_star_surface, loft_sections, fit_section_curve  # noqa: F401
