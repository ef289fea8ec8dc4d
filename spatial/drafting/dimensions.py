"""Dimensions: linear sizes between extension lines and leader notes
(hole callouts, radii), placed around a view without overlaps (ISO 129-1).

A dimension is first stated in view coordinates (model units); `place`
puts it on the sheet in the first free lane on its side of the view: a
lane is free when the dimension's box (line, arrows, text) meets no box
placed before and no other view.  Shorter dimensions take the inner lanes,
so dimensions from a datum stack outwards and the overall size comes last.

Examples
--------
>>> from spatial.drafting.model import Group
>>> g = Group("view-front", "view")
>>> placed = Placer([])
>>> _ = placed.place(g, Linear((0, 0), (40, 0), "h", "below", 40.0), lambda uv: (10 + uv[0], 100 - uv[1]),
...              (10, 90, 50, 100))
>>> g.items[0].data["value"]
'40'
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Group, text_width

__all__ = ["Linear", "Note", "Placer", "format_value", "arrowhead", "ARROW", "TEXT_SIZE"]

#: Arrowhead length and half-width (mm): closed, filled, 30 degrees included.
ARROW = (3.0, 0.8)
#: Dimension text height (mm).
TEXT_SIZE = 3.5
#: First lane's distance from the view and the distance between lanes (mm).
FIRST_LANE, LANE = 9.0, 7.0
#: Gap between a view and its extension lines, and their overshoot (mm).
GAP, OVERSHOOT = 1.5, 2.0


def format_value(value: float) -> str:
    """Millimetres as drawn: at most two decimals, no trailing zeros."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


@dataclass
class Linear:
    """A size between two points of a view along ``h`` (u) or ``v``, drawn on `side`."""

    a: tuple
    b: tuple
    orient: str
    side: str
    value: float
    prefix: str = ""
    kind: str = "linear"


@dataclass
class Note:
    """A leader from `anchor` (a point on a circle or arc) to a text such as ``4x ⌀8``."""

    anchor: tuple
    text: str
    value: float
    kind: str = "diameter"
    count: int = 1
    centre: tuple | None = None


def _overlaps(a, b, pad=0.8) -> bool:
    return not (a[2] + pad <= b[0] or b[2] + pad <= a[0] or a[3] + pad <= b[1] or b[3] + pad <= a[1])


def arrowhead(group: Group, tip, towards):
    tip = np.asarray(tip, dtype=float)
    d = np.asarray(towards, dtype=float) - tip
    d /= max(np.linalg.norm(d), 1e-12)
    n = np.array([-d[1], d[0]])
    base = tip + ARROW[0] * d
    group.polygon([tip, base + ARROW[1] * n, base - ARROW[1] * n], "dimension")


def _segment_boxes(a, b, size: float = 1.5) -> list:
    """Small boxes along the segment from `a` to `b` (a leader as obstacles), the first
    `2 * size` left out: the arrow end sits on the part's outline, among its other marks."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = max(2, int(np.linalg.norm(b - a) / size) + 1)
    t = np.linspace(0, 1, n)[:, None]
    pts = a + t * (b - a)
    pts = pts[np.linalg.norm(pts - a, axis=1) > 2 * size]
    h = 0.4
    return [(x - h, y - h, x + h, y + h) for x, y in pts]


class Placer:
    """Places dimensions lane by lane; remembers every box placed (`boxes`)."""

    def __init__(self, obstacles):
        self.boxes = [tuple(b) for b in obstacles]
        #: Boxes of dimension texts and leaders only (a leader must enter its view, not cross a text).
        self.marks = []
        #: The lane last taken on each side of each view: later (longer) dimensions go outside it.
        self.lanes = {}

    def _free(self, box, own_view=None) -> bool:
        return not any(_overlaps(box, b) for b in self.boxes if b is not own_view)

    def place(self, parent: Group, dim, to_sheet, view_box, *, max_lanes: int = 12):
        """Draw `dim` into a new group of `parent`; returns that group."""
        if isinstance(dim, Note):
            return self._note(parent, dim, to_sheet, view_box, max_lanes)
        return self._linear(parent, dim, to_sheet, view_box, max_lanes)

    # -- linear ---------------------------------------------------------------
    def _linear(self, parent, dim: Linear, to_sheet, view_box, max_lanes):
        a, b = np.asarray(to_sheet(dim.a), float), np.asarray(to_sheet(dim.b), float)
        text = dim.prefix + format_value(dim.value)
        horizontal = dim.orient == "h"
        lo_, hi_ = (min(a[0], b[0]), max(a[0], b[0])) if horizontal else (min(a[1], b[1]), max(a[1], b[1]))
        span = hi_ - lo_
        tw = text_width(text, TEXT_SIZE)
        inside = span >= 2 * ARROW[0] + 1.0
        text_inside = span >= tw + 2 * ARROW[0] + 1.0
        sign = {"below": 1.0, "right": 1.0, "above": -1.0, "left": -1.0}[dim.side]
        edge = {"below": view_box[3], "above": view_box[1], "right": view_box[2], "left": view_box[0]}[dim.side]
        key = (tuple(np.round(view_box, 6)), dim.side)
        for lane in range(min(self.lanes.get(key, -1) + 1, max_lanes - 1), max_lanes):
            at = edge + sign * (FIRST_LANE + lane * LANE)
            line_lo, line_hi = (lo_, hi_) if inside else (lo_ - ARROW[0] - 2, hi_ + ARROW[0] + 2)
            # A text that does not fit between the arrows goes beyond the upper end.
            # A text that does not fit goes past the datum end (`a`): the extension lines of the
            # longer dimensions from the same datum, further out, then never cross it.  Just past
            # the end when the arrows are inside, past the outside arrow otherwise.
            beyond = (ARROW[0] + 3.0) if not inside else 1.5
            at_lo = (a[0] if horizontal else a[1]) <= lo_ + 1e-9
            t_along = 0.5 * (lo_ + hi_) if text_inside else \
                (lo_ - beyond - tw / 2 if at_lo else hi_ + beyond + tw / 2)
            t_lo, t_hi = t_along - tw / 2, t_along + tw / 2
            across_lo, across_hi = at - TEXT_SIZE - 1.2, at + 1.0
            if horizontal:
                box = (min(line_lo, t_lo), across_lo, max(line_hi, t_hi), across_hi)
            else:
                box = (across_lo, min(line_lo, t_lo), across_hi, max(line_hi, t_hi))
            if self._free(box):
                break
        self.lanes[key] = lane
        self.boxes.append(box)
        self.marks.append(box)
        g = parent.group(None, "dimension", kind=dim.kind, value=format_value(dim.value), text=text)
        for p in (a, b):
            if horizontal:
                g.line([(p[0], edge + sign * GAP), (p[0], at + sign * OVERSHOOT)], "dimension")
            else:
                g.line([(edge + sign * GAP, p[1]), (at + sign * OVERSHOOT, p[1])], "dimension")

        def pt(along, across):
            return (along, across) if horizontal else (across, along)

        g.line([pt(line_lo, at), pt(line_hi, at)], "dimension")
        if inside:
            arrowhead(g, pt(lo_, at), pt(hi_, at))
            arrowhead(g, pt(hi_, at), pt(lo_, at))
        else:
            arrowhead(g, pt(lo_, at), pt(lo_ - 1, at))
            arrowhead(g, pt(hi_, at), pt(hi_ + 1, at))
        if horizontal:
            g.text(t_along, at - 1.0, text, size=TEXT_SIZE, cls="dimension-text")
        else:
            # Vertical dimensions read from the right-hand side (ISO 129-1, method 1).
            g.text(at - 1.0, t_along, text, size=TEXT_SIZE, rotate=-90.0, cls="dimension-text")
        return g

    # -- notes ----------------------------------------------------------------
    def _note(self, parent, dim: Note, to_sheet, view_box, max_lanes):
        tw = text_width(dim.text, TEXT_SIZE)
        anchors = [np.asarray(dim.anchor, float)]
        if dim.centre is not None:
            # Other points of the same circle, all up and to the right (the leader runs that way).
            c = np.asarray(dim.centre, float)
            r = float(np.linalg.norm(anchors[0] - c))
            anchors += [c + r * np.array([np.cos(a), np.sin(a)]) for a in np.radians((70.0, 20.0, 85.0, 5.0))]
        first = None
        for anchor in anchors:  # a few candidates, each tried lane by lane
            p = np.asarray(to_sheet(anchor), float)
            for lane in range(max_lanes // 2):
                knee_y = view_box[1] - 5.0 - lane * LANE
                knee = np.array([p[0] + p[1] - knee_y, knee_y])
                end = knee + (3.0, 0.0)
                box = (knee[0] - 0.5, knee_y - TEXT_SIZE - 1.0, end[0] + 1.0 + tw, knee_y + 1.5)
                leader = _segment_boxes(p, knee)
                choice = (p, knee, end, box, leader)
                first = first or choice
                if self._free(box) and not any(_overlaps(box, b, 0.3) for b in self.marks) and \
                        not any(_overlaps(a, b, 0.3) for a in leader for b in self.marks):
                    break
            else:
                continue
            break
        else:
            # Nowhere free: the nearest place, rather than a leader across the sheet.
            choice = first
        p, knee, end, box, leader = choice
        knee_y = knee[1]
        self.boxes.append(box)
        self.marks.append(box)
        self.marks.extend(leader)
        g = parent.group(None, "dimension", kind=dim.kind, value=format_value(dim.value), text=dim.text,
                         count=dim.count)
        g.line([p, knee, end], "dimension")
        arrowhead(g, p, knee)
        g.text(end[0] + 1.0, knee_y + 1.2, dim.text, size=TEXT_SIZE, anchor="start", cls="dimension-text")
        return g
