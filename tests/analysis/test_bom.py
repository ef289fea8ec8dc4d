"""Bill of materials: identical parts counted, volumes and masses against closed forms, CSV."""

import csv
import io
import math

import pytest

from implicit import box, cylinder
from implicit.families import instance
from spatial.analysis import MATERIALS, bill_of_materials


def test_items_counts_volumes_and_masses():
    bolt = instance("hex_bolt", diameter=10.0, length=20.0, head_height=5.0, across_flats=16.0)
    parts = {"plate": box((100.0, 60.0, 5.0)) - cylinder(4.0, 10.0),
             "bolt a": bolt.translate((-30.0, 0.0, 2.5)),
             "bolt b": bolt.rotate(90.0).translate((30.0, 0.0, 2.5)),
             "spacer": cylinder(6.0, 4.0)}
    bom = bill_of_materials(parts, {"plate": "aluminium", "spacer": ("PTFE", 2200.0)}, default_material="steel")
    assert [it.names for it in bom.items] == [["plate"], ["bolt a", "bolt b"], ["spacer"]]
    plate, bolts, spacer = bom.items
    assert plate.volume == pytest.approx(30000.0 - math.pi * 16 * 5, rel=1e-3)
    assert plate.mass == pytest.approx(plate.volume * 1e-9 * MATERIALS["aluminium"], rel=1e-9)
    head = 1.5 * math.sqrt(3) * (16.0 / math.sqrt(3)) ** 2 * 5.0          # hexagon 16 across flats, 5 high
    assert bolts.volume == pytest.approx(math.pi * 25 * 20 + head, rel=1e-3)
    assert bolts.count == 2 and bolts.family == "hex_bolt" and bolts.parameters["diameter"] == 10.0
    assert bolts.total_mass == pytest.approx(2 * bolts.volume * 1e-9 * 7850.0, rel=1e-9)
    assert spacer.material == "PTFE" and spacer.density == 2200.0
    assert bom.part_count == 4
    rows = list(csv.reader(io.StringIO(bom.to_csv())))
    assert rows[0][:4] == ["item", "part", "family", "parameters"] and len(rows) == 4
    assert rows[2][1] == "bolt a, bolt b" and rows[2][8] == "2"
    assert "total mass" in bom.table()


def test_without_materials_there_is_no_mass():
    bom = bill_of_materials({"a": box(2.0)}, resolution=16)
    assert bom.items[0].mass is None and bom.total_mass is None
    assert bom.items[0].volume == pytest.approx(8.0, rel=2e-3)


def test_bad_input():
    with pytest.raises(ValueError, match="unknown material 'unobtainium'"):
        bill_of_materials({"a": box(1.0)}, {"a": "unobtainium"})
    with pytest.raises(ValueError, match="no part named 'b'"):
        bill_of_materials({"a": box(1.0)}, {"b": "steel"})
    with pytest.raises(TypeError, match="parts"):
        bill_of_materials({})
