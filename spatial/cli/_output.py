"""Helpers the manufacturing and inspection commands share: output names, atomic text files."""

from __future__ import annotations

import os


def check_output(path, extensions, what="an output"):
    """The lower-case extension of `path`, after checking it and its folder (before any work)."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in extensions:
        raise ValueError(f"{path}: expected {what} file name ending in {', '.join(extensions)}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    return ext


def write_text(path, text):
    """Write `text` to `path` atomically."""
    from ..files.atomic import atomic_write

    def write(tmp):
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)

    atomic_write(path, write)
