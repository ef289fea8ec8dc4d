"""Sizes too coarse for a part's narrowest gap even when graded are refused before any work, naming the size that can."""

import os
import runpy
import time

import pytest
from hypothesis import given, settings, strategies as st

from implicit import extrude, polygon
from spatial.cli import main
from spatial.fea import tet_mesh
from spatial.fea.resolve import check_resolvable, narrowest_gap

GEAR = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "gear.py")


def _slot(width):
    """A U-shaped profile 10 x 10 with a slot of `width` from the top down to y = 2."""
    a, b = 5 - width / 2, 5 + width / 2
    return extrude(polygon([[0, 0], [10, 0], [10, 10], [b, 10], [b, 2], [a, 2], [a, 10], [0, 10]]), 5.0)


@settings(max_examples=10, deadline=None)
@given(width=st.floats(0.5, 3.0))
def test_the_narrowest_gap_of_a_slot_is_its_width(width):
    found = narrowest_gap(_slot(width), 4.0)
    assert found is not None and found[0] == pytest.approx(width, abs=0.06)
    assert abs(found[1][0] - 5.0) < 0.1 and 2.0 < found[1][1] < 10.0


def test_wide_gaps_and_solids_without_profiles_pass():
    from implicit import box, cylinder

    assert narrowest_gap(box(2.0) - cylinder(0.5, 4.0), 0.5) is None
    assert narrowest_gap(_slot(3.0), 1.0) is None          # only gaps under twice the size are looked for
    check_resolvable(_slot(2.0), 1.8)


def test_gear_past_a_fifth_of_its_gap_is_refused_at_once_naming_the_size_that_works(tmp_path, capsys):
    gear = runpy.run_path(GEAR)["solid"]
    # the gap between two teeth at the root circle: (pitch - root tooth thickness) x root radius
    assert narrowest_gap(gear, 3.0)[0] == pytest.approx(2.23, abs=0.05)
    out = tmp_path / "gear.inp"
    t0 = time.perf_counter()
    status = main(["fea", GEAR, "-o", str(out), "--size", "10", "--no-progress"])
    seconds = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1 and not out.exists()
    # sizes up to 0.8 x 2.22 / 0.2 mesh with a graded size (tests/fea/test_gear_sizes.py)
    assert "the largest size that resolves it is 8.9" in err and "gap 2.2" in err
    assert seconds < 15.0                             # before the surface (30 s and more), TetGen or the mass check
    with pytest.raises(ValueError, match="largest size that resolves it is 8.9$"):
        tet_mesh(gear, size=9.0)
