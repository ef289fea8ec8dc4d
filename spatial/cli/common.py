"""What every `implicad` command shares: the common flags, model and mesh input, warnings, JSON.

* `add_common_flags`: ``--json`` (one object on stdout, nothing else),
  ``--quiet`` (no progress bar; ``--no-progress`` is the same) and
  ``--progress`` (always a bar); a bar otherwise shows on a terminal.
* `load_solid` / `load_target`: a model file (``.py``, ``.json``) or a closed
  mesh file (STL, PLY, OBJ, VTP, VTK) read as a solid (an OpenVDB level set
  of the mesh) -- every command that reads a model reads a mesh too.
* `install_warning_handler`: Python warnings reach the terminal as one line
  each, ``implicad: warning: ...``, without file path or source line.
"""

from __future__ import annotations

import os
import sys
import warnings

__all__ = ["MESH_SUFFIXES", "MESH_SOLID_RESOLUTION", "add_common_flags", "is_mesh_file", "load_solid",
           "load_target", "load_model_and_units", "install_warning_handler", "progress_of"]

MESH_SUFFIXES = (".stl", ".ply", ".obj", ".vtp", ".vtk")
#: Voxels across the largest extent of a mesh read as a solid.
MESH_SOLID_RESOLUTION = 128


def _has(parser, flag):
    return flag in parser._option_string_actions  # argparse keeps no public lookup


def add_common_flags(parser) -> None:
    """Add ``--json``, ``--quiet`` / ``--no-progress`` and ``--progress`` where the command lacks them."""
    if not _has(parser, "--json"):
        parser.add_argument("--json", action="store_true", help="print one JSON object on stdout, nothing else")
    for flag in ("--quiet", "--no-progress"):
        if not _has(parser, flag):
            parser.add_argument(flag, dest="progress", action="store_const", const=False,
                                help="never show a progress bar")
    if not _has(parser, "--progress"):
        parser.add_argument("--progress", dest="progress", action="store_const", const=True,
                            help="always show a progress bar (default: on a terminal)")
    parser.set_defaults(progress=None)


def progress_of(args):
    """The progress option of parsed `args` (False under ``--json``)."""
    if getattr(args, "json", False):
        return False
    return getattr(args, "progress", None)


def is_mesh_file(path) -> bool:
    return os.path.splitext(str(path))[1].lower() in MESH_SUFFIXES


def load_model_and_units(path):
    """``(solid, declared units or None)`` of a model file, or of a mesh file read as a solid."""
    if is_mesh_file(path):
        return load_solid(path), None
    from implicit.models import load_model_units
    return load_model_units(path)


def load_solid(path):
    """The solid of a model file, or of a closed mesh file (a level set of the mesh).

    A mesh that is not closed is refused with the count of its open edges.
    """
    if not is_mesh_file(path):
        from implicit.models import load_model
        return load_model(path)
    import numpy as np

    from ..cells import mesh_to_solid
    from ..files import load_mesh
    mesh = load_mesh(path)
    if mesh.n_cells == 0:
        raise ValueError(f"{path}: the mesh has no faces")
    tri = mesh.triangulate() if not mesh.is_all_triangles else mesh
    open_edges = tri.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                           non_manifold_edges=True).n_cells
    if open_edges:
        raise ValueError(f"{path}: the mesh is not closed ({open_edges} open or non-manifold edges); "
                         "a solid needs a closed surface")
    lo, hi = np.asarray(tri.bounds[0::2]), np.asarray(tri.bounds[1::2])
    h = float(np.max(hi - lo)) / MESH_SOLID_RESOLUTION
    return mesh_to_solid(tri, h)


def load_target(path):
    """A mesh (integrated or checked as it is) for mesh files, else the model's solid."""
    if is_mesh_file(path):
        from ..files import load_mesh
        return load_mesh(path)
    from implicit.models import load_model
    return load_model(path)


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    text = str(message).strip().splitlines()
    stream = sys.stderr if file is None else file
    try:
        stream.write(f"implicad: warning: {text[0] if text else category.__name__}\n")
    except (OSError, ValueError):  # pragma: no cover - the terminal went away
        pass


def install_warning_handler() -> None:
    """Show every Python warning as one line on stderr (no file path, no source line)."""
    warnings.showwarning = _one_line_warning
