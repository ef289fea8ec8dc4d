"""Modules that numba and pyvista import but do not use at import time, run on first use instead.

Two imports of the packages the mesh path loads cost a process that meshes a
part without doing anything for it:

- pyvista's reader registry imports ``pooch`` (downloads of remote files; it
  calls ``pooch.retrieve`` for an ``http://`` path only), and pooch imports
  tqdm, asyncio and platformdirs: 0.05 s;
- numba's configuration imports ``yaml`` to read a ``.numba_config.yaml``
  when the working folder holds one: 0.01 s;
- numba's extension loader imports ``importlib.metadata`` to read the
  installed distributions' entry points, which `implicit.evaluate.numba_start`
  skips when no distribution declares numba extensions: 0.01 s.

`install` puts a finder at the head of ``sys.meta_path`` that gives these
modules, when first imported, a lazy loader (`importlib.util.LazyLoader`):
the import binds the module at once and runs it at the first attribute read
(``pooch.retrieve``, ``yaml.safe_load``, ``metadata.version``), so a process
that never reads one never runs it.  ``IMPLICAD_EAGER_IMPORTS=1`` imports them as usual.

Examples
--------
>>> install()          # idempotent; imports nothing
"""

from __future__ import annotations

import os
import sys

from .import_hooks import spec_behind

__all__ = ["install", "installed", "DEFERRED", "EAGER"]

#: Environment variable: "1" imports every module as usual.
EAGER = "IMPLICAD_EAGER_IMPORTS"
#: Modules run on first use: imported at import time by pyvista (pooch) and numba (yaml, importlib.metadata),
#: used later if ever.
DEFERRED = frozenset({"pooch", "yaml", "importlib.metadata"})


def installed() -> bool:
    """True when the finder is in ``sys.meta_path`` (this process)."""
    return any(isinstance(f, _DeferringFinder) for f in sys.meta_path)


def install() -> None:
    """Put the finder at the head of ``sys.meta_path`` (once; not with ``IMPLICAD_EAGER_IMPORTS=1``)."""
    if os.environ.get(EAGER) == "1" or installed():
        return
    sys.meta_path.insert(0, _DeferringFinder())


class _DeferringFinder:
    """Finds a deferred module with the finders after it and makes its loader lazy."""

    def find_spec(self, name, path=None, target=None):
        if name not in DEFERRED:
            return None
        spec = spec_behind(self, name, path, target)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        from importlib.util import LazyLoader

        spec.loader = LazyLoader(spec.loader)
        return spec

    def invalidate_caches(self):
        return None
