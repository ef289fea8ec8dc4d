"""numba's runtime functions loaded from their machine code on disk instead of compiled in every process.

Before a process runs its first kernel numba compiles, from LLVM IR, the
handful of functions its runtime (NRT) defines in LLVM itself -- atomic
reference counts, a meminfo's data pointer, the abort of an unresolved
symbol: 20 ms of every process that loads its kernels from the cache, half
of the first load.  The IR is the same in every process of one numba on one
machine, so its machine code is kept on disk as numba keeps a cached
kernel's: the object code and the bitcode beside it, under a name that holds
numba's and llvmlite's versions, the Python version and numba's own key of
the code generator (target triple, CPU name and features).  A process loads
that file as numba loads a cached kernel; a missing, unreadable or
mismatched file is compiled and written again.

Installed by `implicit.evaluate.numba_start` with the rest of the start-up;
``IMPLICAD_NUMBA_FULL_START=1`` leaves numba's own.

Examples
--------
>>> runtime_path(None) is None
True
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys

__all__ = ["install", "runtime_path"]

#: Bumped when the file's layout changes.
FORMAT = 1


def install(nrtdynmod) -> None:
    """Make ``nrtdynmod.compile_nrt_functions`` load the runtime's machine code from disk when it can."""
    original = getattr(nrtdynmod, "compile_nrt_functions", None)
    if original is None or hasattr(original, "__wrapped__") or not hasattr(nrtdynmod, "create_nrt_module"):
        return

    def compile_nrt_functions(ctx):
        codegen = ctx.codegen()
        needed = ("magic_tuple", "unserialize_library")
        if not all(hasattr(codegen, a) for a in needed):
            return original(ctx)
        path = runtime_path(codegen)
        library = _load(codegen, path) if path else None
        if library is not None:
            return library
        ir_mod, library = nrtdynmod.create_nrt_module(ctx)
        library.enable_object_caching()  # the engine hands over the machine code it makes
        library.add_ir_module(ir_mod)
        library.finalize()
        if path:
            _store(library, codegen, path)
        return library

    compile_nrt_functions.__doc__ = original.__doc__
    compile_nrt_functions.__wrapped__ = original
    nrtdynmod.compile_nrt_functions = compile_nrt_functions


def _key(codegen) -> tuple:
    import llvmlite
    import numba
    from numba.core import config

    return (FORMAT, numba.__version__, llvmlite.__version__, sys.version, tuple(codegen.magic_tuple()),
            repr(config.OPT))


def runtime_path(codegen) -> str | None:
    """The file of the runtime's machine code for `codegen` (None without a code generator).

    In ``NUMBA_CACHE_DIR`` when set, else in this package's ``__pycache__``.
    """
    if codegen is None:
        return None
    from numba.core import config

    folder = config.CACHE_DIR or os.path.join(os.path.dirname(os.path.abspath(__file__)), "__pycache__")
    digest = hashlib.sha256(repr(_key(codegen)).encode()).hexdigest()[:20]
    return os.path.join(folder, f"numba_runtime-{digest}.nbo")


def _load(codegen, path):
    try:
        with open(path, "rb") as handle:
            saved = pickle.load(handle)
        if not isinstance(saved, dict) or saved.get("key") != _key(codegen):
            return None
        name, kind, data = saved["state"]
        if kind != "object" or not isinstance(data, tuple) or len(data) != 2:
            return None
        return codegen.unserialize_library((name, kind, data))
    except Exception:  # noqa: BLE001 - any damaged or foreign file: compile instead, as without it
        return None


def _store(library, codegen, path) -> None:
    try:
        state = library.serialize_using_object_code()
        os.makedirs(os.path.dirname(path), exist_ok=True)
        temporary = f"{path}.{os.getpid()}.tmp"
        with open(temporary, "wb") as handle:
            pickle.dump({"key": _key(codegen), "state": state}, handle, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(temporary, path)  # whole or not at all: a concurrent process reads the old file or the new
    except Exception:  # noqa: BLE001 - a read-only folder: the next process compiles again
        try:
            os.unlink(temporary)
        except (OSError, UnboundLocalError):
            pass
