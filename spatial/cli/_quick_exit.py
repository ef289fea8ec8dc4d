"""The end of an `implicad` process without the interpreter's teardown.

When a command has done its work the interpreter would still tear itself
down: clear every module (numba's and llvmlite's are a thousand), collect
the garbage of each pass, and free object by object what the process is
about to give back whole.  That is 0.2 s of CPU (0.4 s of wall on a loaded
machine) after ``implicad mesh`` has printed its summary, paid by every
command that imported numba, and nothing of it reaches the user.

`exit_now` keeps what the teardown does for the user and skips the rest: it
runs the ``atexit`` handlers (a Dask cluster's shutdown, `logging`'s flush,
`weakref.finalize` callbacks such as temporary folders' removal), flushes
every open file still buffered -- a model file may have left one open --
and stdout and stderr, then ends the process with `os._exit`.  With another
thread still running it returns instead, and the interpreter exits as usual
(waiting for that thread).
"""

from __future__ import annotations

import atexit
import gc
import io
import os
import sys
import threading

__all__ = ["exit_now"]

_BUFFERED_FILES = (io.BufferedWriter, io.BufferedRandom, io.TextIOWrapper)


def _flush_open_files() -> None:
    """Flush every buffered file object still open (their data would otherwise be lost with the process)."""
    gc.unfreeze()  # objects an exit handler froze (`spatial.files.shutdown`) are listed only once unfrozen
    for obj in gc.get_objects():
        # `type(obj)`, not `isinstance`: isinstance also reads each object's ``__class__``, and on a module
        # bound lazily (yaml's, importlib.metadata's) that attribute runs the module's code, 80 ms of
        # imports at every exit for files that cannot be among them
        if issubclass(type(obj), _BUFFERED_FILES):
            try:
                if not obj.closed:
                    obj.flush()
            except (OSError, ValueError):  # a broken pipe or a detached stream: nothing left to save
                pass


def exit_now(status: int) -> None:
    """End the process with `status` after the ``atexit`` handlers and a flush of open files.

    Returns (and lets the interpreter exit as usual) when a thread other
    than this one is still alive, or when this is not the main thread.
    """
    if threading.current_thread() is not threading.main_thread():
        return
    run_exit_functions = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_functions is None:  # pragma: no cover - an interpreter without CPython's atexit
        return
    if threading.active_count() > 1:
        return
    run_exit_functions()  # (and unregisters them: the interpreter's own exit will not run them again)
    if threading.active_count() > 1:  # an exit handler started a thread: let the interpreter wait for it
        return
    _flush_open_files()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):
            pass
    os._exit(int(status))
