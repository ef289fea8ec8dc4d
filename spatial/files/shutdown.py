"""The end of a process that imported `spatial`: its garbage collected once, then left out of the teardown.

At exit the interpreter clears every module and runs full garbage
collections while it does, each walking every object still alive: with
numba, llvmlite and pyvista loaded that is hundreds of thousands of objects,
0.15 to 0.2 s of CPU (about a second of wall on a loaded machine) after the
user's last line -- a fixed cost of every script that meshes a part.

`install` registers one ``atexit`` handler that collects the garbage once,
with every module still intact (so objects in reference cycles are finalized
as a collection would finalize them), then freezes the survivors
(`gc.freeze`): the teardown's collections then walk only what the teardown
itself leaves, and the memory goes back to the system with the process as
always.  Registered when `spatial` is imported, so it runs after the exit
handlers of everything imported later (a Dask cluster's shutdown, temporary
folders).  ``IMPLICAD_FULL_TEARDOWN=1`` keeps the interpreter's own teardown.

Examples
--------
>>> install()        # idempotent: one handler per process
"""

from __future__ import annotations

import atexit
import gc
import os

__all__ = ["install", "FULL_TEARDOWN"]

#: Environment variable: "1" leaves the end of the process to the interpreter.
FULL_TEARDOWN = "IMPLICAD_FULL_TEARDOWN"
_STATE = {"installed": False}


def _collect_then_freeze() -> None:
    if os.environ.get(FULL_TEARDOWN) == "1":
        return
    gc.collect()
    gc.freeze()


def install() -> None:
    """Register the exit handler (once per process)."""
    if _STATE["installed"]:
        return
    _STATE["installed"] = True
    atexit.register(_collect_then_freeze)
