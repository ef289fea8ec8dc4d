"""Dimensions measured on the mesh and its sections where the tree knows no holes:
circle fits, through holes of an STL plate, sizes, arcs, and the model's unit on the sheet."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import box, cylinder
from spatial.drafting import part_drawing
from spatial.drafting.measured import fit_arcs, fit_circle, step_for
from spatial.drafting.svg import svg_text

NS = {"s": "http://www.w3.org/2000/svg"}
HOLES = [(-12.0, -4.0), (12.0, -4.0), (-12.0, 5.0), (12.0, 5.0)]


def plate():
    p = box((40, 20, 10))
    for c in HOLES:
        p = p - cylinder(4, 30, center=(*c, 0))
    return p


@pytest.fixture(scope="module")
def stl_plate(tmp_path_factory):
    """The plate written to STL and read back as a level set: no cylinder leaves left."""
    import spatial
    from spatial.cells import mesh_to_solid
    from spatial.files import load_mesh

    path = tmp_path_factory.mktemp("stl") / "plate.stl"
    spatial.mesh(plate(), resolution=80, progress=False).save(str(path))
    return mesh_to_solid(load_mesh(str(path)), 0.5)


@given(cx=st.floats(-50, 50), cy=st.floats(-50, 50), r=st.floats(0.1, 40), a0=st.floats(0, 6.28),
       span=st.floats(0.5, 6.28))
@settings(max_examples=40, deadline=None)
def test_the_circle_fit_is_exact_on_points_of_a_circle_even_on_a_short_arc(cx, cy, r, a0, span):
    t = a0 + np.linspace(0, span, 25)
    c, radius, rms = fit_circle(np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)]))
    assert np.allclose(c, (cx, cy), atol=1e-6 * max(r, 1)) and radius == pytest.approx(r, rel=1e-7)
    assert rms < 1e-6 * r


def test_the_circle_fit_is_the_geometric_least_squares_one():
    # Noisy points: the fit's residuals are orthogonal to its three directions (a stationary point).
    rng = np.random.default_rng(4)
    t = rng.uniform(0, 2.0, 60)
    p = np.column_stack([2 + 5 * np.cos(t), 1 + 5 * np.sin(t)]) + rng.normal(0, 0.05, (60, 2))
    c, r, _ = fit_circle(p)
    d = p - c
    dist = np.linalg.norm(d, axis=1)
    res = dist - r
    assert abs(res.sum()) < 1e-9 and np.abs((res[:, None] * d / dist[:, None]).sum(axis=0)).max() < 1e-9


def test_step_for_is_a_quarter_voxel_rounded_up_to_1_2_5():
    assert [step_for(h) for h in (0.25, 0.3, 0.05, 4.0)] == [0.1, 0.1, 0.02, 1.0]


def test_arcs_of_a_rounded_outline_are_found_with_their_radii():
    # A 20 x 10 rectangle with corners of radius 3, counter-clockwise like a section contour.
    pts = []
    for k, centre in enumerate(((7, 2), (-7, 2), (-7, -2), (7, -2))):
        t = np.radians(90 * k) + np.linspace(0, np.pi / 2, 40)
        arc = np.asarray(centre) + 3 * np.column_stack([np.cos(t), np.sin(t)])
        nxt = ((-7, 2), (-7, -2), (7, -2), (7, 2))[k]
        t_next = np.radians(90 * (k + 1))
        start_next = np.asarray(nxt) + 3 * np.array([np.cos(t_next), np.sin(t_next)])
        pts += [arc, np.linspace(arc[-1], start_next, 30)[1:-1]]
    arcs = fit_arcs(np.concatenate(pts), 0.2)
    assert len(arcs) == 4
    assert [round(a[2], 6) for a in arcs] == [3.0] * 4 and not any(a[4] for a in arcs)
    assert sorted(np.round(a[0], 6).tolist() for a in arcs) == [[-7, -2], [-7, 2], [7, -2], [7, 2]]


@pytest.fixture(scope="module")
def stl_sheet(stl_plate):
    return ET.fromstring(svg_text(part_drawing(stl_plate, name="plate", resolution=64)))


def _dims(root, view):
    return root.find(f".//s:g[@id='view-{view}']", NS).findall(".//s:g[@class='dimension']", NS)


def test_an_stl_plate_gets_the_hole_callout_and_positions_from_its_sections(stl_sheet):
    holes = [d for d in _dims(stl_sheet, "top") if d.get("data-kind") == "hole"]
    assert [(h.get("data-text"), h.get("data-count"), h.get("data-value")) for h in holes] == [("4x ⌀8", "4", "8")]
    pos = sorted(float(d.get("data-value")) for d in _dims(stl_sheet, "top") if d.get("data-kind") == "position")
    assert pos == [6.0, 8.0, 15.0, 32.0]
    overall = sorted(float(d.get("data-value")) for d in _dims(stl_sheet, "front") if d.get("data-kind") == "overall")
    assert overall == [10.0, 40.0]
    # Holes are seen end-on from above only, and get centre crosses there.
    assert not [d for d in _dims(stl_sheet, "front") if d.get("data-kind") == "hole"]


def test_the_tree_s_holes_are_not_called_out_twice():
    root = ET.fromstring(svg_text(part_drawing(plate(), name="plate", resolution=48)))
    holes = [d for d in _dims(root, "top") if d.get("data-kind") == "hole"]
    assert [h.get("data-text") for h in holes] == ["4x ⌀8"]


@pytest.mark.parametrize("units, label, scale", [(None, "units of the model", "2:1"), ("mm", "mm", "2:1"),
                                                 ("cm", "cm", "1:5"), ("m", "m", "1:500")])
def test_the_title_block_states_the_model_unit_and_the_scale_is_true(units, label, scale):
    d = part_drawing(box((40, 20, 10)), name="b", resolution=24, units=units)
    root = ET.fromstring(svg_text(d))
    title = root.find(".//s:g[@id='title-block']", NS)
    assert title.get("data-units") == label and title.get("data-scale") == scale
    assert any(t.text == f"Dimensions in {label}; general tolerances ISO 2768-m" for t in title.iter(f"{{{NS['s']}}}text"))


def test_an_unknown_unit_is_refused_before_any_work():
    with pytest.raises(ValueError, match="units: expected one of"):
        part_drawing(box(1.0), units="furlong")


def _notes(sheet, kind):
    out = []
    for g in sheet.walk():
        if g.cls == "dimension" and g.data.get("kind") == kind:
            out.append(g)
    return out


def _view_of(sheet, note):
    for v in sheet.walk():
        if v.cls == "view" and any(g is note for g in v.walk()):
            return v.data["name"]


def test_a_fillet_in_a_corner_is_a_radius_not_a_hole():
    from implicit.models import load_model

    sheet = part_drawing(load_model("examples/bracket_fillet.py"), name="b", resolution=64)
    radii = [(_view_of(sheet, g), g.data["text"]) for g in _notes(sheet, "radius")]
    # The fillet (a cylinder of radius 5 subtracted from a corner square) is seen end-on from the front.
    assert radii == [("front", "R5")]
    holes = sorted(g.data["text"] for g in _notes(sheet, "hole"))
    assert holes == ["⌀6", "⌀6"]


def test_a_torus_gets_its_tube_radius_where_it_is_seen_from_the_side():
    from implicit import torus

    sheet = part_drawing((cylinder(10, 6) | torus(10, 3)) - cylinder(4, 20), name="w", resolution=48)
    radii = sorted((_view_of(sheet, g), g.data["text"]) for g in _notes(sheet, "radius"))
    assert radii == [("front", "R3"), ("side", "R3")]


def test_measured_arcs_give_the_radius_of_a_fillet_the_tree_does_not_know(tmp_path):
    import spatial
    from spatial.cells import mesh_to_solid
    from implicit.models import load_model

    m = spatial.mesh(load_model("examples/bracket_fillet.py"), resolution=64, progress=False)
    part = mesh_to_solid(m, 0.6)
    sheet = part_drawing(part, name="b", resolution=64)
    front = [float(g.data["value"]) for g in _notes(sheet, "radius") if _view_of(sheet, g) == "front"]
    assert any(abs(r - 5.0) <= 0.3 for r in front), front


def test_an_oblique_hole_gets_its_diameter_and_axis_angle_in_the_view_nearest_its_axis():
    part = box((40, 20, 10)) - cylinder(3, 40).rotate(30, (0, 1, 0))
    sheet = part_drawing(part, name="o", resolution=48)
    notes = [(_view_of(sheet, g), g.data["text"]) for g in _notes(sheet, "oblique-hole")]
    assert notes == [("top", "⌀6, axis 30° from z")]
    # The only plain ⌀ callout is the auxiliary view's, where the hole is seen along its axis.
    assert [_view_of(sheet, g) for g in _notes(sheet, "hole")] == ["aux-B"]


def test_an_oblique_hole_gets_an_auxiliary_view_along_its_axis_with_its_true_circle():
    part = box((40, 20, 10)) - cylinder(3, 40).rotate(30, (0, 1, 0))
    sheet = part_drawing(part, name="o", resolution=48)
    root = ET.fromstring(svg_text(sheet))
    view = root.find(".//s:g[@id='view-B']", NS)
    assert view is not None and view.get("data-name") == "aux-B"
    scale = float(view.get("data-scale"))
    rims = view.findall("s:circle[@class='visible']", NS)
    assert len(rims) == 1 and float(rims[0].get("r")) == pytest.approx(3.0 * scale, abs=0.05)
    assert "VIEW B" in [t.text for t in view.findall("s:text", NS)]
    callout = [d for d in view.findall(".//s:g[@class='dimension']", NS) if d.get("data-kind") == "hole"]
    assert [(d.get("data-text"), float(d.get("data-value"))) for d in callout] == [("⌀6", 6.0)]
    # The arrow with the letter: in the front view, where the axis (turned about y) is in true length.
    arrow = root.find(".//s:g[@id='arrow-B']", NS)
    assert arrow is not None and [t.text for t in arrow.findall(".//s:text", NS)] == ["B"]
    # The mouth on the top face z = 5 lies 5 tan 30° right of the centre: 20 + 2.887 from the left end.
    front = root.find(".//s:g[@id='view-front']", NS)
    pos = [float(d.get("data-value")) for d in front.findall(".//s:g[@class='dimension']", NS)
           if d.get("data-kind") == "position"]
    assert pos == [pytest.approx(20 + 5 * np.tan(np.radians(30)), abs=0.01)]
    # No two views' boxes overlap: the auxiliary view sits in free space.
    b = [g.bbox() for g in sheet.walk() if getattr(g, "cls", None) == "view"]
    for i in range(len(b)):
        for j in range(i + 1, len(b)):
            p, q = b[i], b[j]
            assert not (p[0] < q[2] and q[0] < p[2] and p[1] < q[3] and q[1] < p[3])


def test_the_top_view_of_a_box_with_a_hole_draws_each_true_edge_once():
    # The view's lines are the meshing room's sharp feature curves: on the true edges, single.
    sheet = part_drawing(box((40, 20, 10)) - cylinder(4, 30), name="b", resolution=64)
    top = next(g for g in sheet.walk() if g.cls == "view" and g.data.get("name") == "top")
    lines = [it for g in top.walk() if g.cls == "visible" for it in g.items if getattr(it, "cls", "") == "visible"]
    pts = [np.asarray(it.points, dtype=float) for it in lines]
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    scale = (hi[0] - lo[0]) / 40.0
    assert scale == pytest.approx(2.0, rel=1e-3)
    centre = 0.5 * (lo + hi)
    # Every point is on the rectangle's outline or on the circle of the hole (within 0.05 mm of paper).
    local = allp - centre
    on_rect = np.minimum(np.abs(np.abs(local[:, 0]) - 40), np.abs(np.abs(local[:, 1]) - 20)) < 0.05
    on_rect &= (np.abs(local[:, 0]) <= 40.05) & (np.abs(local[:, 1]) <= 20.05)
    on_circle = np.abs(np.linalg.norm(local, axis=1) - 8.0) < 0.05
    assert (on_rect | on_circle).all()
    # Drawn once: the total length is the true one (a doubled edge would add its length again).
    length = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in pts)
    assert length == pytest.approx(2 * (80 + 40) + 2 * np.pi * 8, rel=0.01)


@pytest.fixture(scope="module")
def flange_sheet():
    from implicit.library.pipes import pipe_flange

    return part_drawing(pipe_flange("DN50"), name="f", resolution=64)


def test_bolt_holes_on_a_circle_are_called_out_on_their_pitch_circle(flange_sheet):
    sheet = flange_sheet
    top = next(g for g in sheet.walk() if g.cls == "view" and g.data.get("name") == "top")
    texts = [g.data["text"] for g in top.walk() if g.cls == "dimension" and g.data.get("kind") == "hole"]
    # EN 1092-1 PN16 DN50: 4 bolt holes of 18 on a 125 circle, placed by it (no odd positions).
    assert sorted(texts) == ["4x ⌀18 on PCD ⌀125", "⌀61.1"]
    pos = sorted(float(g.data["value"]) for g in top.walk() if g.cls == "dimension" and g.data.get("kind") == "position")
    assert pos == [82.5, 82.5]
    # The pitch circle is drawn as a chain line through the four hole centres.
    rings = [it for g in top.walk() if g.cls == "center" for it in g.items if len(it.points) > 100]
    assert len(rings) == 1


def _segment_hits_box(a, b, box, pad=0.3):
    t = np.linspace(0, 1, 200)[:, None]
    p = np.asarray(a) + t * (np.asarray(b) - np.asarray(a))
    return bool(((p[:, 0] > box[0] - pad) & (p[:, 0] < box[2] + pad) & (p[:, 1] > box[1] - pad)
                 & (p[:, 1] < box[3] + pad)).any())


def test_no_leader_crosses_another_dimension_s_text(flange_sheet):
    # Three concentric callouts (bore, bolt holes, outline) on one view: each leader keeps off the others' texts.
    dims = [g for g in flange_sheet.walk() if g.cls == "dimension"]
    texts = {id(g): [it.box() for it in g.items if hasattr(it, "text")] for g in dims}
    notes = [g for g in dims if g.data.get("kind") in ("hole", "diameter", "radius")]
    assert len(notes) >= 3
    for g in notes:
        leader = np.asarray(g.items[0].points)
        for other in dims:
            if other is g:
                continue
            for box in texts[id(other)]:
                for a, b in zip(leader[:-1], leader[1:]):
                    assert not _segment_hits_box(a, b, box), (g.data["text"], other.data["text"])


def test_no_dimension_text_is_crossed_by_another_s_extension_line():
    # The bracket at 1:2: hole positions too short for their texts, which go past the datum end;
    # longer dimensions from that datum lie further out, the overall size outermost.
    from implicit.models import load_model

    sheet = part_drawing(load_model("examples/bracket.py"), name="b", resolution=48, projection="third",
                         section="y=15")
    for view in (g for g in sheet.walk() if g.cls == "view"):
        linear = [g for g in view.walk() if g.cls == "dimension" and g.data.get("kind") in ("position", "overall")]
        for g in linear:
            box = next(it.box() for it in g.items if hasattr(it, "text"))
            for other in linear:
                if other is g:
                    continue
                for ext in other.items[:2]:   # the two extension lines
                    a, b = np.asarray(ext.points)[0], np.asarray(ext.points)[-1]
                    assert not _segment_hits_box(a, b, box, pad=0.0), (view.data["name"], g.data["text"],
                                                                       other.data["text"])
        # Lanes outwards in order of length on each side: the overall size is the outermost.
        below = sorted((float(np.asarray(g.items[2].points)[0, 1]), float(g.data["value"]))
                       for g in linear if np.ptp(np.asarray(g.items[2].points)[:, 1]) < 1e-9)
        assert [v for _, v in below] == sorted(v for _, v in below)


def test_a_blind_hole_of_an_stl_plate_gets_its_depth_from_where_the_sections_stop(tmp_path):
    """Drilled 12 deep into a 16 thick plate: the circle fits stop 4 above the bottom face."""
    import spatial
    from spatial.cells import mesh_to_solid
    from spatial.files import load_mesh

    path = tmp_path / "blind.stl"
    spatial.mesh(box((40, 20, 16)) - cylinder(4, 24, center=(-8, 0, 8)), resolution=80, progress=False).save(str(path))
    root = ET.fromstring(svg_text(part_drawing(mesh_to_solid(load_mesh(str(path)), 0.5), name="blind", resolution=64)))
    holes = [d for d in _dims(root, "top") if d.get("data-kind") == "hole"]
    assert [(d.get("data-text"), d.get("data-value")) for d in holes] == [("⌀8 ↧12", "8")]
    pos = sorted(float(d.get("data-value")) for d in _dims(root, "top") if d.get("data-kind") == "position")
    assert pos == [10.0, 12.0]
