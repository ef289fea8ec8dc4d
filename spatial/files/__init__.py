"""What reaches the user's disk and terminal: mesh files, atomic writes, progress bars.

`atomic_write` (a file appears whole or not at all: written under a temporary
name beside the target, then renamed), `save_mesh` / `load_mesh` for triangle
meshes (STL, PLY, OBJ, VTP, VTK) and `progress_bar` (tqdm on a terminal,
silent otherwise).  The bottom room of `spatial`: it imports no other room.

Examples
--------
>>> from spatial.files import MESH_FORMATS
>>> ".stl" in MESH_FORMATS
True
"""

from .atomic import atomic_write, clean_stale_temporaries  # noqa: F401
from .meshes import MESH_FORMATS, load_mesh, mesh_format, save_mesh  # noqa: F401
from .progress import progress_bar  # noqa: F401

__all__ = ["atomic_write", "clean_stale_temporaries", "MESH_FORMATS", "load_mesh", "mesh_format", "save_mesh", "progress_bar"]
