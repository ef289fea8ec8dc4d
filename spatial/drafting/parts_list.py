"""The parts list of an assembly drawing: the analysis room's bill of materials, drawn.

Rows come from `spatial.analysis.bom.bill_of_materials` (identical parts,
whatever their placement, counted together; volumes from `mass_properties`),
so a drawing's parts list and ``implicad bom`` agree row for row.  Drawn as a
table above the title block (ISO 7573: the header at the bottom, items
upwards) and written as CSV.

Examples
--------
>>> from implicit import box
>>> from spatial.analysis.bom import bill_of_materials
>>> bom = bill_of_materials({"a": box(10), "b": box(10).translate((30, 0, 0))}, default_material="steel",
...                         resolution=64)
>>> [(r.item, r.name, r.count, round(r.mass, 5)) for r in parts_list(bom, {"a": box(10), "b": box(10)})]
[(1, 'a', 2, 0.00785)]
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass

import numpy as np

from ..analysis.bom import MATERIALS  # noqa: F401  (the densities the drawing knows by name)
from ..files import atomic_write
from .model import Group, text_width

__all__ = ["PartRow", "parts_list", "describe", "write_csv", "draw_parts_list", "MATERIALS"]

#: Column titles and widths (mm) of the drawn table; 180 mm, the title block's width.
COLUMNS = (("ITEM", 12.0), ("NAME", 28.0), ("FAMILY / PARAMETERS", 80.0), ("MATERIAL", 22.0),
           ("MASS kg", 22.0), ("QTY", 16.0))
ROW = 7.0


@dataclass(frozen=True)
class PartRow:
    item: int
    name: str
    family: str
    parameters: str
    material: str
    mass: float
    count: int
    names: tuple


def _untranslated(solid):
    """The part without a final pure translation (its shape, wherever it stands)."""
    if solid.kind == "affine" and np.allclose(solid.matrix, np.eye(3), atol=1e-12):
        return solid.children[0]
    return solid


def describe(solid) -> tuple[str, str]:
    """(family or kind, parameters as text) of a part."""
    node = _untranslated(solid)
    if node.kind == "family":
        values = node.values
        text = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in values.items())
        return node.family_name, text
    if not node.children:
        params = {k: v for k, v in node.params.items() if k not in ("center", "axis", "point")}
        text = ", ".join(f"{k}={'x'.join(f'{x:g}' for x in v) if isinstance(v, list) else f'{v:g}'}"
                         for k, v in params.items() if isinstance(v, (int, float, list)))
        return node.kind, text
    return "CSG", f"{node.count_primitives()} primitives, {node.count_nodes()} nodes"


def parts_list(bom, parts: dict) -> list[PartRow]:
    """Rows of the drawn parts list from a `BillOfMaterials` of `parts`; masses in kg (per part)."""
    rows = []
    for it in bom.items:
        family, params = describe(parts[it.names[0]])
        rows.append(PartRow(it.item, it.names[0], family, params, it.material,
                            float(it.mass) if it.mass is not None else float("nan"), it.count, tuple(it.names)))
    return rows


def csv_text(rows) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["item", "name", "family", "parameters", "material", "mass_kg", "count"])
    for r in rows:
        w.writerow([r.item, r.name, r.family, r.parameters, r.material, f"{r.mass:.6g}", r.count])
    return out.getvalue()


def write_csv(rows, path) -> str:
    """The parts list as CSV (written atomically)."""
    text = csv_text(rows)

    def write(tmp):
        with open(tmp, "w", encoding="utf-8", newline="") as f:
            f.write(text)

    atomic_write(os.fspath(path), write)
    return os.fspath(path)


def _fit(text: str, width: float, size: float) -> list[str]:
    """`text` in at most two lines that fit `width` at `size` (cut with '...' beyond)."""
    chars = max(4, int(width / (0.6 * size)))
    if len(text) <= chars:
        return [text]
    cut = text.rfind(", ", 0, chars)
    first = text[:cut + 1] if cut > 0 else text[:chars]
    rest = text[len(first):].strip()
    if len(rest) > chars:
        rest = rest[:chars - 3] + "..."
    return [first, rest]


def draw_parts_list(group: Group, rows, right: float, bottom: float) -> tuple:
    """The table with its bottom-right corner at (right, bottom); returns its box."""
    width = sum(w for _, w in COLUMNS)
    x0 = right - width
    top = bottom - ROW * (len(rows) + 1)
    table = group.group("parts-list", "parts-list", rows=len(rows))
    table.line([(x0, top), (right, top), (right, bottom), (x0, bottom)], "title", closed=True)
    for k in range(1, len(rows) + 1):
        table.line([(x0, bottom - k * ROW), (right, bottom - k * ROW)], "thin")
    x = x0
    for title, w in COLUMNS:
        if x > x0:
            table.line([(x, top), (x, bottom)], "thin")
        table.text(x + 1.5, bottom - 2.2, title, size=2.2, anchor="start", cls="label", bold=True)
        x += w
    for r in rows:
        y = bottom - (r.item + 1) * ROW + ROW
        cells = [str(r.item), r.name, f"{r.family}: {r.parameters}" if r.parameters else r.family, r.material,
                 f"{r.mass:.3g}", str(r.count)]
        row = table.group(f"part-{r.item}", "part-row", item=r.item, name=r.name, count=r.count,
                          mass=f"{r.mass:.6g}")
        x = x0
        for (title, w), text in zip(COLUMNS, cells):
            size = 2.5 if text_width(text, 2.5) <= w - 2 else 2.0
            lines = _fit(text, w - 2.0, size)
            for i, line in enumerate(lines):
                base = y - 2.2 if len(lines) == 1 else y - 4.3 + 2.6 * i
                row.text(x + 1.0, base, line, size=size, anchor="start", cls="value")
            x += w
    return (x0, top, right, bottom)
