"""Atomic writes: a file appears whole or not at all.

The writer works on a temporary name beside the target and the result is
renamed into place (``os.replace``), so a failure never leaves half a file.
"""

from __future__ import annotations

import os
import uuid

__all__ = ["atomic_write"]


def atomic_write(path, write, suffix=None):
    """Call ``write(tmp_path)`` then rename the temporary file onto `path`.

    The temporary name lives in the destination's directory (so the rename is
    atomic) and is created by the writer itself, so the file gets the usual
    permissions (umask) rather than a private temporary file's.  It ends in
    `suffix` (default: the extension of `path`) for writers that choose the
    format by it.
    """
    path = os.fspath(path)
    if suffix is None:
        suffix = os.path.splitext(path)[1]
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise FileNotFoundError(2, "No such directory", directory)
    tmp = os.path.join(directory, f".{os.path.basename(path)}.{uuid.uuid4().hex}.tmp{suffix}")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
