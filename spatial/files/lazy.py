"""Public names of a package loaded on first use (PEP 562), so that a job imports only what it needs.

A package lists ``name -> (module, attribute)`` in a table and hands it to
`lazy_exports`, which gives its module-level ``__getattr__`` and ``__dir__``:
``import spatial`` then costs a few milliseconds, and ``spatial.tet_mesh``
imports the FEA room the first time it is read.  An attribute of ``None``
names the module itself (a room: ``spatial.analysis``).

Examples
--------
>>> getattr_, dir_ = lazy_exports("spatial.files", {"MESH_FORMATS": (".meshes", "MESH_FORMATS")})
>>> ".stl" in getattr_("MESH_FORMATS")
True
"""

from __future__ import annotations

import importlib
import sys

__all__ = ["lazy_exports"]


def lazy_exports(package: str, table: dict):
    """``(__getattr__, __dir__)`` for `package`, loading the names of `table` on first use.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    table : dict
        ``{name: (module, attribute)}``; `module` is relative to the package
        (``".analysis"``), `attribute` None for the module itself.
    """
    namespace = sys.modules[package].__dict__

    def __getattr__(name):
        try:
            where, attribute = table[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        module = importlib.import_module(where, package)
        value = module if attribute is None else getattr(module, attribute)
        namespace[name] = value  # later reads are plain attribute reads
        return value

    def __dir__():
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__
