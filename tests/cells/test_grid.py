"""Occupancy grids: samples at voxel centres, booleans, volumes, conversions, memory guard."""

import math

import numpy as np
import pytest

from implicit import box, sphere, torus
from spatial import BOUNDARY, FULL, OccupancyGrid, Octree
from spatial.cells.grid import check_dense_memory

from meshcheck import topology

BOUNDS = ((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2))


def test_samples_at_voxel_centres():
    s = sphere(1.0, center=(0.1, 0.0, -0.2))
    g = OccupancyGrid.from_solid(s, resolution=20)
    assert g.distance.dtype == np.float32 and g.occupancy.dtype == bool
    idx = np.array([[0, 0, 0], [5, 7, 9], [g.shape[0] - 1, 3, g.shape[2] - 1]])
    centres = g.origin + (idx + 0.5) * g.voxel_size
    assert np.allclose(g.distance[idx[:, 0], idx[:, 1], idx[:, 2]], s(centres), atol=1e-6)
    assert np.array_equal(g.occupancy, g.distance <= 0)
    assert np.allclose(g.centres[5, 7, 9], centres[1])


@pytest.mark.parametrize("solid, volume", [
    (sphere(1.0), 4 / 3 * math.pi),
    (torus(1.0, 0.35), 2 * math.pi ** 2 * 0.35 ** 2),
    (box((1.3, 0.9, 0.7), center=(0.013, 0.021, 0.017)), 1.3 * 0.9 * 0.7),
])
def test_volume_methods(solid, volume):
    g = OccupancyGrid.from_solid(solid, resolution=64)
    # fractional occupancy is about second order (measured: 9.5e-4 worst of five shapes at N=64)
    assert g.volume("fraction") == pytest.approx(volume, rel=2.5e-3)
    assert g.volume("count") == pytest.approx(volume, rel=5e-2)
    with pytest.raises(ValueError, match="'count' or 'fraction'"):
        g.volume("exact")


def test_booleans_on_one_lattice():
    a = OccupancyGrid.from_solid(sphere(1.0), resolution=24, bounds=BOUNDS)
    b = OccupancyGrid.from_solid(sphere(0.8, center=(0.6, 0, 0)), resolution=24, bounds=BOUNDS)
    assert np.array_equal((a | b).occupancy, a.occupancy | b.occupancy)
    assert np.array_equal((a & b).occupancy, a.occupancy & b.occupancy)
    inter = (a - b)
    assert np.array_equal(inter.occupancy, a.occupancy & ~(b.distance < 0))
    assert np.array_equal((~a).occupancy, a.distance >= 0)
    # inclusion-exclusion holds exactly for voxel counts
    assert (a | b).volume() + (a & b).volume() == pytest.approx(a.volume() + b.volume())
    other = OccupancyGrid.from_solid(sphere(1.0), resolution=20, bounds=BOUNDS)
    with pytest.raises(ValueError, match="share one lattice"):
        a | other
    with pytest.raises(TypeError, match="OccupancyGrid"):
        a & sphere(1.0)
    with pytest.raises(TypeError, match="ambiguous"):
        bool(a)


def test_memory_guard_refuses_before_sampling():
    with pytest.raises(MemoryError, match=r"GB.*available.*Octree"):
        OccupancyGrid.from_solid(sphere(1.0), resolution=64, max_bytes=1e5)
    with pytest.raises(MemoryError, match=r"1\.00 GB"):
        check_dense_memory((1000, 1000, 250), bytes_per_voxel=4, what="test", max_bytes=1e6)
    assert check_dense_memory((10, 10, 10), bytes_per_voxel=4, what="test") == 4000


def test_to_octree_merges_uniform_blocks():
    g = OccupancyGrid.from_solid(sphere(1.0), resolution=30)
    tree = g.to_octree()
    side = 2 ** tree.depth
    assert np.sum(tree.size ** 3) == pytest.approx((side * g.voxel_size) ** 3)
    states = g.cell_states()
    assert np.sum(tree.state == BOUNDARY) == np.sum(states == BOUNDARY)
    full_voxels = np.sum((2.0 ** (tree.depth - tree.level.astype(float))) ** 3 * (tree.state == FULL))
    assert full_voxels == np.sum(states == FULL)
    assert len(tree) < 0.5 * np.prod(g.shape)  # merged
    lo, hi = tree.volume_bounds()
    assert lo < 4 / 3 * math.pi < hi
    back = tree.to_grid()
    assert np.array_equal(back.occupancy, g.occupancy)


def test_grid_octree_classification_is_conservative():
    s = torus(1.0, 0.3)
    g = OccupancyGrid.from_solid(s, resolution=24)
    tree = g.to_octree()
    decided = np.flatnonzero((tree.state != BOUNDARY) & np.all(tree.index < g.shape, axis=1))
    rng = np.random.default_rng(3)
    pts = tree.lo[decided, None, :] + rng.random((decided.size, 6, 3)) * tree.size[decided, None, None]
    v = s(pts)
    full = tree.state[decided] == FULL
    assert np.all(v[full] < 0) and np.all(v[~full] > 0)


def test_to_mesh_and_to_solid():
    s = sphere(1.0)
    g = OccupancyGrid.from_solid(s, resolution=32)
    m = g.to_mesh()
    topo = topology(m)
    assert topo["edge_counts"] == {2} and topo["euler"] == 2
    assert m.volume == pytest.approx(4 / 3 * math.pi, rel=5e-3)
    solid = g.to_solid()
    idx = np.array([[3, 4, 5], [16, 16, 16]])
    centres = g.origin + (idx + 0.5) * g.voxel_size
    assert np.allclose(solid(centres), g.distance[idx[:, 0], idx[:, 1], idx[:, 2]])
    # occupancy touching the grid's border still closes
    cut = OccupancyGrid(np.full((4, 4, 4), -1.0), voxel_size=0.5)
    assert topology(cut.to_mesh())["euler"] == 2
    with pytest.warns(RuntimeWarning, match="no boundary"):
        assert OccupancyGrid(np.ones((3, 3, 3))).to_mesh().n_cells == 0


def test_octree_and_grid_share_the_lattice():
    s = torus(1.0, 0.3)
    g = OccupancyGrid.from_solid(s, resolution=24)
    tree = Octree.from_solid(s, resolution=24)
    assert np.allclose(g.origin, tree.origin) and g.voxel_size == tree.voxel_size
    assert g.shape == tuple(tree.shape.tolist())


def test_bad_construction():
    with pytest.raises(ValueError, match="3-d"):
        OccupancyGrid(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="voxel_size"):
        OccupancyGrid(np.zeros((3, 3, 3)), voxel_size=0)
    with pytest.raises(ValueError, match="exactly one"):
        OccupancyGrid.from_solid(sphere(1.0))
