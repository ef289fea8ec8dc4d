"""The thinnest wall of a CSG tree, the sampled estimate, and the default voxel that resolves it."""

import math
import warnings

import pytest

import implicit as I
from spatial import mesh
from spatial.cells.thickness import WALL_VOXELS, default_voxel_size, sampled_thickness, thinnest_wall


@pytest.mark.parametrize("solid, expected", [
    (I.box((100, 100, 1)), 1.0),
    (I.sphere(0.7), 1.4),
    (I.cylinder(0.5, 0.2), 0.2),
    (I.torus(1.0, 0.1), 0.2),
    (I.shell(I.sphere(1.0), 0.05), 0.05),
    (I.scale(I.box(1.0), (1, 1, 0.1)), 0.1),
    (I.rotate(I.box((10, 10, 0.5)), 30, (1, 1, 0)), 0.5),
    (I.offset(I.box((2, 2, 1)), -0.25), 0.5),
    (I.box(3) - I.cylinder(0.2, 5), 0.4),
    (I.extrude(I.rectangle((2.0, 0.3)), 5.0), 0.3),
])
def test_tree_walk_finds_the_thinnest_primitive(solid, expected):
    assert thinnest_wall(solid)[0] == pytest.approx(expected)


def test_tree_walk_names_the_feature_and_knows_nothing_of_a_half_space():
    assert "shell of thickness 0.05" in thinnest_wall(I.shell(I.sphere(1.0), 0.05))[1]
    assert math.isinf(thinnest_wall(I.halfspace((0, 0, 1)))[0])


def test_sampled_estimate_finds_walls_the_tree_does_not_name():
    # a hollow box: walls 0.1 thick, primitives of 1 and 0.8
    hollow = I.box(1.0) - I.box(0.8)
    assert thinnest_wall(hollow)[0] == pytest.approx(0.8)
    assert sampled_thickness(hollow) == pytest.approx(0.1, rel=0.2)
    assert thinnest_wall(hollow, sample=True)[0] == pytest.approx(0.1, rel=0.2)


def test_default_voxel_resolves_the_thin_plate_and_measures_it():
    plate = I.box((100, 100, 1))
    h = default_voxel_size(plate)
    assert h <= 1.0 / WALL_VOXELS * 1.0001
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning with the default
        m = mesh(plate, progress=False)
    assert m.volume == pytest.approx(1e4, rel=2e-3)


def test_coarse_voxel_warns_once_naming_the_wall():
    with pytest.warns(RuntimeWarning, match=r"thinnest wall \(box of sides \[100.0, 100.0, 1.0\]: 1\).*voxel_size=0.25"):
        mesh(I.box((100, 100, 1)), resolution=64, progress=False)


def test_default_voxel_is_capped_by_memory():
    # a wall of 1e-4 on a part of 10: the cap, not the wall, decides
    h = default_voxel_size(I.box((10, 10, 1e-4)))
    assert h > 1e-4 / WALL_VOXELS
    assert 2 * (100 + 2e-3) / h ** 2 <= 2.0001e7
