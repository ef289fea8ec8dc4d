"""`volume_on_one_level`: a solid's volume from one corrected feature mesh, its error from the shell's
two quadratures and its tilt, against the exact volumes of parts with curved faces, sharp edges and
corners, on feature meshes, bevelled (plain) meshes and meshes a little off the surface."""

import numpy as np
import pytest

from implicit import box, cylinder, sphere, torus
from spatial.analysis.mass_shell import volume_on_one_level
from spatial.analysis.mass_solid import FEATURE_FLOOR, level_moments, volume_on_finest
from spatial.meshing.arrays import faces_array
from spatial.meshing.boundary import mesh

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
BENCH_VOLUME = 0.988789504774

PARTS = {
    "bench": (BENCH, BENCH_VOLUME, (0.02, 0.05)),
    "sphere": (sphere(1.0), 4 / 3 * np.pi, (0.05, 0.1)),
    "torus": (torus(1.0, 0.25), 2 * np.pi**2 * 0.25**2, (0.025, 0.05)),
    "cylinder": (cylinder(0.3, 2.0), np.pi * 0.09 * 2.0, (0.025, 0.05)),
    "beam": (box((100, 10, 10), center=(50, 0, 0)), 1e4, (1.25, 2.5)),
}


def _scaled(m, solid, factor):
    c = 0.5 * (np.asarray(solid.bounds[0]) + np.asarray(solid.bounds[1]))
    return m.translate(-c, inplace=False).scale(factor, inplace=False).translate(c, inplace=False)


@pytest.mark.parametrize("name", sorted(PARTS))
def test_the_claimed_error_holds_the_actual_one(name):
    solid, exact, voxels = PARTS[name]
    for h in voxels:
        for features, factor in ((True, 1.0), (False, 1.0), (True, 1.001)):
            m = mesh(solid, voxel_size=h, features=features, progress=False)
            if factor != 1.0:
                m = _scaled(m, solid, factor)
            got = volume_on_one_level(solid, m, h, tolerance=0.99)
            assert got is not None
            v, err = got
            assert FEATURE_FLOOR <= err and abs(v - exact) <= err * exact, (name, h, features, factor)


def test_the_volume_is_the_corrected_levels_and_tighter_than_three_levels_claim():
    h = 0.02  # the voxel of the benchmark part's surface at size 0.08
    fine = mesh(BENCH, voxel_size=h, features=True, progress=False)
    v, err = volume_on_one_level(BENCH, fine, h, tolerance=1e-3)
    pts, tri = faces_array(fine)
    c0 = 0.5 * (np.asarray(BENCH.bounds[0]) + np.asarray(BENCH.bounds[1]))
    assert v == level_moments(BENCH, pts, tri, c0, voxel_size=h, area=False)[0]
    assert abs(v - BENCH_VOLUME) <= err * BENCH_VOLUME and err < 5e-5  # 2.1e-5 against an actual 7.9e-6
    assert err < volume_on_finest(BENCH, fine, h, tolerance=1e-3)[1]  # 1.1e-4


def test_a_mesh_off_the_surface_is_refused():
    for h in (0.02, 0.05):
        bad = _scaled(mesh(BENCH, voxel_size=h, features=True, progress=False), BENCH, 1.01)  # 3 % more volume
        assert volume_on_one_level(BENCH, bad, h, tolerance=1e-3) is None
        v, err = volume_on_one_level(BENCH, bad, h, tolerance=0.5)
        assert err > 1e-2 and abs(v - BENCH_VOLUME) <= err * BENCH_VOLUME


def test_a_bevelled_mesh_is_refused_where_its_edges_miss_the_tolerance():
    h = 0.02
    plain = mesh(BENCH, voxel_size=h, features=False, progress=False)  # actual error 4.2e-4
    assert volume_on_one_level(BENCH, plain, h, tolerance=1e-3) is None


def test_refusals_of_the_options():
    fine = mesh(sphere(1.0), voxel_size=0.1, features=True, progress=False)
    with pytest.raises(ValueError, match="tolerance"):
        volume_on_one_level(sphere(1.0), fine, 0.1, tolerance=0.0)
    assert volume_on_one_level(sphere(1.0), fine, 0.1, tolerance=FEATURE_FLOOR / 2) is None
    thin = box((10, 10, 1))
    with pytest.warns(RuntimeWarning, match="thinnest wall"):
        plate = mesh(thin, voxel_size=0.9, features=True, progress=False)
    assert plate.n_cells and volume_on_one_level(thin, plate, 0.9, tolerance=0.5) is None  # a wall 1.1 voxels thick
