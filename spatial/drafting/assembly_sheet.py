"""An assembly's sheet: the parts in an isometric view, pulled apart along
the directions from the assembly's centroid (or along one axis), a balloon
with its item number on every part, and the parts list above the title block.

Examples
--------
>>> from implicit import box
>>> parts = {"base": box((40, 40, 10)), "cap": box((20, 20, 10), center=(0, 0, 10))}
>>> sheet, rows = assembly_drawing(parts, name="stack", resolution=32)
>>> [g.data["item"] for g in sheet.walk() if g.cls == "balloon"]
['1', '2']
"""

from __future__ import annotations

import numpy as np

from .edges import silhouettes, surface_edges
from .layout import ViewPlace
from .model import Group
from .part_sheet import PAPER_TOLERANCE, check_options, simplify_paper
from .part_views import MIN_PIECE, part_mesh
from .parts_list import MATERIALS, ROW, draw_parts_list, parts_list
from .render import explode_offsets
from .sheet import TITLE_BLOCK, drawing_area, new_sheet
from .units import check_units, unit_label
from .views import choose_scale, scale_text, view_frame
from .visibility import DepthBuffer, classify_polylines

__all__ = ["assembly_drawing", "axis_offsets"]

#: Balloon radius and the distance of balloons from the view (mm on paper).
BALLOON, BALLOON_REACH = 4.5, 14.0


def axis_offsets(lows, highs, axis, gap: float) -> np.ndarray:
    """Offsets (n, 3) along `axis` that stack the parts apart: taken in the order
    of their tops along the axis, each part moves up until it starts `gap`
    above the one before; the lowest part stays.

    Parameters
    ----------
    lows, highs : (n,) float
        Each part's extent along the axis.

    Examples
    --------
    >>> axis_offsets([0, -10, 5], [2, 4, 9], (0, 0, 1), 1.0)[:, 2].tolist()
    [0.0, 13.0, 13.0]
    """
    lows, highs = np.asarray(lows, dtype=float), np.asarray(highs, dtype=float)
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    shift = np.zeros(len(lows))
    top = -np.inf
    for i in np.argsort(highs, kind="stable"):  # one step per part
        shift[i] = 0.0 if not np.isfinite(top) else max(0.0, top + gap - lows[i])
        top = highs[i] + shift[i]
    return shift[:, None] * a[None]


def _parse_axis(axis):
    if axis is None:
        return None
    if isinstance(axis, str):
        key = axis.strip().lower()
        table = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}
        if key not in table:
            raise ValueError(f"explode axis: expected x, y or z, got {axis!r}")
        return np.array(table[key], dtype=float)
    a = np.asarray(axis, dtype=float)
    if a.shape != (3,) or not np.isfinite(a).all() or np.linalg.norm(a) == 0:
        raise ValueError(f"explode axis: expected a nonzero 3-vector, got {axis!r}")
    return a


def assembly_drawing(parts: dict, *, name: str = "assembly", projection: str = "first", sheet: str = "A3",
                     explode: bool = True, axis=None, factor: float = 0.6, resolution: int = 96,
                     material: str = "steel", density: float | None = None, date: str | None = None,
                     units: str | None = None):
    """The exploded (or assembled) isometric view of `parts` with balloons and a parts list.

    Parameters
    ----------
    parts : dict of str to Solid
        Named parts in assembly position, in `units`.
    explode : bool
        Pull the parts apart; otherwise they are drawn assembled.
    axis : {"x", "y", "z"} or (3,) float, optional
        Explode along this axis instead of radially from the centroid.
    factor : float
        How far parts move, as a fraction of the assembly's size.
    material, density :
        For the masses of the parts list (kg/m^3; by default the named material's).
    units : str, optional
        The parts' length unit (`spatial.analysis.UNITS`); without it the sheet and the
        masses say "mm, assumed".

    Returns
    -------
    (Drawing, list of PartRow)
    """
    from implicit import Solid

    if not isinstance(parts, dict) or not parts:
        raise TypeError("parts: expected a non-empty dict of part names to solids")
    for key, solid in parts.items():
        if not isinstance(solid, Solid):
            raise TypeError(f"parts[{key!r}]: expected an implicit Solid, got {type(solid).__name__}")
    check_options(projection, sheet, resolution)
    check_units(units)
    if not np.isfinite(factor) or factor < 0:
        raise ValueError(f"factor: expected a non-negative number, got {factor!r}")
    if density is None:
        if material not in MATERIALS:
            raise ValueError(f"material: expected one of {', '.join(MATERIALS)} or a density, got {material!r}")
        density = MATERIALS[material]
    direction = _parse_axis(axis)
    meshes = {k: part_mesh(s, resolution=resolution) for k, s in parts.items()}
    edges = {k: surface_edges(meshes[k], parts[k]) for k in parts}
    from ..analysis.bom import bill_of_materials

    # The analysis room's bill of materials (its volume error is far below the three digits shown).
    bom = bill_of_materials(parts, default_material=(material, float(density)), units=units or "mm", resolution=64)
    rows = parts_list(bom, parts)
    centroids = np.array([np.asarray(meshes[k].points).mean(axis=0) for k in parts])
    if not explode:
        offsets = np.zeros_like(centroids)
    elif direction is not None:
        along = [np.asarray(m.points) @ direction for m in meshes.values()]
        span = float(np.ptp(np.concatenate(along)))
        offsets = axis_offsets([t.min() for t in along], [t.max() for t in along], direction,
                               0.5 * factor * span)
    else:
        offsets = explode_offsets(centroids, factor)
    frame = view_frame("iso")
    pts, tris, lines, n0 = [], [], [], 0
    h = min(e.voxel_size for e in edges.values())
    for (k, e), off in zip(edges.items(), offsets):
        pts.append(e.points + off)
        tris.append(e.triangles + n0)
        n0 += len(e.points)
        lines.extend(p + off for p in list(e.polylines) + silhouettes(e, frame[2]))
    pts, tris = np.concatenate(pts), np.concatenate(tris)
    buffer = DepthBuffer(pts, tris, frame, pixel=0.5 * h)
    visible, _ = classify_polylines(lines, buffer, frame, tolerance=1.5 * h, min_length=MIN_PIECE * h)
    uv = pts @ frame[:2].T
    extent = (*uv.min(axis=0), *uv.max(axis=0))
    # The view goes above the parts list or beside it, whichever allows the larger scale;
    # balloons need their reach all round.
    x0, y0, x1, y1 = drawing_area(sheet)
    table_h = ROW * (len(rows) + 1)
    room = 2 * (BALLOON_REACH + 2 * BALLOON)
    ew, eh = extent[2] - extent[0], extent[3] - extent[1]
    areas = [(x0, y0, x1, y1 - table_h), (x0, y0, x1 - TITLE_BLOCK[0], y1 + TITLE_BLOCK[1])]

    def scale_in(a):
        return choose_scale(lambda sc: sc * ew <= a[2] - a[0] - room and sc * eh <= a[3] - a[1] - room)

    area = max(areas, key=scale_in)
    s = scale_in(area)
    meta = {"title": name, "projection": projection, "material": material, "scale": scale_text(s),
            "units": unit_label(units) if units else "mm, assumed"}
    if date:
        meta["date"] = date
    drawing, _ = new_sheet(sheet, meta)
    vw, vh = s * ew, s * eh
    place = ViewPlace(0.5 * (area[0] + area[2] - vw), 0.5 * (area[1] + area[3] - vh), s, extent)
    g = drawing.group("view-exploded" if explode else "view-assembly", "view", name="iso", scale=scale_text(s))
    sub = g.group(None, "visible")
    for p in visible:
        q = simplify_paper(place.to_sheet(p))
        if len(q) >= 2 and np.linalg.norm(np.diff(q, axis=0), axis=1).sum() > 2 * PAPER_TOLERANCE:
            sub.line(q, "visible")
    right, bottom = drawing.width - 10.0, drawing.height - 10.0 - TITLE_BLOCK[1]
    table_box = draw_parts_list(drawing.group("parts", "parts"), rows, right, bottom)
    _balloons(drawing.group("balloons", "balloons"), rows, parts, meshes, offsets, frame, place, buffer, h,
              obstacles=[table_box])
    return drawing, rows


def _balloons(group: Group, rows, parts, meshes, offsets, frame, place, buffer, h, obstacles):
    """A numbered balloon per part, its leader ending in a dot on a visible point of the part."""
    names = list(parts)
    x0, y0, x1, y1 = place.box()
    centre = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)])
    placed = [tuple(b) for b in obstacles] + [place.box()]
    item_of = {n: r.item for r in rows for n in r.names}
    for k, name in enumerate(names):
        pts = np.asarray(meshes[name].points) + offsets[k]
        vis = buffer.visible(pts, 1.5 * h)
        cand = pts[vis] if vis.any() else pts
        sheet_pts = place.to_sheet(cand @ frame[:2].T)
        mid = sheet_pts.mean(axis=0)
        anchor = sheet_pts[np.argmin(np.linalg.norm(sheet_pts - mid, axis=1))]
        out = anchor - centre
        out = out / max(np.linalg.norm(out), 1e-9) if np.linalg.norm(out) > 1e-6 else np.array([0.0, -1.0])
        spot = None
        for turn in np.radians([0, 20, -20, 40, -40, 60, -60, 90, -90, 120, -120, 180]):
            rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
            d = rot @ out
            # Out of the view's box along d, then the balloon's reach.
            t_exit = min((v for v in ((x1 - anchor[0]) / d[0] if d[0] > 1e-9 else np.inf,
                                      (x0 - anchor[0]) / d[0] if d[0] < -1e-9 else np.inf,
                                      (y1 - anchor[1]) / d[1] if d[1] > 1e-9 else np.inf,
                                      (y0 - anchor[1]) / d[1] if d[1] < -1e-9 else np.inf)), default=0.0)
            c = anchor + d * (t_exit + BALLOON_REACH * 0.6)
            box = (c[0] - BALLOON, c[1] - BALLOON, c[0] + BALLOON, c[1] + BALLOON)
            if all(box[2] < b[0] or b[2] < box[0] or box[3] < b[1] or b[3] < box[1] for b in placed):
                spot = c
                break
        if spot is None:
            spot = anchor + out * (BALLOON_REACH + 30.0)
        placed.append((spot[0] - BALLOON, spot[1] - BALLOON, spot[0] + BALLOON, spot[1] + BALLOON))
        b = group.group(f"balloon-{name}", "balloon", item=item_of[name], part=name)
        d = spot - anchor
        d = d / max(np.linalg.norm(d), 1e-9)
        b.line([anchor, spot - BALLOON * d], "balloon")
        b.circle(anchor[0], anchor[1], 0.6, "balloon", fill=True)
        b.circle(spot[0], spot[1], BALLOON, "balloon")
        b.text(spot[0], spot[1] + 1.8, str(item_of[name]), size=5.0, cls="balloon-number")
