"""Writing a `Drawing`: SVG (the project's own writer), PDF and PNG (the same
SVG rendered by CairoSVG, so every format shows the same sheet) and DXF
(`dxf`).  Files are written atomically.

Examples
--------
>>> check_output("sheet.pdf")
'.pdf'
>>> check_output("sheet.doc")
Traceback (most recent call last):
...
ValueError: output: expected a name ending in .svg, .pdf, .dxf or .png, got 'sheet.doc'
"""

from __future__ import annotations

import os

from ..files import atomic_write
from .svg import svg_text

__all__ = ["FORMATS", "check_output", "write_drawing"]

FORMATS = (".svg", ".pdf", ".dxf", ".png")

#: Pixels per paper millimetre of PNG sheets (about 200 dpi).
PNG_PX_PER_MM = 8.0


def check_output(path) -> str:
    """The extension of `path` when it is a drawing format and its folder exists."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"output: expected a file name, got {type(path).__name__}")
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"output: expected a name ending in .svg, .pdf, .dxf or .png, got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    return ext


def write_drawing(drawing, path) -> str:
    """Write `drawing` to `path` in the format its extension names; returns the path."""
    ext = check_output(path)
    path = os.fspath(path)
    if ext == ".dxf":
        from .dxf import write_dxf

        write_dxf(drawing, path)
        return path
    text = svg_text(drawing)
    if ext == ".svg":
        def write(tmp):
            with open(tmp, "w", encoding="utf-8") as f:
                f.write(text)
    else:
        try:
            import cairosvg
        except (ImportError, OSError) as exc:  # pragma: no cover - a dependency
            raise ImportError("PDF and PNG sheets need CairoSVG and libcairo: pip install cairosvg") from exc

        def write(tmp):
            if ext == ".pdf":
                cairosvg.svg2pdf(bytestring=text.encode("utf-8"), write_to=tmp)
            else:
                cairosvg.svg2png(bytestring=text.encode("utf-8"), write_to=tmp,
                                 output_width=int(round(drawing.width * PNG_PX_PER_MM)),
                                 output_height=int(round(drawing.height * PNG_PX_PER_MM)), background_color="white")
    atomic_write(path, write)
    return path
