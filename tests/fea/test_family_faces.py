"""A part family's own face names carried through the FEA: `implicad fea --fix hole_1.wall`,
the set-name mapping it prints, CalculiX's reactions on the named faces, `implicad info`."""

import json

import numpy as np
import pytest

from spatial.cli import main
from spatial.fea import read_frd

MODEL = ("from implicit.families import instance\n"
         "solid = instance('hole_plate', length=60, width=20, thickness=5, hole_diameter=6, rows=1, cols=2,"
         " margin=15)\n")


def test_family_model_solved_with_a_fix_and_a_load_on_family_named_faces(tmp_path, capsys):
    model = tmp_path / "plate.py"
    model.write_text(MODEL)
    deck = tmp_path / "plate.inp"
    status = main(["fea", str(model), "-o", str(deck), "--size", "2.5", "--fix", "hole_1.wall",
                   "--load", "hole_2.wall=0,0,-200", "--solve", "--no-progress"])
    out = capsys.readouterr().out
    assert status == 0, out
    # the mapping printed: the family's names and the sets they became in the deck
    assert "hole_1.wall -> HOLE_1_WALL" in out and "hole_2.wall -> HOLE_2_WALL" in out
    assert "plate.top -> PLATE_TOP" in out and "cylinder_" not in out and "box_" not in out
    text = deck.read_text()
    assert "*NSET, NSET=HOLE_1_WALL" in text
    grid = read_frd(tmp_path / "plate.frd")
    # CalculiX's reactions on the clamped hole balance the load on the other one
    nodes = _set_nodes(text, "HOLE_1_WALL")
    ids = np.asarray(grid.field_data["node_ids"])
    order = np.argsort(ids)
    index = order[np.searchsorted(ids[order], nodes)]
    assert np.array_equal(ids[index], nodes)
    reaction = np.asarray(grid.point_data["FORC"])[index].sum(axis=0)
    np.testing.assert_allclose(reaction, [0.0, 0.0, 200.0], atol=0.05)
    uz = float(out.split("mean displacement of hole_2.wall: (")[1].split(")")[0].split(",")[2])
    assert uz < 0


def _set_nodes(text, name):
    """The node numbers of ``*NSET, NSET=name``."""
    lines = text.splitlines()
    start = lines.index(f"*NSET, NSET={name}")
    out = []
    for line in lines[start + 1:]:
        if line.startswith("*"):
            break
        out.extend(int(v) for v in line.split(",") if v.strip())
    return np.array(out)


def test_info_lists_every_face_the_family_names(tmp_path, capsys):
    model = tmp_path / "plate.py"
    model.write_text(MODEL)
    assert main(["info", str(model), "--json"]) == 0
    faces = json.loads(capsys.readouterr().out)["faces"]
    assert faces == ["hole_1.wall", "hole_2.wall", "plate.+x", "plate.+y", "plate.-x", "plate.-y", "plate.bottom",
                     "plate.top"]
    assert main(["info", str(model)]) == 0
    assert "hole_1.wall, hole_2.wall, plate.+x" in capsys.readouterr().out
    # an unknown face: one line naming the family's faces, exit 2, nothing written
    status = main(["fea", str(model), "-o", str(tmp_path / "x.inp"), "--size", "3", "--fix", "cylinder_1.wall"])
    err = capsys.readouterr().err
    assert status == 2 and "no face named 'cylinder_1.wall'" in err and "hole_1.wall" in err
    assert not (tmp_path / "x.inp").exists()
