"""Cell decompositions of a solid: the lattice, octree cells, occupancy grids, VDB level sets.

`make_lattice` / `descend` (`lattice`: the regular lattice and its conservative
FULL / EMPTY / BOUNDARY classification by value bounds), `Octree` (`octree`:
the leaves as flat arrays), `OccupancyGrid` (`grid`: dense sampled distances
and their occupancy) and OpenVDB narrow-band level sets and `.vdb` files
(`vdb`: `save_vdb`, `load_vdb`, `mesh_to_solid`; a large grid loads as a
`SparseGridSolid` of its band's tiles, `sparse_grid`), and the thinnest wall of
a solid with the default voxel that resolves it (`thickness`:
`thinnest_wall`, `default_voxel_size`; `walls`: `thin_wall`, the walls a
Boolean, offset or blend thinned, measured on the field).  Above `files` only; the
meshers of the room above reach the cells' ``to_mesh`` methods through
`lattice.provide`.

Examples
--------
>>> from implicit import sphere
>>> from spatial.cells import Octree, BOUNDARY
>>> tree = Octree.from_solid(sphere(1.0), resolution=16)
>>> bool((tree.state == BOUNDARY).any())
True
"""

from .lattice import (BOUNDARY, EMPTY, FULL, STATE_NAMES, CHILD_OFFSETS, Lattice, available_memory,  # noqa: F401
                      check_dense_memory, descend, make_lattice)
from .octree import Octree  # noqa: F401
from .grid import OccupancyGrid  # noqa: F401
from .budget import check_mesh_memory, check_tet_memory, estimate_mesh_bytes  # noqa: F401
from .thickness import default_voxel_size, min_feature_size, sampled_thickness, thinnest_wall  # noqa: F401
from .sparse_grid import SparseGridSolid  # noqa: F401
from .walls import Wall, thin_wall  # noqa: F401
from .vdb import VDB_HALF_WIDTH, import_openvdb, load_vdb, mesh_to_solid, save_vdb, vdb_metadata  # noqa: F401

__all__ = ["BOUNDARY", "EMPTY", "FULL", "STATE_NAMES", "Lattice", "make_lattice", "descend", "Octree",
           "OccupancyGrid", "check_dense_memory", "check_mesh_memory", "check_tet_memory", "estimate_mesh_bytes",
           "available_memory", "save_vdb", "load_vdb", "mesh_to_solid", "vdb_metadata", "import_openvdb",
           "thinnest_wall", "sampled_thickness", "default_voxel_size", "min_feature_size", "SparseGridSolid", "thin_wall", "Wall"]
