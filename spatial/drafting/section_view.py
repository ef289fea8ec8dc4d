"""Section views: the cutting plane, the part beyond it, and ISO 128-50
hatching (thin lines at 45 degrees) of the cut face.

A plane ``x=c``, ``y=c`` or ``z=c`` replaces the view that looks along its
normal (side, front, top): the material between the eye and the plane is
removed, the section's exact contours (`spatial.analysis.section`) are
hatched, and the plane is drawn edge-on in a neighbouring view as a chain
line, thick at its ends, with arrows in the direction of viewing and the
letter ``A``.

Examples
--------
>>> square = [np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)]
>>> segs = hatch_segments(square, spacing=2.0)
>>> bool(np.all(segs >= -1e-9) and np.all(segs <= 10 + 1e-9)), len(segs)
(True, 7)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .views import side_direction

__all__ = ["SectionPlan", "plan_section", "hatch_segments", "section_loops"]


@dataclass(frozen=True)
class SectionPlan:
    """Which view becomes the section, which view shows the plane, and the cut.

    Attributes
    ----------
    plane : str
        As given (``"y=0"``).
    axis : int
        0, 1 or 2.
    offset : float
    section_view : str
        The view replaced by the section.
    line_view : str
        The view the cutting plane is drawn in.
    direction : (3,) float
        Direction of viewing of the section (the arrows).
    """

    plane: str
    axis: int
    offset: float
    section_view: str
    line_view: str
    direction: tuple

    def cut(self, solid):
        """`solid` without the material between the eye and the plane."""
        from implicit import halfspace

        point = np.zeros(3)
        point[self.axis] = self.offset
        return solid & halfspace(tuple(-np.asarray(self.direction)), tuple(point))


def plan_section(plane: str, projection: str = "first") -> SectionPlan:
    """Plan the section for ``"x=c"``, ``"y=c"`` or ``"z=c"``."""
    from ..analysis import parse_plane

    if not isinstance(plane, str):
        raise TypeError(f"section: expected a plane such as 'y=0', got {type(plane).__name__}")
    point, normal = parse_plane(plane)
    axis = int(np.argmax(np.abs(normal)))
    if axis == 1:
        return SectionPlan(plane, 1, float(point[1]), "front", "top", (0.0, 1.0, 0.0))
    if axis == 2:
        return SectionPlan(plane, 2, float(point[2]), "top", "front", (0.0, 0.0, -1.0))
    return SectionPlan(plane, 0, float(point[0]), "side", "front", side_direction(projection))


def section_loops(solid, plan: SectionPlan, frame, *, resolution: int = 256) -> list[np.ndarray]:
    """The cut face's closed contours in the section view's coordinates."""
    from ..analysis.section import section

    s = section(solid, plan.plane, resolution=resolution)
    return [np.asarray(l3) @ np.asarray(frame)[:2].T for l3 in s.loops3d]


def hatch_segments(loops, spacing: float, angle: float = 45.0) -> np.ndarray:
    """Hatch lines ``(m, 2, 2)`` filling the region inside `loops` (even-odd rule).

    Lines at `angle` degrees, `spacing` apart; all loops at once, every line
    against every loop edge in one array operation.
    """
    if spacing <= 0:
        raise ValueError(f"spacing: expected a positive number, got {spacing!r}")
    loops = [np.asarray(l, dtype=float) for l in loops if len(l) >= 3]
    if not loops:
        return np.zeros((0, 2, 2))
    a = np.radians(angle)
    rot = np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])  # hatch direction -> x axis
    p0 = np.concatenate([l for l in loops]) @ rot.T
    p1 = np.concatenate([np.roll(l, -1, axis=0) for l in loops]) @ rot.T
    lo, hi = min(p0[:, 1].min(), p1[:, 1].min()), max(p0[:, 1].max(), p1[:, 1].max())
    ys = np.arange(np.ceil(lo / spacing) * spacing, hi, spacing)
    ys = ys[(ys > lo) & (ys < hi)]
    if ys.size == 0:
        return np.zeros((0, 2, 2))
    y0, y1 = p0[:, 1][None], p1[:, 1][None]
    yy = ys[:, None]
    # Half-open crossing rule: every line meets a closed loop an even number of times.
    cross = ((y0 <= yy) & (yy < y1)) | ((y1 <= yy) & (yy < y0))
    li, si = np.nonzero(cross)
    t = (ys[li] - p0[si, 1]) / (p1[si, 1] - p0[si, 1])
    xs = p0[si, 0] + t * (p1[si, 0] - p0[si, 0])
    order = np.lexsort((xs, li))
    li, xs = li[order], xs[order]
    counts = np.bincount(li, minlength=len(ys))
    # Pair the crossings of each line in order: (1st, 2nd), (3rd, 4th), ...
    rank = np.arange(len(li)) - np.repeat(np.cumsum(counts) - counts, counts)
    start = rank % 2 == 0
    start &= np.roll(li, -1) == li
    start[-1] = False
    a_x, b_x, y = xs[start], xs[np.flatnonzero(start) + 1], ys[li[start]]
    back = rot.T
    pa = np.column_stack([a_x, y]) @ back.T
    pb = np.column_stack([b_x, y]) @ back.T
    return np.stack([pa, pb], axis=1)
