"""Heavy packages imported with the cyclic garbage collector paused, their objects then frozen.

Importing numba and pyvista creates about 100,000 objects that live as long as
the process: functions, classes, type caches.  While they are created the
collector runs its young generations hundreds of times and the full one at
least once, and every later full collection walks them all again -- about
0.2 s of a process that meshes one part at N=256 (0.04 s during numba's
import, 0.02 s during pyvista's, a full collection of 0.06 s during the
first mesh and one of 0.07 s at exit), for no garbage: these imports leave
almost no reference cycles behind.

`install` puts a finder at the head of ``sys.meta_path`` that finds nothing
itself: when one of `PACKAGES` is first imported (and no other is being
imported), it wraps the package's loader so that the collector is off while
the package and everything it imports run, and then freezes everything alive
(`gc.freeze`): the collector no longer walks those objects.  The freeze
takes the objects older than the import with it, and the garbage not yet
collected: numba's and pyvista's imports leave about 200 objects in
reference cycles, which stay until the process ends (collecting them first
would walk every object the imports made, 0.03 s each), and an object frozen
that later becomes part of a garbage cycle is not collected either -- the
price of the freeze, as in a server that freezes before it forks.
``IMPLICAD_FULL_GC=1`` leaves the collector as it is.

Examples
--------
>>> install()          # idempotent; imports nothing
"""

from __future__ import annotations

import gc
import os
import sys

from .import_hooks import WrappingLoader, spec_behind

__all__ = ["install", "installed", "PACKAGES", "FULL_GC"]

#: Environment variable: "1" leaves every import to the collector as usual.
FULL_GC = "IMPLICAD_FULL_GC"
#: Top-level packages imported with the collector paused (their submodules imported later are not).
PACKAGES = frozenset({"numba", "llvmlite", "pyvista", "vtkmodules", "scipy", "skimage"})
_STATE = {"depth": 0}


def installed() -> bool:
    """True when the finder is in ``sys.meta_path`` (this process)."""
    return any(isinstance(f, _PausingFinder) for f in sys.meta_path)


def install() -> None:
    """Put the finder at the head of ``sys.meta_path`` (once; not with ``IMPLICAD_FULL_GC=1``)."""
    if os.environ.get(FULL_GC) == "1" or installed():
        return
    sys.meta_path.insert(0, _PausingFinder())


class _PausingFinder:
    """Finds a package with the finders after it; wraps its loader when it is the outermost heavy import."""

    def find_spec(self, name, path=None, target=None):
        if _STATE["depth"] or name not in PACKAGES:
            return None
        return _PausingLoader.wrap(spec_behind(self, name, path, target))

    def invalidate_caches(self):
        return None


class _PausingLoader(WrappingLoader):
    """The original loader run with the collector off; everything alive afterwards frozen."""

    def run(self, module):
        enabled = gc.isenabled()
        gc.disable()
        _STATE["depth"] += 1
        try:
            self.loader.exec_module(module)
        finally:
            _STATE["depth"] -= 1
            # not collected first: a collection of the young generation (every object the import made)
            # costs 0.03 s for numba's and finds about a hundred objects of garbage
            gc.freeze()
            if enabled:
                gc.enable()
