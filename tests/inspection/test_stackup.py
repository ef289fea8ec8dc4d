"""Tolerance stack-up against the closed forms of a shaft in a hole."""

import math

import numpy as np
import pytest

from implicit import box, cylinder, sphere
from spatial.inspection import Tolerance, signed_gap, stackup, stackup_picture


def shaft_in_plate(v):
    """A plate with a hole of diameter D and a shaft of diameter d, off the hole's axis by e."""
    return {"plate": box((3.0, 3.0, 0.5)) - cylinder(v["D"] / 2, 2.0),
            "shaft": cylinder(v["d"] / 2, 1.5).translate((v.get("e", 0.0), 0.0, 0.0))}


def test_signed_gap_closed_forms():
    assert signed_gap(sphere(1.0), sphere(0.5, center=(2.0, 0.0, 0.0))) == pytest.approx(0.5, abs=1e-8)
    for D, d, e in ((1.0, 0.96, 0.0), (1.0, 0.96, 0.012), (1.0, 1.04, 0.0)):
        parts = shaft_in_plate({"D": D, "d": d, "e": e})
        assert signed_gap(parts["plate"], parts["shaft"]) == pytest.approx((D - d) / 2 - e, abs=1e-7)


def test_worst_case_rss_and_monte_carlo_of_a_one_dimensional_stack():
    tD, td = Tolerance.symmetric(1.0, 0.01), Tolerance.symmetric(0.995, 0.01)
    r = stackup(shaft_in_plate, {"D": tD, "d": td, "e": 0.0}, between=("plate", "shaft"), samples=120, seed=7)
    # gap = (D - d) / 2: worst case from the limits, RSS from the sigmas (a sixth of each band)
    assert r.worst_min == pytest.approx((0.99 - 1.005) / 2, abs=1e-7)
    assert r.worst_max == pytest.approx((1.01 - 0.985) / 2, abs=1e-7)
    assert r.sensitivities["D"] == pytest.approx(0.5, abs=1e-6) and r.sensitivities["d"] == pytest.approx(-0.5, abs=1e-6)
    sigma = math.hypot(tD.std, td.std) / 2
    assert r.rss_mean == pytest.approx(0.0025, abs=1e-7)
    assert r.rss_std == pytest.approx(sigma, rel=1e-5)
    # Monte-Carlo within its sampling error (120 samples)
    assert abs(r.mc_mean - 0.0025) < 3 * sigma / math.sqrt(120)
    assert r.mc_std == pytest.approx(sigma, rel=0.2)
    p = 0.5 * math.erfc(0.0025 / sigma / math.sqrt(2))            # P(gap < 0) = Phi(-mean / sigma) = 0.145
    assert abs(r.probability_interference - p) < 3 * math.sqrt(p * (1 - p) / 120)
    assert r.contributions["D"] == pytest.approx(0.5, abs=1e-6)
    one = stackup(shaft_in_plate, {"D": tD, "d": td, "e": 0.0}, between=("plate", "shaft"), samples=4, seed=3)
    two = stackup(shaft_in_plate, {"D": tD, "d": td, "e": 0.0}, between=("plate", "shaft"), samples=4, seed=3)
    assert np.array_equal(one.samples, two.samples)                 # seeded


def test_an_eccentricity_contributes_most_and_the_worst_corner_is_checked(tmp_path):
    tol = {"D": Tolerance(1.0, 0.02, 0.0, "uniform"), "d": Tolerance(0.96, 0.0, 0.02, "uniform"),
           "e": Tolerance.symmetric(0.0, 0.015, "uniform")}
    r = stackup(shaft_in_plate, tol, between=("plate", "shaft"), samples=0, check_worst=True, check_resolution=24)
    assert r.worst_min == pytest.approx((1.0 - 0.96) / 2 - 0.015, abs=1e-7)
    assert r.worst_max == pytest.approx((1.02 - 0.94) / 2, abs=1e-7)        # centred shaft, the middle of e
    assert max(r.contributions, key=r.contributions.get) == "e"
    assert r.worst_check == {"interfering": [], "touching": []}
    tight = {**tol, "e": Tolerance.symmetric(0.0, 0.03, "uniform")}
    r2 = stackup(shaft_in_plate, tight, between=("plate", "shaft"), samples=0, check_worst=True, check_resolution=24)
    assert r2.worst_min < 0 and [p[:2] for p in r2.worst_check["interfering"]] == [["plate", "shaft"]]
    stackup_picture(r2, tmp_path / "stack.png")
    assert (tmp_path / "stack.png").stat().st_size > 10000


def test_bad_input():
    with pytest.raises(ValueError, match="plus, minus"):
        Tolerance(1.0, -0.1, 0.0)
    with pytest.raises(ValueError, match="distribution"):
        Tolerance(1.0, 0.1, 0.1, "beta")
    with pytest.raises(ValueError, match="exactly one"):
        stackup(shaft_in_plate, {"D": Tolerance.symmetric(1.0, 0.01)})
    with pytest.raises(ValueError, match="no part 'pin'"):
        stackup(shaft_in_plate, {"D": Tolerance.symmetric(1.0, 0.01), "d": 0.9}, between=("plate", "pin"))
