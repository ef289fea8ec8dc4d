"""Warnings of the cluster path, pointed at the caller's line: `spatial.files.warn`'s, under this room's name."""

from __future__ import annotations

from ..files.warn import user_stacklevel, user_warnings  # noqa: F401

__all__ = ["user_warnings", "user_stacklevel"]
