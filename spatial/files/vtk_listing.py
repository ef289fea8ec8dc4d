"""VTK's extension modules found in one listing of their folder instead of one glob each.

The ``vtkmodules`` package finds each of its extension modules
(``vtkmodules.vtkCommonCore`` ...) with its own finder, which globs the
package's folder -- several hundred files -- for ``vtkCommonCore[.-]*``:
about 50 globs when pyvista is imported, 0.02-0.03 s of CPU.  `install`
replaces that search, right after ``vtkmodules`` has run, with one that
lists each folder once and picks the same file: the first name of the
listing, in the folder's own order as the glob reads it, that starts with
the module's name and a ``.`` or ``-``, resolves to a file and has the
extension among its suffixes, ``.pyd`` before ``.so`` as VTK has it.
``IMPLICAD_EAGER_IMPORTS=1`` leaves VTK's search as it is.

Examples
--------
>>> install()          # idempotent; imports nothing
"""

from __future__ import annotations

import os
import sys

from .import_hooks import WrappingLoader, spec_behind

__all__ = ["install", "find_lib_path"]

_PACKAGE = "vtkmodules"
_LISTINGS: dict = {}


def install() -> None:
    """Patch ``vtkmodules.find_lib_path`` now if VTK is loaded, else right after its import."""
    if os.environ.get("IMPLICAD_EAGER_IMPORTS") == "1":
        return
    if _PACKAGE in sys.modules:
        _patch(sys.modules[_PACKAGE])
    elif not any(isinstance(f, _AfterVtk) for f in sys.meta_path):
        sys.meta_path.insert(0, _AfterVtk())


def _listing(folder: str) -> list:
    names = _LISTINGS.get(folder)
    if names is None:
        try:
            with os.scandir(folder) as entries:
                names = [entry.name for entry in entries]  # the folder's order, as a glob reads it
        except OSError:
            names = []
        _LISTINGS[folder] = names
    return names


def find_lib_path(paths, vtk_module_name, extensions=(".pyd", ".so")):
    """The file of VTK extension module `vtk_module_name` in the folders `paths`, or None.

    What ``vtkmodules.find_lib_path`` returns, from one listing per folder.
    """
    from pathlib import PurePath

    size = len(vtk_module_name)
    for ext in extensions:
        for base in paths:
            for name in _listing(str(base)):
                if len(name) <= size or not name.startswith(vtk_module_name) or name[size] not in ".-":
                    continue
                resolved = os.path.realpath(os.path.join(str(base), name))
                if os.path.isfile(resolved) and ext in PurePath(resolved).suffixes:
                    return resolved
    return None


def _patch(module) -> None:
    original = getattr(module, "find_lib_path", None)
    if original is None or hasattr(original, "__wrapped__"):
        return
    extensions = tuple(getattr(module, "LIB_EXTS", (".pyd", ".so")))

    def patched(paths, vtk_module_name):
        return find_lib_path(paths, vtk_module_name, extensions)

    patched.__doc__ = find_lib_path.__doc__
    patched.__wrapped__ = original
    module.find_lib_path = patched


class _AfterVtk:
    """Finds ``vtkmodules`` with the finders after it and patches it right after it has run."""

    def find_spec(self, name, path=None, target=None):
        if name != _PACKAGE:
            return None
        sys.meta_path.remove(self)
        return _PatchingLoader.wrap(spec_behind(self, name, path, target))

    def invalidate_caches(self):
        return None


class _PatchingLoader(WrappingLoader):
    def run(self, module):
        self.loader.exec_module(module)
        _patch(module)
