"""Atomic writes: a file appears whole or not at all.

The writer works on a temporary name beside the target and the result is
renamed into place (``os.replace``), so a failure never leaves half a file.
A killed process cannot clean up after itself: its temporary files, named
``.<target>.<pid>-<hex>.tmp<suffix>``, are removed by the next write into the
same folder once their writer's process is gone (or, for names without a
pid, once they are older than `STALE_SECONDS`).
"""

from __future__ import annotations

import os
import re
import time
import uuid

__all__ = ["atomic_write", "clean_stale_temporaries", "STALE_SECONDS", "check_output_path"]

#: Age after which a temporary file whose writer is unknown counts as abandoned.
STALE_SECONDS = 15 * 60

_TMP_RE = re.compile(r"^\..+\.(?:(?P<pid>\d+)-)?[0-9a-f]{32}\.tmp[^/]*$")


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:     # someone else's live process
        return True
    except OSError:  # pragma: no cover - e.g. pid out of range
        return False
    return True


def clean_stale_temporaries(directory, *, now: float | None = None) -> list[str]:
    """Remove the temporary files of interrupted atomic writes in `directory`.

    A file counts as abandoned when its name carries a pid of no live
    process, or carries none and is older than `STALE_SECONDS`.  Files of a
    live writer (another process still writing) are left alone.

    Returns
    -------
    list of str
        The paths removed.

    Examples
    --------
    >>> import tempfile
    >>> clean_stale_temporaries(tempfile.mkdtemp())
    []
    """
    directory = os.fspath(directory)
    now = time.time() if now is None else now
    removed = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for entry in entries:
        m = _TMP_RE.match(entry.name)
        if m is None:
            continue
        try:
            if not entry.is_file(follow_symlinks=False):
                continue
            pid = m.group("pid")
            if pid is not None:
                stale = not _alive(int(pid))
            else:
                stale = now - entry.stat(follow_symlinks=False).st_mtime > STALE_SECONDS
            if stale:
                os.unlink(entry.path)
                removed.append(entry.path)
        except OSError:     # raced with another cleaner or the writer itself
            continue
    return removed


def atomic_write(path, write, suffix=None):
    """Call ``write(tmp_path)`` then rename the temporary file onto `path`.

    The temporary name lives in the destination's directory (so the rename is
    atomic) and is created by the writer itself, so the file gets the usual
    permissions (umask) rather than a private temporary file's.  It ends in
    `suffix` (default: the extension of `path`) for writers that choose the
    format by it, and carries this process's id so that a later write can
    tell an abandoned temporary file from a live one
    (`clean_stale_temporaries`, run before every write).
    """
    path = os.fspath(path)
    if suffix is None:
        suffix = os.path.splitext(path)[1]
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise FileNotFoundError(2, "No such directory", directory)
    clean_stale_temporaries(directory)
    tmp = os.path.join(directory, f".{os.path.basename(path)}.{os.getpid()}-{uuid.uuid4().hex}.tmp{suffix}")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def check_output_path(path, extension: str, name: str = "path") -> str:
    """`path` as a string when it ends in `extension` and its folder exists; else a clear error.

    Called before any work, so a bad output name fails before the job starts.

    Examples
    --------
    >>> check_output_path("part.png", ".png")
    'part.png'
    """
    p = os.fspath(path)
    if not p.lower().endswith(extension):
        raise ValueError(f"{name}: expected a {extension} file name, got {p!r}")
    folder = os.path.dirname(os.path.abspath(p))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    return p
