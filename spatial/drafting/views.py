"""Views of a part by the projection standards, their places and one scale.

Frames are rows ``u`` (paper right), ``v`` (paper up), ``d`` (the direction
of viewing, from the eye into the part).  The front view looks along +y with
z up.  First-angle projection (ISO 5456-2) puts the view from above *below*
the front view and the view from the left on its *right*; third-angle
projection (ASME Y14.3) puts the view from above *above* the front view and
the view from the right on its right.  The isometric view takes the free
corner.

Examples
--------
>>> view_frame("front")[2].tolist()
[0.0, 1.0, 0.0]
>>> [v for v, _ in grid("first")]
['front', 'side', 'top', 'iso']
>>> scale_text(0.5), choose_scale(lambda s: s * 100 <= 250)
('1:2', 2.0)
"""

from __future__ import annotations

import numpy as np

__all__ = ["PROJECTIONS", "STANDARD_SCALES", "view_frame", "side_direction", "grid", "choose_scale",
           "scale_text", "frame_from_direction"]

PROJECTIONS = ("first", "third")

#: Enlargement and reduction scales of ISO 5455, largest first.
STANDARD_SCALES = (50.0, 20.0, 10.0, 5.0, 2.0, 1.0, 1 / 2, 1 / 5, 1 / 10, 1 / 20, 1 / 50, 1 / 100,
                   1 / 200, 1 / 500, 1 / 1000)


def frame_from_direction(d, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Rows (u, v, d) for viewing along `d` with `up` as near to paper-up as possible."""
    d = np.asarray(d, dtype=float)
    d = d / np.linalg.norm(d)
    up = np.asarray(up, dtype=float)
    u = np.cross(d, up)
    if np.linalg.norm(u) < 1e-9:
        u = np.cross(d, (0.0, 1.0, 0.0))
    u /= np.linalg.norm(u)
    v = np.cross(u, d)
    return np.array([u, v, d])


def side_direction(projection: str) -> tuple:
    """Viewing direction of the side view: from the left in first angle, from the right in third."""
    return (1.0, 0.0, 0.0) if projection == "first" else (-1.0, 0.0, 0.0)


def view_frame(name: str, projection: str = "first") -> np.ndarray:
    """Frame of a named view: ``front``, ``top``, ``side`` or ``iso``."""
    if name == "front":
        return frame_from_direction((0.0, 1.0, 0.0))
    if name == "top":
        return frame_from_direction((0.0, 0.0, -1.0), up=(0.0, 1.0, 0.0))
    if name == "side":
        return frame_from_direction(side_direction(projection))
    if name == "iso":
        # Seen from front-right-top: x runs to the lower right, y to the upper right, z up.
        return frame_from_direction((-1.0, 1.0, -1.0))
    raise ValueError(f"view: expected front, top, side or iso, got {name!r}")


def grid(projection: str) -> list[tuple[str, tuple[int, int]]]:
    """(view, (column, row)) of the four views; row 0 is the upper row."""
    if projection == "first":
        return [("front", (0, 0)), ("side", (1, 0)), ("top", (0, 1)), ("iso", (1, 1))]
    if projection == "third":
        return [("top", (0, 0)), ("iso", (1, 0)), ("front", (0, 1)), ("side", (1, 1))]
    raise ValueError(f"projection: expected 'first' or 'third', got {projection!r}")


def choose_scale(fits) -> float:
    """The largest standard scale ``s`` (paper mm per model unit) with ``fits(s)`` true."""
    for s in STANDARD_SCALES:
        if fits(s):
            return s
    return STANDARD_SCALES[-1]


def scale_text(scale: float) -> str:
    """``2.0 -> '2:1'``, ``0.2 -> '1:5'``."""
    if scale >= 1:
        return f"{scale:g}:1"
    return f"1:{1 / scale:g}"
