"""The drawing as data: groups of lines, filled shapes, circles and texts on a
sheet, in millimetres with the origin at the sheet's top-left corner and y
pointing down (as SVG has it).  Every writer (SVG, DXF, PDF, PNG) reads this
one structure.

Line classes follow ISO 128-2: ``visible`` continuous wide (0.5 mm),
``hidden`` dashed narrow, ``center`` long-dash dot narrow, ``dimension``
and ``hatch`` continuous narrow (0.25 mm).

Examples
--------
>>> d = Drawing(297.0, 210.0)
>>> g = d.group("view-front", "view")
>>> g.line([(10, 10), (50, 10)], "visible")
>>> d.find("view-front").items[0].cls
'visible'
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["LINE_STYLES", "Path", "Text", "Circle", "Group", "Drawing", "text_width"]

#: Per class: stroke width (mm), dash pattern (mm, None for continuous), DXF layer and linetype.
LINE_STYLES = {
    "visible": (0.5, None, "VISIBLE", "CONTINUOUS"),
    "hidden": (0.25, (3.0, 1.0), "HIDDEN", "DASHED"),
    "center": (0.25, (8.0, 1.0, 1.0, 1.0), "CENTER", "CENTER"),
    "cutting": (0.25, (8.0, 1.0, 1.0, 1.0), "CUTTING", "CENTER"),
    "cutting-end": (0.7, None, "CUTTING", "CONTINUOUS"),
    "dimension": (0.25, None, "DIMENSIONS", "CONTINUOUS"),
    "hatch": (0.25, None, "HATCH", "CONTINUOUS"),
    "border": (0.7, None, "BORDER", "CONTINUOUS"),
    "title": (0.35, None, "TITLE", "CONTINUOUS"),
    "thin": (0.25, None, "TITLE", "CONTINUOUS"),
    "balloon": (0.35, None, "DIMENSIONS", "CONTINUOUS"),
}


def text_width(text: str, size: float) -> float:
    """Width estimate of `text` at height `size` (a sans-serif font's mean advance)."""
    return 0.6 * size * len(text)


@dataclass
class Path:
    points: np.ndarray
    cls: str
    closed: bool = False
    fill: bool = False


@dataclass
class Text:
    x: float
    y: float
    text: str
    size: float = 3.5
    anchor: str = "middle"
    rotate: float = 0.0
    cls: str = "text"
    bold: bool = False

    def box(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) of the text, rotation by multiples of 90 degrees."""
        w, h = text_width(self.text, self.size), self.size
        x0 = {"start": 0.0, "middle": -w / 2, "end": -w}[self.anchor]
        corners = np.array([[x0, -h], [x0 + w, -h], [x0, 0.2 * h], [x0 + w, 0.2 * h]])
        a = np.radians(self.rotate)
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        c = corners @ rot.T + (self.x, self.y)
        return float(c[:, 0].min()), float(c[:, 1].min()), float(c[:, 0].max()), float(c[:, 1].max())


@dataclass
class Circle:
    cx: float
    cy: float
    r: float
    cls: str
    fill: bool = False


@dataclass
class Group:
    id: str | None
    cls: str
    items: list = field(default_factory=list)
    data: dict = field(default_factory=dict)

    def line(self, points, cls: str, *, closed: bool = False):
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(pts) >= 2:
            self.items.append(Path(pts, cls, closed))

    def polygon(self, points, cls: str):
        self.items.append(Path(np.asarray(points, dtype=float).reshape(-1, 2), cls, True, True))

    def circle(self, cx, cy, r, cls: str, *, fill: bool = False):
        self.items.append(Circle(float(cx), float(cy), float(r), cls, fill))

    def text(self, x, y, text, **kw):
        self.items.append(Text(float(x), float(y), str(text), **kw))

    def group(self, id, cls, **data) -> "Group":
        g = Group(id, cls, [], {k: str(v) for k, v in data.items()})
        self.items.append(g)
        return g

    def walk(self):
        """Every group below and including this one."""
        yield self
        for item in self.items:
            if isinstance(item, Group):
                yield from item.walk()

    def bbox(self):
        """(x0, y0, x1, y1) over all items, or None."""
        boxes = []
        for item in self.items:
            if isinstance(item, Group):
                b = item.bbox()
                if b:
                    boxes.append(b)
            elif isinstance(item, Path):
                boxes.append((*item.points.min(axis=0), *item.points.max(axis=0)))
            elif isinstance(item, Circle):
                boxes.append((item.cx - item.r, item.cy - item.r, item.cx + item.r, item.cy + item.r))
            elif isinstance(item, Text):
                boxes.append(item.box())
        if not boxes:
            return None
        b = np.array(boxes, dtype=float)
        return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


@dataclass
class Drawing:
    """A sheet: its size in mm and its groups, with metadata for the title block."""

    width: float
    height: float
    groups: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)

    def group(self, id, cls, **data) -> Group:
        g = Group(id, cls, [], {k: str(v) for k, v in data.items()})
        self.groups.append(g)
        return g

    def walk(self):
        for g in self.groups:
            yield from g.walk()

    def find(self, id) -> Group | None:
        return next((g for g in self.walk() if g.id == id), None)
