"""Scan against design: a known offset, a local bump, a rigid misplacement, datum planes, files."""

import json

import numpy as np
import pytest

from implicit import box, cylinder, sphere
from implicit.transforms import rotation_matrix
from spatial.inspection import datum_align, deviation_picture, histogram_picture, inspect, load_scan
from spatial.meshing import mesh

#: The mesher's vertices sit on the surface to this (its edge refinement).
ON_SURFACE = 5e-5


def benchmark_part():
    return (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))


def _motion(angle, axis, t):
    T = np.eye(4)
    T[:3, :3] = rotation_matrix(angle, axis)
    T[:3, 3] = t
    return T


def test_a_uniform_offset_is_recovered_by_the_best_fit():
    part = benchmark_part()
    r = inspect(part, mesh(part.offset(0.02), resolution=40), tolerance=0.03)
    assert r.mean_deviation == pytest.approx(0.02, abs=2e-4)
    assert r.max_deviation == pytest.approx(0.02, abs=2e-3) and r.min_deviation == pytest.approx(0.02, abs=2e-3)
    assert np.abs(r.transform - np.eye(4)).max() < 2e-4       # the offset does not move the fit
    assert r.passed and r.within_tolerance == 1.0
    assert not inspect(part, mesh(part.offset(0.02), resolution=40), tolerance=0.015, align="none").passed


def test_a_local_bump_is_found_and_located():
    design = box((2.0, 2.0, 1.0))
    scan = mesh(design | sphere(0.1, center=(0.5, 0.3, 0.55)), resolution=64)
    r = inspect(design, scan, tolerance=0.05)
    # the bump's top stands 0.15 above the face at (0.5, 0.3, 0.65)
    assert r.max_deviation == pytest.approx(0.15, abs=0.005)
    top = r.worst(1)[0]
    assert np.allclose(top["point"], [0.5, 0.3, 0.65], atol=0.03)
    assert not r.passed and 0.97 < r.within_tolerance < 1.0
    # Huber weights: the bump does not pull the fit (1.3e-5 on the feature mesh, whose sharp rim round
    # the bump keeps more points far out than the plain mesh's chamfer did)
    assert np.abs(r.transform - np.eye(4)).max() < 2e-5


def test_a_rigid_misplacement_is_undone():
    part = benchmark_part()
    applied = _motion(7.0, (1, 2, 3), (0.05, -0.03, 0.08))
    pts = mesh(part, resolution=40).points
    moved = pts @ applied[:3, :3].T + applied[:3, 3]
    r = inspect(part, moved, tolerance=0.01)
    assert np.abs(r.transform @ applied - np.eye(4)).max() < 1e-3
    assert r.rms_deviation < ON_SURFACE


def test_datum_planes_align_a_box():
    design = box((3.0, 2.0, 1.0))
    applied = _motion(2.0, (0.3, -0.2, 1.0), (0.03, 0.02, -0.04))
    pts = mesh(design, resolution=48).points
    moved = pts @ applied[:3, :3].T + applied[:3, 3]
    datums = [((0, 0, -0.5), (0, 0, -1)), ((0, -1.0, 0), (0, -1, 0)), ((-1.5, 0, 0), (-1, 0, 0))]
    T = datum_align(moved, design, datums, band=0.02)
    assert np.abs(T @ applied - np.eye(4)).max() < 1e-3
    r = inspect(design, moved, align="datum", datums=datums, tolerance=0.01)
    assert r.passed


def test_scan_files_and_report(tmp_path):
    design = sphere(1.0)
    pts = mesh(sphere(1.01), resolution=24).points
    xyz = tmp_path / "scan.xyz"
    np.savetxt(xyz, pts)
    loaded, m = load_scan(xyz)
    assert m is None and np.allclose(loaded, pts)
    r = inspect(design, xyz, tolerance=0.02)
    d = json.loads(r.to_json())
    for key in ("max_deviation", "min_deviation", "mean_deviation", "rms_deviation", "within_tolerance"):
        assert d[key] == pytest.approx(0.01, abs=2e-4) if key != "within_tolerance" else d[key] == 1.0
    assert np.array(d["transform"]).shape == (4, 4)
    from spatial.files import save_mesh

    stl = tmp_path / "scan.stl"
    save_mesh(mesh(sphere(1.01), resolution=24), stl)
    assert inspect(design, stl, tolerance=0.02).mean_deviation == pytest.approx(0.01, abs=2e-4)
    bad = tmp_path / "scan.xyz"
    bad.write_text("1 2\n3 4\n")
    with pytest.raises(ValueError, match="x y z"):
        load_scan(bad)
    with pytest.raises(ValueError, match="unknown scan format"):
        load_scan(tmp_path / "scan.step")


def test_pictures(tmp_path):
    design = box((2.0, 2.0, 1.0))
    r = inspect(design, mesh(design | sphere(0.1, center=(0.5, 0.3, 0.55)), resolution=32), tolerance=0.05)
    from PIL import Image

    p = deviation_picture(r, tmp_path / "dev.png", window_size=(500, 400))
    img = np.asarray(Image.open(p).convert("RGB")).astype(int)
    assert ((img[..., 0] - img[..., 2]) > 80).sum() > 50        # the red bump
    h = histogram_picture(r, tmp_path / "hist.png")
    assert Image.open(h).size[0] > 500


@pytest.mark.parametrize("kwargs, match", [({"tolerance": -1}, "tolerance"), ({"align": "best"}, "align"),
                                           ({"align": "datum"}, "datums")])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        inspect(sphere(1.0), np.zeros((10, 3)) + 1.0, **kwargs)
