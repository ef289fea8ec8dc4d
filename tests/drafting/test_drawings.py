"""Drawing sheets: views placed by the projection standard, true dimensions,
hidden lines where hidden holes are, sections, files read back by their readers."""

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from implicit import box, cylinder
from spatial.drafting import part_drawing, write_drawing
from spatial.drafting.svg import svg_text

NS = {"s": "http://www.w3.org/2000/svg"}
RES = 64

#: The test block: 40 x 20 x 10 with four through holes of diameter 8 along z.
HOLES = [(-12.0, -4.0), (12.0, -4.0), (-12.0, 5.0), (12.0, 5.0)]


def block_with_holes():
    return box((40, 20, 10)) - cylinder(4, 30, center=(*HOLES[0], 0)) - cylinder(4, 30, center=(*HOLES[1], 0)) \
        - cylinder(4, 30, center=(*HOLES[2], 0)) - cylinder(4, 30, center=(*HOLES[3], 0))


@pytest.fixture(scope="module")
def first():
    return ET.fromstring(svg_text(part_drawing(block_with_holes(), name="block", resolution=RES)))


@pytest.fixture(scope="module")
def third():
    return ET.fromstring(svg_text(part_drawing(block_with_holes(), name="block", projection="third",
                                               resolution=RES)))


def view(root, name):
    g = root.find(f".//s:g[@id='view-{name}']", NS)
    assert g is not None, f"no view-{name}"
    return g


def dims(root, name):
    return view(root, name).findall(".//s:g[@class='dimension']", NS)


def path_points(g, cls):
    pts = []
    for p in g.findall(f".//s:path[@class='{cls}']", NS):
        nums = [float(x) for x in re.findall(r"-?\d+\.?\d*", p.get("d"))]
        pts.append(np.array(nums).reshape(-1, 2))
    return np.concatenate(pts) if pts else np.zeros((0, 2))


def box_of(g, cls="visible"):
    pts = path_points(g, cls)
    return pts.min(axis=0), pts.max(axis=0)


def test_the_four_views_and_the_title_block_are_there(first):
    ids = {g.get("id") for g in first.iter(f"{{{NS['s']}}}g") if g.get("class") == "view"}
    assert ids == {"view-front", "view-top", "view-side", "view-iso"}
    title = first.find(".//s:g[@id='title-block']", NS)
    assert title.get("data-projection") == "first" and title.get("data-tolerance") == "ISO 2768-m"
    assert title.get("data-units") == "units of the model" and title.get("data-scale") == "2:1"
    texts = [t.text for t in title.iter(f"{{{NS['s']}}}text")]
    assert "block" in texts and "2:1" in texts and any("ISO 2768-m" in t for t in texts)
    assert title.find(".//s:g[@class='projection-symbol']", NS) is not None


def test_overall_sizes_and_hole_callout_are_the_true_ones(first):
    def overall(name):
        return sorted(float(d.get("data-value")) for d in dims(first, name) if d.get("data-kind") == "overall")

    assert overall("front") == [10.0, 40.0]
    assert overall("top") == [20.0, 40.0]
    assert overall("side") == [10.0, 20.0]
    holes = [d for d in dims(first, "top") if d.get("data-kind") == "hole"]
    assert [(h.get("data-text"), h.get("data-count"), h.get("data-value")) for h in holes] == [("4x ⌀8", "4", "8")]
    # Hole positions from the datum corner (-20, -10): x 8 and 32, y 6 and 15.
    pos = sorted(float(d.get("data-value")) for d in dims(first, "top") if d.get("data-kind") == "position")
    assert pos == [6.0, 8.0, 15.0, 32.0]
    # The holes are seen end-on only from above.
    assert not [d for d in dims(first, "front") if d.get("data-kind") == "hole"]


def test_the_dimension_lines_measure_what_they_say(first):
    # On the sheet, an overall dimension spans its value times the scale between its extension lines.
    for d in dims(first, "top"):
        if d.get("data-kind") != "overall":
            continue
        pts = path_points(d, "dimension")
        span = np.ptp(pts[:, 0]) if np.ptp(pts[:, 0]) > np.ptp(pts[:, 1]) else np.ptp(pts[:, 1])
        assert span == pytest.approx(2.0 * float(d.get("data-value")), abs=0.05)


def test_no_two_dimensions_overlap(first):
    boxes = []
    for name in ("front", "top", "side"):
        for d in dims(first, name):
            text = d.find("s:text", NS)
            x, y = float(text.get("x")), float(text.get("y"))
            w, h = 0.6 * 3.5 * len(text.text), 3.5
            boxes.append((x - w / 2, y - h, x + w / 2, y) if not text.get("transform") else (x - h, y - w / 2, x, y + w / 2))
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1], (a, b)


def test_hidden_holes_are_dashed_lines_where_the_holes_are(first):
    front = view(first, "front")
    lo, hi = box_of(front)
    scale = (hi[0] - lo[0]) / 40.0
    assert scale == pytest.approx(2.0, rel=1e-3)
    hidden = front.findall(".//s:path[@class='hidden']", NS)
    assert hidden, "no hidden lines in the front view"
    xs = path_points(front, "hidden")[:, 0]
    model_x = (xs - lo[0]) / scale - 20.0
    # Every hidden line is a hole's silhouette: x = -16, -8, 8 or 16.
    assert np.abs(model_x[:, None] - np.array([-16.0, -8.0, 8.0, 16.0])[None]).min(axis=1).max() < 0.3
    assert set(np.round(model_x).astype(int)) == {-16, -8, 8, 16}
    # The style sheet draws the class dashed.
    style = first.find("s:style", NS).text
    assert re.search(r"\.hidden\{[^}]*stroke-dasharray", style)


def test_a_plain_block_has_no_hidden_lines():
    root = ET.fromstring(svg_text(part_drawing(box((40, 20, 10)), resolution=32)))
    for name in ("front", "top", "side"):
        assert not view(root, name).findall(".//s:path[@class='hidden']", NS)
        assert not view(root, name).findall(".//s:path[@class='center']", NS)


def test_centre_lines_on_the_holes(first):
    top = view(first, "top")
    centre = top.findall(".//s:path[@class='center']", NS)
    assert centre
    lo, hi = box_of(top)
    pts = path_points(top, "center")
    xs = (pts[:, 0] - lo[0]) / 2.0 - 20.0
    # The vertical centre lines of the holes stand at x = -12 and 12.
    vertical = np.isin(np.round(xs, 3), [-12.0, 12.0])
    assert vertical.sum() >= 4


def centre_of(g):
    lo, hi = box_of(g)
    return 0.5 * (lo + hi)


def test_first_angle_puts_the_top_view_below_and_third_angle_above(first, third):
    # SVG y points down: below means a larger y.
    assert centre_of(view(first, "top"))[1] > centre_of(view(first, "front"))[1]
    assert centre_of(view(third, "top"))[1] < centre_of(view(third, "front"))[1]
    for root in (first, third):
        f, s, t = centre_of(view(root, "front")), centre_of(view(root, "side")), centre_of(view(root, "top"))
        assert s[0] > f[0] and s[1] == pytest.approx(f[1], abs=0.6)   # side view right of the front, level
        assert t[0] == pytest.approx(f[0], abs=0.6)                     # top view aligned with the front
    assert third.find(".//s:g[@id='title-block']", NS).get("data-projection") == "third"


def test_section_view_is_hatched_where_the_material_is_cut():
    part = block_with_holes()
    sheet = part_drawing(part, section="y=-4", resolution=RES)
    root = ET.fromstring(svg_text(sheet))
    front = view(root, "front")
    assert front.get("data-section") == "A-A"
    assert "SECTION A-A" in [t.text for t in front.iter(f"{{{NS['s']}}}text")]
    hatch = front.findall(".//s:path[@class='hatch']", NS)
    assert hatch
    # Hatch lines 2.5 mm apart fill the cut area: 40 x 10 less two hole bores of 8 x 10, at scale 2.
    segs = []
    for p in hatch:
        nums = np.array([float(x) for x in re.findall(r"-?\d+\.?\d*", p.get("d"))]).reshape(-1, 2, 2)
        segs.append(nums)
    segs = np.concatenate(segs)
    length = np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum()
    assert length * 2.5 == pytest.approx((40 * 10 - 2 * 8 * 10) * 4.0, rel=0.08)
    d = segs[:, 1] - segs[:, 0]
    assert np.allclose(np.abs(d[:, 0]), np.abs(d[:, 1]), atol=1e-2)           # 45 degrees
    plane = view(root, "top").find(".//s:g[@id='cutting-plane-A']", NS)
    assert plane is not None and plane.get("data-plane") == "y=-4"
    assert [t.text for t in plane.iter(f"{{{NS['s']}}}text")] == ["A", "A"]
    # No hidden lines in a section view.
    assert not front.findall(".//s:path[@class='hidden']", NS)


def test_dxf_reads_back_with_layers_and_linetypes(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    out = tmp_path / "block.dxf"
    write_drawing(part_drawing(block_with_holes(), resolution=48), out)
    doc = ezdxf.readfile(out)
    assert doc.dxfversion == "AC1024"   # R2010
    layers = {layer.dxf.name: layer.dxf.linetype for layer in doc.layers}
    assert layers["VISIBLE"] == "CONTINUOUS" and layers["HIDDEN"] == "DASHED" and layers["CENTER"] == "CENTER"
    on = {}
    for e in doc.modelspace():
        on[e.dxf.layer] = on.get(e.dxf.layer, 0) + 1
    assert on["VISIBLE"] > 10 and on["HIDDEN"] >= 4 and on["CENTER"] >= 4 and on["DIMENSIONS"] > 10
    texts = [e.dxf.text for e in doc.modelspace().query("TEXT")]
    assert "4x %%c8" in texts and "40" in texts


def test_pdf_has_one_page_and_png_the_sheet_size(tmp_path):
    sheet = part_drawing(box((40, 20, 10)), resolution=32)
    pdf = write_drawing(sheet, tmp_path / "s.pdf")
    data = open(pdf, "rb").read()
    assert data.startswith(b"%PDF")
    assert len(re.findall(rb"/Type\s*/Page[^s]", data)) == 1
    png = write_drawing(sheet, tmp_path / "s.png")
    from PIL import Image

    assert Image.open(png).size == (2376, 1680)   # A4 at 8 px/mm
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.pdf", "s.png"]


def test_bad_input_fails_before_any_work_or_file(tmp_path):
    part = box(10)
    with pytest.raises(ValueError, match="projection: expected 'first' or 'third'"):
        part_drawing(part, projection="second")
    with pytest.raises(ValueError, match="sheet: expected one of A4, A3"):
        part_drawing(part, sheet="A7")
    with pytest.raises(ValueError, match="plane: expected 'x=<number>'"):
        part_drawing(part, section="w=3")
    with pytest.raises(TypeError, match="solid: expected an implicit Solid"):
        part_drawing("box")
    with pytest.raises(ValueError, match="output: expected a name ending in .svg, .pdf, .dxf or .png"):
        write_drawing(part_drawing(part, resolution=16), tmp_path / "a.docx")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("projection, side", [("first", "left"), ("third", "right")])
def test_the_side_view_is_seen_from_the_left_in_first_angle_and_from_the_right_in_third(projection, side):
    # A hole at y = +6: seen from the left (-y to the right) it lies left of the middle,
    # seen from the right (+y to the right) right of it.
    part = box((40, 20, 10)) - cylinder(2, 30, center=(0, 6, 0))
    root = ET.fromstring(svg_text(part_drawing(part, projection=projection, resolution=48)))
    g = view(root, "side")
    lo, hi = box_of(g)
    xs = path_points(g, "hidden")[:, 0]
    middle = 0.5 * (lo[0] + hi[0])
    assert xs.size
    assert (xs < middle).all() if side == "left" else (xs > middle).all()


def test_radii_of_rounded_boxes_and_spherical_outlines():
    from implicit import rounded_box, sphere

    rounded = ET.fromstring(svg_text(part_drawing(rounded_box((30, 20, 10), radius=3.0), resolution=48)))
    notes = [d.get("data-text") for d in dims(rounded, "front") if d.get("data-kind") == "radius"]
    assert notes == ["R3"]
    ball = (sphere(10.0) & box(15.0)) - cylinder(3.0, 40)
    root = ET.fromstring(svg_text(part_drawing(ball, resolution=48)))
    assert [d.get("data-text") for d in dims(root, "front") if d.get("data-kind") == "radius"] == ["SR10"]
    assert [d.get("data-text") for d in dims(root, "top") if d.get("data-kind") == "hole"] == ["⌀6"]


def test_dimensions_stay_off_the_other_views(first):
    views = {n: box_of(view(first, n)) for n in ("front", "top", "side", "iso")}
    for name in ("front", "top", "side"):
        for d in dims(first, name):
            text = d.find("s:text", NS)
            x, y = float(text.get("x")), float(text.get("y"))
            for other, (lo, hi) in views.items():
                if other == name:
                    continue
                assert not (lo[0] - 1 < x < hi[0] + 1 and lo[1] - 1 < y < hi[1] + 1), (name, other, text.text)
