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

Two more costs of every cached load go with it (about 5 ms of a 10 ms load,
0.15 s of CPU over the 35 kernels of `implicad mesh`):

- numba parses the LLVM bitcode kept beside the machine code and walks it
  through LLVM's C API for the names the engine defines; those names are read
  from the machine code's own symbol table (`numba_objects`) and the bitcode
  is parsed only when a later compilation links the kernel into its caller.
- every LLVM call broadcasts numba's "numba:llvm_lock" start and end events
  (5 us a pair, thousands per process); a cached load runs without them, so
  a dispatcher's ``llvm_lock`` timer counts compilations only.

A kernel that inlined one of numba's own implementations (``np.empty``'s,
in numba.np.arrayobj) carries that module's environment, and numba imports
the module to rebuild it, for globals that only object mode reads: 45 ms of
the first load, importing numba.np.arrayobj, numba.cpython.unicode and a few
more.  Such an environment gets a namespace of the module's name alone when
the module is not loaded yet.

And before the first call of any kernel numba looks for its extensions among
the entry points of every installed distribution, reading all their metadata
through importlib.metadata (40 ms here, 90 distributions).  When no
``entry_points.txt`` on ``sys.path`` names the ``numba_extensions`` group
there is none to load, and numba is told so; otherwise it looks as before.

Examples
--------
>>> from implicit.evaluate.numba_start import install
>>> install()          # idempotent; numba is not imported by it
"""

from __future__ import annotations

import os
import sys

__all__ = ["install", "installed", "no_numba_extensions", "FULL_START"]

#: Environment variable: "1" leaves numba's start-up as numba does it.
FULL_START = "IMPLICAD_NUMBA_FULL_START"
_CACHING = "numba.core.caching"
_ENTRY_POINTS = "numba.core.entrypoints"
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
    after_import(_ENTRY_POINTS, _patch_entry_points)


def _patch(caching) -> None:
    from numba.core import codegen

    lazy = _patch_unserialize(codegen)
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
        lock = _llvm_lock()
        callbacks = getattr(lock, "_cblist", None)
        if isinstance(callbacks, list):
            lock._cblist = []
        try:
            with self._guard_against_spurious_io_errors():
                return self._load_overload(sig, target_context)
        finally:
            if isinstance(callbacks, list):
                lock._cblist = callbacks + lock._cblist  # any registered meanwhile kept
        return None  # the guard swallowed an I/O error: compile instead, as numba does

    load_overload.__doc__ = original.__doc__
    load_overload.__wrapped__ = original
    cache.load_overload = load_overload
    if lazy is not None:
        lazy()
    _patch_rebuild_env()
    from numba.core.runtime import nrtdynmod

    from .numba_runtime import install as cached_runtime

    cached_runtime(nrtdynmod)  # the runtime's own functions loaded from disk, not compiled (20 ms)
    _STATE["patched"] = True


def _patch_rebuild_env() -> None:
    """Cached kernels' environments of numba's own modules rebuilt without importing those modules."""
    from numba.core import environment

    original = getattr(environment, "_rebuild_env", None)
    kind = getattr(environment, "Environment", None)
    # the rebuild this was written against (numba 0.49 and later): memo, lookup, then the module's globals
    if original is None or hasattr(original, "__wrapped__") or not hasattr(environment, "lookup_environment") \
            or not hasattr(getattr(kind, "_memo", None), "__setitem__"):
        return

    def _rebuild_env(modname, consts, env_name):
        # an inlined numba implementation (np.empty's lives in numba.np.arrayobj) gives its kernel the
        # environment of its own module; numba imports that module for its globals, which only object
        # mode reads.  A module not loaded yet gets a namespace of its name alone (45 ms at the first load).
        if environment.lookup_environment(env_name) is not None or not modname \
                or not modname.startswith("numba.") or modname in sys.modules:
            return original(modname, consts, env_name)
        env = kind({"__name__": modname})
        env.consts[:] = consts
        env.env_name = env_name
        kind._memo[env_name] = env
        return env

    _rebuild_env.__doc__ = original.__doc__
    _rebuild_env.__wrapped__ = original
    # a kernel cached from here on names the rebuild as numba's own (pickled by reference): any
    # process loads it, this patch installed or not
    _rebuild_env.__module__, _rebuild_env.__qualname__ = original.__module__, original.__qualname__
    _rebuild_env.__name__ = original.__name__
    environment._rebuild_env = _rebuild_env


def _llvm_lock():
    from llvmlite.binding import ffi

    return getattr(ffi.lib, "_lock", None)


def _patch_unserialize(codegen):
    """A function that makes cached kernels' bitcode lazy, or None if this numba's loader is another."""
    library = getattr(codegen, "CPUCodeLibrary", None)
    engine = getattr(codegen, "JitEngine", None)
    needed = ("_unserialize", "_get_module_for_linking", "enable_object_caching", "_set_compiled_object",
              "_finalize_final_module")
    if library is None or engine is None or not all(hasattr(library, a) for a in needed) \
            or not hasattr(engine, "_load_defined_symbols"):
        return None
    unserialize = library.__dict__["_unserialize"].__func__
    for_linking = library._get_module_for_linking

    def _unserialize_lazily(cls, codegen_, state):
        name, kind, data = state
        names = None
        if kind == "object":
            from .numba_objects import defined_symbols

            names = defined_symbols(data[0])
        if names is None:
            return unserialize(cls, codegen_, state)
        object_code, shared_bitcode = data
        self = codegen_.create_library(name)
        self.enable_object_caching()
        self._set_compiled_object(object_code)
        self._implicad_bitcode = shared_bitcode  # parsed by _get_module_for_linking, if ever
        self._finalize_final_module()
        codegen_._engine._defined_symbols |= names
        return self

    def _get_module_for_linking(self):
        bitcode = self.__dict__.pop("_implicad_bitcode", None)
        if bitcode is not None and self._shared_module is None:
            from llvmlite import binding

            self._shared_module = binding.parse_bitcode(bitcode)
        return for_linking(self)

    _unserialize_lazily.__wrapped__ = unserialize
    _get_module_for_linking.__wrapped__ = for_linking

    def apply():
        library._unserialize = classmethod(_unserialize_lazily)
        library._get_module_for_linking = _get_module_for_linking

    return apply


def _patch_entry_points(entrypoints) -> None:
    original = getattr(entrypoints, "init_all", None)
    if original is None or not hasattr(entrypoints, "_already_initialized") or hasattr(original, "__wrapped__"):
        return

    def init_all():
        if not entrypoints._already_initialized and no_numba_extensions():
            entrypoints._already_initialized = True
            return
        original()

    init_all.__doc__ = original.__doc__
    init_all.__wrapped__ = original
    entrypoints.init_all = init_all


def no_numba_extensions(paths=None) -> bool:
    """True when no distribution on `paths` (default ``sys.path``) declares a ``numba_extensions`` entry point.

    Reads only the ``entry_points.txt`` files of the ``*.dist-info`` and
    ``*.egg-info`` folders, where importlib.metadata's path finder would find
    them.  False (numba looks for itself) when anything else might provide
    distributions: a zip or egg on the path or, for ``sys.path``, another
    distribution finder in ``sys.meta_path``.

    Examples
    --------
    >>> import tempfile
    >>> no_numba_extensions([tempfile.mkdtemp()])
    True
    """
    from importlib.machinery import PathFinder

    if paths is None and any(hasattr(f, "find_distributions") and f is not PathFinder for f in sys.meta_path):
        return False
    for entry in sys.path if paths is None else paths:
        folder = entry or os.getcwd()
        if not os.path.isdir(folder):
            if os.path.exists(folder):
                return False  # a zip: its distributions are not read here
            continue
        try:
            names = os.listdir(folder)
        except OSError:
            return False
        for name in names:
            if name.endswith(".egg"):
                return False
            if not name.endswith((".dist-info", ".egg-info")):
                continue
            path = os.path.join(folder, name, "entry_points.txt")
            try:
                with open(path, "rb") as handle:
                    text = handle.read()
            except (FileNotFoundError, NotADirectoryError):  # no entry points, or an egg-info file
                continue
            except OSError:
                return False
            if b"numba_extensions" in text:
                return False
    return True
