"""Walls thinned by Booleans, offsets and blends: measured on the field, warned of, resolved by default."""

import warnings

import numpy as np
import pytest

import implicit as I
from spatial import mesh
from spatial.cells.thickness import WALL_VOXELS, default_voxel_size, thinnest_wall
from spatial.cells.walls import thin_wall


def _messages(solid, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = mesh(solid, progress=False, **kw)
    return m, [str(w.message) for w in caught]


def test_a_difference_leaves_a_wall_the_tree_does_not_know():
    slab = I.box(10) - I.box(10, center=(0.05, 0, 0))      # x in [-5, -4.95]
    assert thinnest_wall(slab)[0] == pytest.approx(10.0)
    w = thin_wall(slab)
    assert w.thickness == pytest.approx(0.05, rel=1e-3)
    assert w.between == "box_0.-x and box_1.-x"
    assert min(abs(w.at[0] + 5.0), abs(w.at[0] + 4.95)) < 1e-6      # on one of its faces
    assert thinnest_wall(slab, sample=True)[0] == pytest.approx(0.05, rel=1e-3)


def test_the_silent_loss_is_now_one_line_naming_the_wall_and_the_voxel_that_keeps_it():
    slab = I.box(10) - I.box(10, center=(0.05, 0, 0))
    m, said = _messages(slab, voxel_size=0.2)
    thin = [s for s in said if "wall may be lost" in s]
    assert len(thin) == 1
    assert "a wall 0.05 thick between box_0.-x and box_1.-x near (-5," in thin[0] \
        or "a wall 0.05 thick between box_0.-x and box_1.-x near (-4.95," in thin[0]
    assert "voxel_size=0.0125 keeps it" in thin[0]


@pytest.mark.parametrize("solid, t", [
    (I.box(1.0) & I.box(1.0, center=(0.97, 0, 0)), 0.03),                     # intersection
    (I.box(2.0) - I.box((1.8, 1.8, 1.95), center=(0, 0, 0.05)), 0.075),        # pocket floor
    (I.shell(I.sphere(1.0), 0.3) - I.sphere(0.99, center=(0, 0, 0.06)), None),  # a blend-free pinch
    (I.offset(I.shell(I.shell(I.sphere(0.75), 0.146), 0.148), -0.068), 0.012),  # offset of shells
])
def test_walls_thinned_by_operations_are_measured(solid, t):
    w = thin_wall(solid)
    assert w is not None
    if t is not None:
        assert w.thickness == pytest.approx(t, rel=0.02)
    else:
        assert w.thickness < 0.15


def test_thick_parts_and_knife_edges_report_no_wall():
    # a sphere is one wall of its diameter (above the measured range); a flat cone's rim is a knife
    # edge (faces 17 degrees apart, not a wall); a box's edges are convex corners
    assert thin_wall(I.sphere(1.0)) is None
    assert thin_wall(I.cone(1.0, 0.3)) is None
    assert thin_wall(I.box(1.0)) is None


def test_points_on_an_edge_measure_no_wall():
    # a tetrahedron of half-spaces: samples symmetric about its edges project onto them, where the
    # gradient is a mix of two faces' (a ray along it once met the opposite edge: "a wall 0.149")
    c = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    planes = []
    for k in range(4):
        f = [c[i] for i in range(4) if i != k]
        n = np.cross(f[1] - f[0], f[2] - f[0])
        planes.append(I.halfspace(-n if np.dot(n, c[k] - f[0]) > 0 else n, f[0]))
    assert thin_wall(planes[0] & planes[1] & planes[2] & planes[3]) is None


def test_no_warning_on_parts_whose_walls_the_voxel_holds():
    bench = (I.sphere(1.0) & I.box(1.5)) - I.cylinder(0.5, 4, axis=(1, 0, 0)) - I.cylinder(0.5, 4, axis=(0, 1, 0)) \
        - I.cylinder(0.5, 4, axis=(0, 0, 1))
    for solid, res in ((bench, 64), (I.cone(1.0, 0.3), 48), (I.box((4, 4, 1)) | I.box(1, center=(0, 0, 1)), 32)):
        _, said = _messages(solid, resolution=res)
        assert not [s for s in said if "wall may be lost" in s], said


def test_default_voxel_holds_the_wall_a_difference_left():
    slab = I.box(2) - I.box(2, center=(0.05, 0, 0))
    h = default_voxel_size(slab)
    assert h <= 0.05 / WALL_VOXELS * 1.0001
    m, said = _messages(slab)
    assert not [s for s in said if "wall may be lost" in s]
    assert m.volume == pytest.approx(0.05 * 4, rel=0.02)


def test_offset_of_a_field_that_is_no_distance_is_not_called_empty():
    # the tree's arithmetic (0.146 * shell ... - 2 * 0.068 < 0.0) used to report a wall of 0 and
    # advise voxel_size=0; the tree now tells nothing there and the measured wall decides
    s = I.offset(I.shell(I.shell(I.sphere(0.75), 0.146), 0.148), -0.068)
    t, what = thinnest_wall(s)
    assert t > 0
    t2, what2 = thinnest_wall(s, sample=True)
    assert 0 < t2 < 0.02 and what2


def test_measurement_is_kept_per_solid():
    s = I.box(1.0) - I.box(1.0, center=(0.02, 0, 0))
    assert thin_wall(s) is thin_wall(s)
    assert np.isclose(thin_wall(s).thickness, 0.02, rtol=1e-3)
