"""A part's drawing sheet: four views by a projection standard, one scale,
hidden and centre lines, automatic dimensions, an optional section A-A,
the frame and the title block.

Examples
--------
>>> from implicit import box, cylinder
>>> part = box((40, 20, 10)) - cylinder(4, 30, center=(10, 0, 0))
>>> sheet = part_drawing(part, name="plate", resolution=48)
>>> sorted(g.id for g in sheet.walk() if g.cls == "view")
['view-front', 'view-iso', 'view-side', 'view-top']
"""

from __future__ import annotations

import numpy as np

from .auto_dims import view_dimensions
from .dimensions import FIRST_LANE, LANE, Linear, Note, Placer, TEXT_SIZE, arrowhead
from .layout import place_grid
from .model import Drawing, Group
from .part_views import ViewLines, exact_bounds, part_mesh, present_features, view_lines
from .edges import surface_edges
from .aux_view import draw_auxiliary_views, oblique_holes
from .measured import is_measured, measured_holes, section_arcs, snap, snap_to_holes, step_for
from .units import check_units, paper_per_unit, unit_label
from .section_view import hatch_segments, plan_section, section_loops
from .sheet import SHEETS, TITLE_BLOCK, drawing_area, new_sheet
from .views import PROJECTIONS, grid, scale_text

__all__ = ["part_drawing", "check_options", "emit_view_lines", "simplify_paper"]

#: Simplification tolerance of drawn polylines on paper (mm).
PAPER_TOLERANCE = 0.03
#: Centre lines overshoot the outline of their feature by this much on paper (mm).
CENTRE_OVERSHOOT = 3.0
#: Hatch spacing on paper (mm).
HATCH_SPACING = 2.5


def check_options(projection, sheet, resolution):
    if projection not in PROJECTIONS:
        raise ValueError(f"projection: expected 'first' or 'third', got {projection!r}")
    if sheet not in SHEETS:
        raise ValueError(f"sheet: expected one of {', '.join(SHEETS)}, got {sheet!r}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 16 <= resolution <= 1024:
        raise ValueError(f"resolution: expected a whole number from 16 to 1024, got {resolution!r}")


def simplify_paper(points: np.ndarray) -> np.ndarray:
    """A sheet polyline with the points dropped that stay within `PAPER_TOLERANCE` of it
    (Douglas-Peucker, scikit-image); also drops the mesh's back-and-forth steps along an edge."""
    from skimage.measure import approximate_polygon

    if len(points) <= 2:
        return points
    return approximate_polygon(points, PAPER_TOLERANCE)


def emit_view_lines(group: Group, view: ViewLines, place, *, centre_lines: bool = True):
    """Visible, hidden and centre lines of `view` into `group` at `place`."""
    for cls, lines in (("hidden", view.hidden), ("visible", view.visible)):
        sub = group.group(None, cls)
        for p in lines:
            q = simplify_paper(place.to_sheet(p))
            if len(q) >= 2 and np.linalg.norm(q[-1] - q[0]) + np.linalg.norm(np.diff(q, axis=0), axis=1).sum() > 0.05:
                sub.line(q, cls)
    if not centre_lines:
        return
    sub = group.group(None, "center")
    for a, b in view.axes:
        pa, pb = place.to_sheet(np.array(a)), place.to_sheet(np.array(b))
        d = pb - pa
        n = np.linalg.norm(d)
        if n < 1e-9:
            continue
        d /= n
        sub.line([pa - CENTRE_OVERSHOOT * d, pb + CENTRE_OVERSHOOT * d], "center")
    for c, r in view.pitch_circles:
        t = np.linspace(0, 2 * np.pi, 145)
        ring = np.asarray(c) + r * np.column_stack([np.cos(t), np.sin(t)])
        sub.line(place.to_sheet(ring), "center")
    for c, r in view.centres:
        pc = place.to_sheet(np.array(c))
        arm = r * place.scale + CENTRE_OVERSHOOT
        sub.line([pc - (arm, 0), pc + (arm, 0)], "center")
        sub.line([pc - (0, arm), pc + (0, arm)], "center")


def _margins(dims) -> tuple:
    """Room (mm) each side of a view needs for its dimensions, lane by lane."""
    count = {"left": 0, "right": 0, "above": 0, "below": 0}
    for d in dims:
        count["above" if isinstance(d, Note) else d.side] += 1

    def room(n, text_outside=0.0, first=FIRST_LANE):
        return first + (n - 1) * LANE + 3.0 + text_outside if n else 6.0

    return (room(count["left"], TEXT_SIZE + 1.5), room(count["right"]), room(count["above"], TEXT_SIZE, 5.0),
            room(count["below"]))


def part_drawing(solid, *, name: str = "part", projection: str = "first", sheet: str = "A4",
                 section: str | None = None, resolution: int = 160, material: str | None = None,
                 date: str | None = None, scale: float | None = None, units: str | None = None,
                 units_assumed: bool = False) -> Drawing:
    """The drawing of one part.

    Parameters
    ----------
    solid : implicit.Solid
        A bounded solid, in `units`.
    name : str
        Part name for the title block.
    projection : {"first", "third"}
        ISO 5456-2 first-angle or ASME Y14.3 third-angle placement.
    sheet : {"A4", "A3", "A2"}
    section : str, optional
        A cutting plane ``"x=c"``, ``"y=c"`` or ``"z=c"``: the view along its
        normal becomes SECTION A-A.
    resolution : int
        Voxels across the part's longest side for the drawing mesh.
    scale : float, optional
        Paper mm per model unit; by default the largest standard scale that fits.
    units : str, optional
        The model's length unit (``"mm"``, ``"m"``...: `spatial.analysis.UNITS`), stated in the
        title block and making the scale a true ratio; None draws in "units of the model".
    units_assumed : bool
        The model declares no unit and `units` is the caller's assumption: the title
        block says so ("m, assumed"), as the report and the mass output do.

    Returns
    -------
    Drawing
    """
    from implicit import Solid

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected an implicit Solid, got {type(solid).__name__}")
    check_options(projection, sheet, resolution)
    check_units(units)
    plan = plan_section(section, projection) if section is not None else None
    mesh = part_mesh(solid, resolution=resolution)
    if mesh.n_cells == 0:
        raise ValueError("solid: nothing to draw (the solid is empty)")
    edges = surface_edges(mesh, solid)
    h = edges.voxel_size
    bounds = exact_bounds(solid, mesh)
    if is_measured(solid):
        # Sizes measured on the mesh are drawn to the precision the mesh gives them.
        bounds = tuple(snap(b, step_for(h)) for b in bounds)
    features = present_features(solid, h)
    measured = measured_holes(solid, bounds, h, known=features, mesh=mesh)
    features = features + measured
    if measured and is_measured(solid):
        # The mesh's edges round the measured holes, moved onto the fitted walls.
        edges.polylines = [snap_to_holes(p, measured, 1.5 * h) for p in edges.polylines]
    views, loops = {}, None
    for view_name, _ in grid(projection):
        if plan is not None and view_name == plan.section_view:
            cut = plan.cut(solid)
            cut_mesh = part_mesh(cut, resolution=resolution)
            cut_edges = surface_edges(cut_mesh, cut)
            views[view_name] = view_lines(cut, cut_mesh, cut_edges, view_name, projection=projection,
                                          hidden=False, features=present_features(cut, h), bounds=bounds)
            loops = section_loops(solid, plan, views[view_name].frame, resolution=max(256, 2 * resolution))
        else:
            views[view_name] = view_lines(solid, mesh, edges, view_name, projection=projection,
                                          hidden=view_name != "iso", features=features, bounds=bounds)
    arcs = {}
    if is_measured(solid):
        # Radii the tree cannot give: arcs of the middle section across each view direction.
        for v in views:
            if v != "iso":
                arcs[v] = [_snapped_arc(a, step_for(h)) for a in
                           section_arcs(solid, bounds, h, axis=int(np.argmax(np.abs(views[v].frame[2]))))]
    dims = {v: view_dimensions(v, views[v].frame, views[v].extent, views[v].features, solid, h, arcs.get(v, ()))
            for v in views}
    cells = {}
    for view_name, cell in grid(projection):
        margins = _margins(dims[view_name])
        if plan is not None and view_name in (plan.section_view, plan.line_view):
            margins = tuple(m + (8.0 if i >= 2 else 4.0) for i, m in enumerate(margins))
        cells[view_name] = (cell, tuple(views[view_name].extent), margins)
    unit_mm = paper_per_unit(units)
    s, places = place_grid(cells, drawing_area(sheet), scale=scale, unit_mm=unit_mm)
    meta = {"title": name, "projection": projection, "material": material or "-", "scale": scale_text(s / unit_mm),
            "units": unit_label(units) + (", assumed" if units_assumed and units is not None else "")}
    if date:
        meta["date"] = date
    drawing, _ = new_sheet(sheet, meta)
    boxes = [p.box() for p in places.values()]
    tb = (drawing.width - 10.0 - TITLE_BLOCK[0], drawing.height - 10.0 - TITLE_BLOCK[1],
          drawing.width - 10.0, drawing.height - 10.0)
    placer = Placer(boxes + [tb])
    for view_name, view in views.items():
        place = places[view_name]
        g = drawing.group(f"view-{view_name}", "view", name=view_name, scale=scale_text(s / unit_mm),
                          section="A-A" if plan is not None and view_name == plan.section_view else "")
        if plan is not None and view_name == plan.section_view:
            _hatch(g, loops, place)
        emit_view_lines(g, view, place, centre_lines=True)
        if plan is not None and view_name == plan.line_view:
            placer.boxes.append(_cutting_plane(g, plan, view, place).bbox())
        dg = g.group(None, "dimensions")
        ordered = sorted(dims[view_name], key=lambda d: (isinstance(d, Note), abs(d.value) if isinstance(d, Linear) else 0))
        for d in ordered:
            placer.place(dg, d, place.to_sheet, place.box())
        if plan is not None and view_name == plan.section_view:
            x0, _, x1, _ = place.box()
            below = g.bbox()[3]
            g.text(0.5 * (x0 + x1), below + 7.0, "SECTION A-A", size=5.0, cls="view-label", bold=True)
            placer.boxes.append(g.items[-1].box())
    draw_auxiliary_views(drawing, views, places, oblique_holes(features), placer, drawing_area(sheet), s)
    return drawing


def _snapped_arc(arc, step):
    from dataclasses import replace

    return replace(arc, radius=float(snap(arc.radius, step)))


def _hatch(group: Group, loops, place):
    if not loops:
        return
    sub = group.group(None, "hatch")
    sheet_loops = [place.to_sheet(l) for l in loops]
    for seg in hatch_segments(sheet_loops, HATCH_SPACING):
        sub.line(seg, "hatch")


def _cutting_plane(group: Group, plan, view: ViewLines, place):
    """The cutting plane edge-on: chain line, thick ends, arrows and letters (ISO 128-40)."""
    umin, vmin, umax, vmax = view.extent
    frame = view.frame
    point = np.zeros(3)
    point[plan.axis] = plan.offset
    normal2 = frame[:2] @ np.eye(3)[plan.axis]
    along2 = np.array([-normal2[1], normal2[0]])
    c2 = frame[:2] @ point
    # The line's two ends, 6 mm beyond the outline on paper.
    ts = (np.array([umin, vmin, umax, vmax]).reshape(2, 2) - c2) @ along2
    t0, t1 = ts.min() - 6.0 / place.scale, ts.max() + 6.0 / place.scale
    a = place.to_sheet(c2 + t0 * along2)
    b = place.to_sheet(c2 + t1 * along2)
    g = group.group("cutting-plane-A", "cutting-plane", plane=plan.plane, name="A")
    d = (b - a) / np.linalg.norm(b - a)
    g.line([a, b], "cutting")
    g.line([a, a + 6.0 * d], "cutting-end")
    g.line([b, b - 6.0 * d], "cutting-end")
    view_dir = place.to_sheet(frame[:2] @ np.asarray(plan.direction)) - place.to_sheet(np.zeros(2))
    view_dir = view_dir / max(np.linalg.norm(view_dir), 1e-12)
    for end in (a + 2.0 * d, b - 2.0 * d):
        tip = end + 7.0 * view_dir
        g.line([end, tip], "dimension")
        arrowhead(g, tip, end)
        label = tip + 3.5 * view_dir + (0, TEXT_SIZE * 0.4)
        g.text(label[0], label[1], "A", size=5.0, cls="view-label", bold=True)
    return g
