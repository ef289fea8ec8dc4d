"""SVG of a `Drawing`: one ``<g>`` per group with its id and class, one
``<path>`` per line class and group, styles in one ``<style>`` block.

Dimensions keep their value in ``data-value`` (and their kind in
``data-kind``), so a program can read the measurements back.

Examples
--------
>>> from spatial.drafting.model import Drawing
>>> d = Drawing(100.0, 50.0)
>>> d.group("view-front", "view").line([(0, 0), (10, 0)], "visible")
>>> text = svg_text(d)
>>> '<g id="view-front" class="view">' in text, 'class="visible"' in text
(True, True)
"""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from .model import LINE_STYLES, Circle, Group, Path, Text

__all__ = ["svg_text", "FONT"]

#: Font family for every text (DejaVu Sans has the diameter sign).
FONT = "DejaVu Sans, Arial, Helvetica, sans-serif"


def _num(x: float) -> str:
    return f"{x:.3f}".rstrip("0").rstrip(".") if abs(x) < 1e9 else "0"


def _path_data(paths) -> str:
    parts = []
    for p in paths:
        pts = p.points
        s = "M" + " L".join(f"{_num(x)} {_num(y)}" for x, y in pts)
        if p.closed:
            s += " Z"
        parts.append(s)
    return " ".join(parts)


def _style_block() -> str:
    rules = []
    for cls, (width, dash, _, _) in LINE_STYLES.items():
        rule = f"stroke:#000;stroke-width:{width};fill:none;stroke-linecap:round;stroke-linejoin:round"
        if dash:
            rule += ";stroke-dasharray:" + ",".join(f"{d:g}" for d in dash) + ";stroke-linecap:butt"
        rules.append(f".{cls}{{{rule}}}")
    rules.append(".fill{fill:#000;stroke:none}")
    rules.append(f"text{{font-family:{FONT};fill:#000;stroke:none}}")
    return "\n".join(rules)


def _emit(group: Group, out: list, indent: str):
    attrs = ""
    if group.id:
        attrs += f" id={quoteattr(group.id)}"
    attrs += f" class={quoteattr(group.cls)}"
    for k, v in group.data.items():
        attrs += f" data-{k}={quoteattr(v)}"
    out.append(f"{indent}<g{attrs}>")
    inner = indent + "  "
    # Lines of one class share a path; filled shapes and circles follow, texts last.
    by_cls: dict[str, list] = {}
    fills = []
    for item in group.items:
        if isinstance(item, Path):
            (fills if item.fill else by_cls.setdefault(item.cls, [])).append(item)
    for cls, paths in by_cls.items():
        out.append(f'{inner}<path class="{cls}" d="{_path_data(paths)}"/>')
    if fills:
        out.append(f'{inner}<path class="fill" d="{_path_data(fills)}"/>')
    for item in group.items:
        if isinstance(item, Circle):
            cls = "fill" if item.fill else item.cls
            out.append(f'{inner}<circle class="{cls}" cx="{_num(item.cx)}" cy="{_num(item.cy)}" r="{_num(item.r)}"/>')
    for item in group.items:
        if isinstance(item, Text):
            transform = f' transform="rotate({_num(item.rotate)} {_num(item.x)} {_num(item.y)})"' if item.rotate else ""
            weight = ' font-weight="bold"' if item.bold else ""
            out.append(f'{inner}<text x="{_num(item.x)}" y="{_num(item.y)}" font-size="{_num(item.size)}" '
                       f'text-anchor="{item.anchor}"{weight}{transform}>{escape(item.text)}</text>')
    for item in group.items:
        if isinstance(item, Group):
            _emit(item, out, inner)
    out.append(f"{indent}</g>")


def svg_text(drawing) -> str:
    """The SVG document of `drawing` (a sheet `width` x `height` mm)."""
    w, h = drawing.width, drawing.height
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(w)}mm" height="{_num(h)}mm" '
           f'viewBox="0 0 {_num(w)} {_num(h)}">']
    title = drawing.meta.get("title")
    if title:
        out.append(f"  <title>{escape(str(title))}</title>")
    out.append(f"  <style>\n{_style_block()}\n  </style>")
    out.append(f'  <rect x="0" y="0" width="{_num(w)}" height="{_num(h)}" fill="#fff"/>')
    for g in drawing.groups:
        _emit(g, out, "  ")
    out.append("</svg>")
    return "\n".join(out) + "\n"
