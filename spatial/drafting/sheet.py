"""Sheets: ISO 5457 sizes and frames, the title block and the projection symbol.

The frame leaves 20 mm on the left for filing and 10 mm elsewhere; the
title block (180 mm wide) sits in the bottom-right corner and states the
part, scale, units, general tolerances (ISO 2768-m), projection method by
its symbol (ISO 5456-2), date and sheet number.

Examples
--------
>>> d, area = new_sheet("A4", {"title": "plate", "scale": "2:1", "projection": "first"})
>>> d.width, d.height, d.find("title-block").data["projection"]
(297.0, 210.0, 'first')
"""

from __future__ import annotations

import datetime

from .units import UNKNOWN
from .model import Drawing, Group

__all__ = ["SHEETS", "new_sheet", "drawing_area", "projection_symbol", "TITLE_BLOCK"]

#: Landscape sheet sizes (mm).
SHEETS = {"A4": (297.0, 210.0), "A3": (420.0, 297.0), "A2": (594.0, 420.0)}

#: Title block width and height (mm).
TITLE_BLOCK = (180.0, 32.0)

_MARGIN_LEFT, _MARGIN = 20.0, 10.0


def projection_symbol(group: Group, x: float, y: float, projection: str, size: float = 8.0):
    """The truncated cone of ISO 5456-2 with its left edge at `x`, centred on `y`.

    The end view shows both circles as visible lines, so it looks at the
    small end; placed on the right, it was seen from the left (first angle:
    the large end faces it) or from the right (third angle: the small end
    faces it).
    """
    big, small, length, gap = size / 2, size / 4, size, size * 0.6
    near, far = (big, small) if projection == "first" else (small, big)
    x0, x1 = x, x + length
    group.line([(x0, y - far), (x1, y - near), (x1, y + near), (x0, y + far)], "title", closed=True)
    cx = x1 + gap + big
    group.circle(cx, y, big, "title")
    group.circle(cx, y, small, "title")
    group.line([(x0 - 1.5, y), (cx + big + 1.5, y)], "center")
    group.line([(cx, y - big - 1.5), (cx, y + big + 1.5)], "center")
    return cx + big


def drawing_area(size: str) -> tuple:
    """(x0, y0, x1, y1): the free area inside the frame, above the title block."""
    if size not in SHEETS:
        raise ValueError(f"sheet: expected one of {', '.join(SHEETS)}, got {size!r}")
    w, h = SHEETS[size]
    return (_MARGIN_LEFT + 2.0, _MARGIN + 2.0, w - _MARGIN - 2.0, h - _MARGIN - TITLE_BLOCK[1] - 2.0)


def new_sheet(size: str, meta: dict) -> tuple[Drawing, tuple]:
    """A sheet with its frame and title block.

    Parameters
    ----------
    size : {"A4", "A3", "A2"}
    meta : dict
        ``title``, ``scale`` (text), ``projection`` ("first"/"third"),
        optional ``units``, ``tolerance``, ``material``, ``sheet``, ``date``.

    Returns
    -------
    (Drawing, (x0, y0, x1, y1))
        The sheet, and the free drawing area inside the frame above the title block.
    """
    if size not in SHEETS:
        raise ValueError(f"sheet: expected one of {', '.join(SHEETS)}, got {size!r}")
    w, h = SHEETS[size]
    meta = dict(meta)
    meta.setdefault("units", UNKNOWN)
    meta.setdefault("tolerance", "ISO 2768-m")
    meta.setdefault("date", datetime.date.today().isoformat())
    meta.setdefault("sheet", "1/1")
    meta["size"] = size
    drawing = Drawing(w, h, meta=meta)
    fx0, fy0, fx1, fy1 = _MARGIN_LEFT, _MARGIN, w - _MARGIN, h - _MARGIN
    border = drawing.group("frame", "frame")
    border.line([(fx0, fy0), (fx1, fy0), (fx1, fy1), (fx0, fy1)], "border", closed=True)
    # Centring marks (ISO 5457) at the middle of each side.
    for (x, y), (x2, y2) in (((w / 2, 0), (w / 2, fy0)), ((w / 2, h), (w / 2, fy1)), ((0, h / 2), (fx0, h / 2)),
                             ((w, h / 2), (fx1, h / 2))):
        border.line([(x, y), (x2, y2)], "border")
    _title_block(drawing, fx1, fy1, meta)
    return drawing, drawing_area(size)


def _title_block(drawing: Drawing, right: float, bottom: float, meta: dict):
    bw, bh = TITLE_BLOCK
    x0, y0 = right - bw, bottom - bh
    g = drawing.group("title-block", "title-block", projection=meta.get("projection", ""),
                      scale=meta.get("scale", ""), units=meta["units"], tolerance=meta["tolerance"])
    g.line([(x0, y0), (right, y0), (right, bottom), (x0, bottom)], "border", closed=True)
    c1, c2 = x0 + 105.0, x0 + 140.0
    ym = y0 + bh / 2
    g.line([(c1, y0), (c1, bottom)], "title")
    g.line([(c2, y0), (c2, bottom)], "title")
    g.line([(x0, ym), (right, ym)], "title")
    g.line([(x0, ym + 8.0), (c1, ym + 8.0)], "title")

    def label(x, y, text):
        g.text(x + 1.5, y + 3.2, text, size=2.2, anchor="start", cls="label")

    def value(x, y, text, size=3.5, bold=False):
        g.text(x, y, text, size=size, anchor="start", cls="value", bold=bold)

    label(x0, y0, "TITLE")
    value(x0 + 3.0, y0 + 12.5, str(meta.get("title", "")), size=5.0, bold=True)
    label(x0, ym, "UNITS AND GENERAL TOLERANCES")
    value(x0 + 3.0, ym + 7.0, f"Dimensions in {meta['units']}; general tolerances {meta['tolerance']}", size=2.8)
    label(x0, ym + 8.0, "MATERIAL")
    value(x0 + 3.0, ym + 14.5, str(meta.get("material", "-")), size=2.8)
    label(c1, y0, "SCALE")
    value(c1 + 3.0, y0 + 12.5, str(meta.get("scale", "")), size=5.0, bold=True)
    label(c1, ym, "DATE")
    value(c1 + 3.0, ym + 11.0, str(meta["date"]), size=3.0)
    label(c2, y0, f"{meta.get('projection', 'first').upper()} ANGLE PROJECTION")
    sym = g.group("projection-symbol", "projection-symbol", projection=meta.get("projection", "first"))
    projection_symbol(sym, c2 + 10.0, y0 + 10.5, meta.get("projection", "first"), size=8.0)
    label(c2, ym, f"SHEET  ({meta['size']})")
    value(c2 + 3.0, ym + 11.0, str(meta["sheet"]), size=3.5)
