"""Interference, contact and clearance between solids; assembly checks with box pre-filtering."""

import numpy as np
import pytest

import spatial.analysis.interference as interference_module
from implicit import box, cylinder, sphere
from spatial.analysis.interference import box_pairs, check_assembly, interference


def test_overlapping_spheres_lens_volume():
    d = 1.5
    r = interference(sphere(1.0), sphere(1.0, center=(d, 0, 0)), resolution=32)
    lens = np.pi * (4 + d) * (2 - d) ** 2 / 12
    assert r.interferes and not r.touching
    assert abs(r.volume - lens) <= r.volume_error
    assert r.volume == pytest.approx(lens, rel=1e-4)
    lo, hi = r.overlap_bounds
    # bounds of the mesh's vertices: within a small fraction of a cell of the lens's box
    np.testing.assert_allclose(lo, [0.5, -np.sqrt(1 - 0.75 ** 2), -np.sqrt(1 - 0.75 ** 2)], atol=0.05 * r.voxel_size)
    np.testing.assert_allclose(hi[0], 1.0, atol=0.05 * r.voxel_size)


def test_box_minus_through_hole_and_pin():
    plate = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0)
    pin = cylinder(0.3, 2.0)                     # oversize pin: a ring of overlap
    r = interference(plate, pin, resolution=48)
    ring = np.pi * (0.3 ** 2 - 0.25 ** 2) * 0.5
    assert r.interferes and abs(r.volume - ring) <= r.volume_error
    assert r.volume == pytest.approx(ring, rel=1e-3)
    loose = interference(plate, cylinder(0.2, 2.0), resolution=48)
    assert not loose.interferes and not loose.touching
    assert loose.clearance == pytest.approx(0.05, abs=1e-9)


def test_clearance_between_disjoint_parts():
    r = interference(sphere(1.0), sphere(0.5, center=(2.0, 1.0, 0.0)), resolution=32)
    exact = np.sqrt(5.0) - 1.5
    assert not r.interferes and not r.touching
    assert r.clearance == pytest.approx(exact, abs=1e-9)
    # the bracket [clearance - error, clearance] holds the true value
    assert r.clearance - r.clearance_error <= exact <= r.clearance + 1e-12
    pa, pb = r.closest_points
    assert np.linalg.norm(pa) == pytest.approx(1.0, abs=1e-9)
    assert np.linalg.norm(pb - [2.0, 1.0, 0.0]) == pytest.approx(0.5, abs=1e-9)


def test_touching_is_not_interfering():
    r = interference(box(1.0), box(1.0, center=(1.0, 0.3, 0.2)), resolution=32)
    assert r.touching and not r.interferes
    assert r.volume == 0.0 and r.clearance == 0.0
    r = interference(sphere(1.0), sphere(1.0, center=(2.0, 0, 0)), resolution=32)
    assert r.touching and not r.interferes


def test_argument_errors():
    with pytest.raises(TypeError, match="a: expected a Solid"):
        interference("a", sphere(1.0))
    with pytest.raises(ValueError, match="b: expected a bounded"):
        interference(sphere(1.0), ~sphere(1.0))
    with pytest.raises(ValueError, match="resolution"):
        interference(sphere(1.0), sphere(1.0), resolution=2)
    with pytest.raises(TypeError, match="parts"):
        check_assembly([sphere(1.0)])


def test_box_pairs_sweep_matches_brute_force():
    rng = np.random.default_rng(7)
    lo = rng.uniform(0, 10, (300, 3))
    hi = lo + rng.uniform(0.1, 1.5, (300, 3))
    pairs = {tuple(p) for p in box_pairs(lo, hi).tolist()}
    over = np.all((lo[:, None] <= hi[None]) & (lo[None] <= hi[:, None]), axis=2)
    i, j = np.nonzero(np.triu(over, 1))
    assert pairs == set(zip(i.tolist(), j.tolist()))


def test_assembly_of_100_parts_runs_few_full_checks(monkeypatch):
    calls = []
    real = interference_module.interference

    def counting(a, b, **kw):
        calls.append(1)
        return real(a, b, **kw)

    monkeypatch.setattr(interference_module, "interference", counting)
    parts = {f"ball{i:02d}": sphere(0.3, center=(i % 10, i // 10, 0)) for i in range(100)}
    parts["ball00"] = sphere(0.3, center=(0.0, 0.0, 0.0))
    parts["ball01"] = sphere(0.3, center=(0.5, 0.0, 0.0))     # overlaps ball00
    report = check_assembly(parts, resolution=16)
    assert report.pairs_possible == 4950
    assert report.full_checks == len(calls) == report.candidates == 1
    assert [(a, b) for a, b, _ in report.interfering] == [("ball00", "ball01")]
    d = report.to_dict()
    assert d["interfering"][0]["a"] == "ball00" and d["full_checks"] == 1
