"""numba's start-up in a process that loads its kernels from the on-disk cache.

Before it loads the first cached kernel of a process, numba refreshes its
whole CPU target: it imports its typing and lowering registries (numba.np
arraymath and linalg, which import scipy.linalg for BLAS) and installs them,
about 0.3 s of a whole `implicad mesh` run.  A kernel loaded from the cache
needs none of that: its machine code is linked as it was compiled and the
dispatcher calls it without typing anything.  All it needs is numba's runtime
(NRT: the allocator its arrays use), which the refresh would also have set up.

`install` makes numba's cache loader set up the runtime alone; the first real
compilation of a process still refreshes everything (numba's compiler does
so itself), so a kernel compiled here after cached ones types and lowers as
before.  ``IMPLICAD_NUMBA_FULL_START=1`` keeps numba's own behaviour; so does
a numba whose cache loader is not the one this was written against.

Examples
--------
>>> from implicit.evaluate.numba_start import install
>>> install()          # idempotent; numba is not imported by it
"""

from __future__ import annotations

import os

__all__ = ["install", "installed", "FULL_START"]

#: Environment variable: "1" leaves numba's start-up as numba does it.
FULL_START = "IMPLICAD_NUMBA_FULL_START"
_CACHING = "numba.core.caching"
_STATE = {"patched": False}


def installed() -> bool:
    """True once numba's cache loader sets up the runtime alone (this process)."""
    return _STATE["patched"]


def install() -> None:
    """Load cached kernels without numba's target refresh, now or as soon as numba is imported.

    Does not import numba: when numba's cache module is not loaded yet, a finder
    at the head of ``sys.meta_path`` patches it right after it has run.
    """
    if os.environ.get(FULL_START) == "1" or _STATE["patched"]:
        return
    from ..after_import import after_import

    after_import(_CACHING, _patch)


def _patch(caching) -> None:
    cache = getattr(caching, "Cache", None)
    original = getattr(cache, "load_overload", None)
    # the loader this was written against (numba 0.49 to 0.61 and later): refresh, then _load_overload
    if original is None or not all(hasattr(cache, a) for a in ("_load_overload", "_guard_against_spurious_io_errors")):
        return

    def load_overload(self, sig, target_context):
        if type(target_context).__name__ != "CPUContext":
            return original(self, sig, target_context)
        from numba.core.runtime import rtsys

        rtsys.initialize(target_context)  # what the cached code links against; the registries wait
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)
        return None  # the guard swallowed an I/O error: compile instead, as numba does

    load_overload.__doc__ = original.__doc__
    load_overload.__wrapped__ = original
    cache.load_overload = load_overload
    _STATE["patched"] = True
