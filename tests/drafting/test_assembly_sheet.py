"""Assembly sheets: exploded parts, balloons, the parts list on the sheet and as CSV."""

import csv
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from implicit import box
from spatial.drafting import assembly_drawing, write_csv
from spatial.drafting.assembly_sheet import axis_offsets
from spatial.drafting.svg import svg_text

NS = {"s": "http://www.w3.org/2000/svg"}
EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")


@pytest.fixture(scope="module")
def example():
    sys.path.insert(0, EXAMPLES)
    try:
        from assembly import assembly
    finally:
        sys.path.remove(EXAMPLES)
    return assembly()


@pytest.fixture(scope="module")
def sheet(example):
    return assembly_drawing(example, name="plate assembly", resolution=32, axis="z")


def test_balloons_number_every_part(sheet):
    drawing, rows = sheet
    root = ET.fromstring(svg_text(drawing))
    balloons = [g for g in root.iter(f"{{{NS['s']}}}g") if g.get("class") == "balloon"]
    assert sorted(g.get("data-part") for g in balloons) == ["block", "bolt", "plate"]
    assert sorted(int(g.get("data-item")) for g in balloons) == [1, 2, 3]
    for g in balloons:
        assert g.find("s:text", NS).text == g.get("data-item")
    assert root.find(".//s:g[@id='view-exploded']", NS) is not None


def test_parts_list_rows_masses_and_csv(sheet, tmp_path):
    drawing, rows = sheet
    by_name = {r.name: r for r in rows}
    assert by_name["plate"].family == "hole_plate" and "hole_diameter=8" in by_name["plate"].parameters
    assert by_name["bolt"].family == "hex_bolt"
    # The block is 20 x 20 x 10 mm of steel (7850 kg/m^3): 31.4 g, to the mesh's accuracy.
    assert by_name["block"].mass == pytest.approx(20 * 20 * 10 * 7850e-9, rel=0.02)
    plate = 100 * 60 * 5 - 6 * np.pi * 4 ** 2 * 5
    assert by_name["plate"].mass == pytest.approx(plate * 7850e-9, rel=0.03)
    root = ET.fromstring(svg_text(drawing))
    table = root.find(".//s:g[@id='parts-list']", NS)
    assert table.get("data-rows") == "3"
    out = write_csv(rows, tmp_path / "parts.csv")
    with open(out, newline="") as f:
        got = list(csv.DictReader(f))
    assert [r["name"] for r in got] == ["plate", "bolt", "block"]
    assert set(got[0]) == {"item", "name", "family", "parameters", "material", "mass_kg", "count"}
    assert float(got[2]["mass_kg"]) == pytest.approx(by_name["block"].mass, rel=1e-5)


def test_identical_parts_are_counted_once():
    parts = {"a": box(10), "b": box(10).translate((30, 0, 0)), "c": box((5, 5, 5), center=(0, 30, 0))}
    _, rows = assembly_drawing(parts, resolution=24, explode=False)
    assert [(r.name, r.count) for r in rows] == [("a", 2), ("c", 1)]


def test_axis_offsets_stack_the_parts_apart():
    lows, highs = np.array([-2.5, -17.5, 15.0]), np.array([2.5, 7.5, 25.0])   # plate, bolt, block
    off = axis_offsets(lows, highs, (0, 0, 2), 5.0)
    assert np.allclose(off[:, :2], 0)
    assert off[:, 2].tolist() == [0.0, 25.0, 22.5]
    lo, hi = lows + off[:, 2], highs + off[:, 2]
    order = np.argsort(hi)
    # Stacked without overlap, 5 apart.
    assert np.allclose(lo[order][1:] - hi[order][:-1], 5.0)


def test_bad_assembly_input():
    with pytest.raises(TypeError, match="parts: expected a non-empty dict"):
        assembly_drawing({})
    with pytest.raises(ValueError, match="explode axis: expected x, y or z"):
        assembly_drawing({"a": box(1)}, axis="w")
    with pytest.raises(ValueError, match="material: expected one of steel"):
        assembly_drawing({"a": box(1)}, material="cheese")


def test_parts_list_is_the_bill_of_materials(example, sheet):
    from spatial.analysis.bom import bill_of_materials

    _, rows = sheet
    bom = bill_of_materials(example, default_material="steel", units="mm", resolution=64)
    assert [(r.item, r.names, r.count, r.material) for r in rows] == \
        [(it.item, tuple(it.names), it.count, it.material) for it in bom.items]
    for r, it in zip(rows, bom.items):
        assert r.mass == pytest.approx(it.mass, rel=1e-12)
