"""DXF (AutoCAD R2010) of a `Drawing` through ezdxf: one layer per line
class with its ISO linetype (CONTINUOUS, DASHED, CENTER) and lineweight,
y pointing up as DXF has it, dimensions as plain geometry and text (the
value in the text), the diameter sign as ``%%c``.

Examples
--------
>>> from spatial.drafting.model import Drawing
>>> d = Drawing(100.0, 50.0)
>>> d.group("view-front", "view").line([(0, 0), (10, 0)], "hidden")
>>> doc = dxf_document(d)
>>> doc.layers.get("HIDDEN").dxf.linetype
'DASHED'
"""

from __future__ import annotations

import os

from ..files import atomic_write
from .model import LINE_STYLES, Circle, Group, Path, Text

__all__ = ["dxf_document", "write_dxf"]

#: DXF lineweights are hundredths of a millimetre from a fixed list.
_WEIGHTS = {0.25: 25, 0.35: 35, 0.5: 50, 0.7: 70}


def _ezdxf():
    try:
        import ezdxf
    except ImportError as exc:  # pragma: no cover - a dependency
        raise ImportError("DXF sheets need ezdxf: pip install ezdxf") from exc
    return ezdxf


def dxf_document(drawing):
    """An ezdxf document (R2010) holding `drawing` in model space, millimetres."""
    ezdxf = _ezdxf()
    doc = ezdxf.new("R2010", setup=True)
    doc.units = 4  # millimetres
    doc.header["$MEASUREMENT"] = 1
    # The setup linetypes are drawn small; this scale gives ISO 128 dashes of about 3 mm.
    doc.header["$LTSCALE"] = 2.4
    for cls, (width, _, layer, linetype) in LINE_STYLES.items():
        if layer not in doc.layers:
            doc.layers.add(layer, linetype=linetype, lineweight=_WEIGHTS.get(width, 25))
    for layer in ("TEXT", "HATCH-FILL"):
        if layer not in doc.layers:
            doc.layers.add(layer, lineweight=25)
    msp = doc.modelspace()
    height = drawing.height

    def flip(points):
        return [(float(x), float(height - y)) for x, y in points]

    def emit(group: Group):
        for item in group.items:
            if isinstance(item, Group):
                emit(item)
            elif isinstance(item, Path):
                layer = LINE_STYLES.get(item.cls, LINE_STYLES["thin"])[2]
                pts = flip(item.points)
                if item.fill:
                    hatch = msp.add_hatch(color=7, dxfattribs={"layer": layer})
                    hatch.paths.add_polyline_path(pts, is_closed=True)
                else:
                    msp.add_lwpolyline(pts, close=item.closed, dxfattribs={"layer": layer})
            elif isinstance(item, Circle):
                layer = LINE_STYLES.get(item.cls, LINE_STYLES["thin"])[2]
                msp.add_circle((item.cx, height - item.cy), item.r, dxfattribs={"layer": layer})
            elif isinstance(item, Text):
                text = item.text.replace("\u2300", "%%c")
                align = {"start": "LEFT", "middle": "CENTER", "end": "RIGHT"}[item.anchor]
                entity = msp.add_text(text, height=item.size * 0.8, rotation=-item.rotate,
                                      dxfattribs={"layer": "TEXT"})
                entity.set_placement((item.x, height - item.y), align=_align(ezdxf, align))

    for g in drawing.groups:
        emit(g)
    return doc


def _align(ezdxf, name):
    from ezdxf.enums import TextEntityAlignment

    return {"LEFT": TextEntityAlignment.LEFT, "CENTER": TextEntityAlignment.CENTER,
            "RIGHT": TextEntityAlignment.RIGHT}[name]


def write_dxf(drawing, path) -> str:
    """Write `drawing` as DXF R2010 to `path` (atomically)."""
    doc = dxf_document(drawing)
    atomic_write(os.fspath(path), lambda tmp: doc.saveas(tmp))
    return os.fspath(path)
