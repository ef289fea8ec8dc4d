"""Octree cell decomposition: conservative classification, tiling, statistics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings

from implicit import box, halfspace, sphere, torus
from implicit.solid import Solid
from spatial import BOUNDARY, EMPTY, FULL, OccupancyGrid, Octree

from solid_strategies import solids


def test_states_are_the_agreed_constants():
    assert (EMPTY, FULL, BOUNDARY) == (0, 1, 2)


@pytest.mark.parametrize("solid, volume", [
    (sphere(1.0), 4 / 3 * math.pi),
    (box((1.0, 2.0, 0.5)), 1.0),
    (torus(1.0, 0.3), 2 * math.pi ** 2 * 0.09),
])
def test_volume_bounds_bracket_exact_volume(solid, volume):
    tree = Octree.from_solid(solid, resolution=24)
    lo, hi = tree.volume_bounds()
    assert lo < volume < hi
    finer = Octree.from_solid(solid, resolution=48)
    flo, fhi = finer.volume_bounds()
    assert lo <= flo < volume < fhi <= hi
    # the gap is the boundary shell: it halves as the cells halve
    assert (fhi - flo) / (hi - lo) == pytest.approx(0.5, abs=0.12)


def test_leaves_tile_the_root_cube_without_overlap():
    tree = Octree.from_solid(torus(1.0, 0.4), resolution=20)
    side = 2 ** tree.depth
    assert np.sum(tree.size ** 3) == pytest.approx((side * tree.voxel_size) ** 3)
    cover = np.zeros((side,) * 3, dtype=np.int32)
    for idx, s in zip(tree.index, (2 ** (tree.depth - tree.level.astype(int)))):
        cover[idx[0]:idx[0] + s, idx[1]:idx[1] + s, idx[2]:idx[2] + s] += 1
    assert np.all(cover == 1)
    assert np.all(tree.level[tree.state == BOUNDARY] == tree.depth)
    assert np.allclose(tree.lo, tree.origin + tree.index * tree.voxel_size)


def test_attributes_and_lattice():
    tree = Octree.from_solid(sphere(1.0), voxel_size=0.25)
    assert tree.voxel_size == 0.25
    # bounds [-1, 1] -> 8 cells + 2 padding = 10 -> depth 4
    assert tree.shape.tolist() == [10, 10, 10] and tree.depth == 4
    assert np.allclose(tree.origin, -1.25)
    assert tree.index.dtype == np.int32 and tree.state.dtype == np.uint8
    assert tree.lo.shape == (len(tree), 3) and tree.size.shape == (len(tree),)
    same = Octree.from_solid(sphere(1.0), resolution=8)
    assert same.voxel_size == 0.25 and len(same) == len(tree)


def test_each_level_is_one_value_bounds_call(monkeypatch):
    calls = []
    original = Solid.value_bounds

    def counting(self, lo, hi):
        calls.append(np.asarray(lo).shape[0])
        return original(self, lo, hi)

    monkeypatch.setattr(Solid, "value_bounds", counting)
    tree = Octree.from_solid(sphere(1.0), resolution=16)
    assert len(calls) == tree.depth + 1
    assert sum(calls) == tree.evaluations


def test_level_stats():
    tree = Octree.from_solid(sphere(1.0), resolution=32)
    stats = tree.level_stats()
    assert [s["level"] for s in stats] == list(range(tree.depth + 1))
    assert sum(s["empty"] + s["full"] + s["boundary"] for s in stats) == len(tree)
    assert stats[-1]["boundary"] == int(np.sum(tree.state == BOUNDARY))
    assert all(s["boundary"] == 0 for s in stats[:-1])
    assert sum(s["bytes"] for s in stats) == pytest.approx(tree.nbytes, rel=1e-6)
    assert stats[-1]["cell_size"] == tree.voxel_size


def test_boundary_cells_grow_with_the_surface():
    counts = [int(np.sum(Octree.from_solid(sphere(1.0), resolution=n).state == BOUNDARY)) for n in (16, 32, 64)]
    assert 3.3 < counts[1] / counts[0] < 4.7
    assert 3.5 < counts[2] / counts[1] < 4.5


@settings(derandomize=True, max_examples=25, deadline=None)
@given(solids())
def test_full_and_empty_cells_never_hold_boundary(solid):
    tree = Octree.from_solid(solid, resolution=12)
    rng = np.random.default_rng(7)
    decided = np.flatnonzero(tree.state != BOUNDARY)
    k = 24
    u = rng.random((decided.size, k, 3))
    # corners and face centres included: closed cells
    u[:, :8] = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)])
    pts = tree.lo[decided, None, :] + u * tree.size[decided, None, None]
    values = solid(pts)
    full = tree.state[decided] == FULL
    assert np.all(values[full] < 0)
    assert np.all(values[~full] > 0)


def test_to_grid_matches_sampled_grid():
    s = torus(1.0, 0.35)
    tree = Octree.from_solid(s, resolution=24)
    g = tree.to_grid()
    ref = OccupancyGrid.from_solid(s, resolution=24)
    assert g.shape == ref.shape and np.allclose(g.origin, ref.origin)
    assert np.array_equal(g.occupancy, ref.occupancy)
    b = tree.boundary_index()
    b = b[np.all(b < tree.shape, axis=1)]
    assert np.array_equal(g.distance[b[:, 0], b[:, 1], b[:, 2]], ref.distance[b[:, 0], b[:, 1], b[:, 2]])
    # elsewhere the magnitude never exceeds the sampled distance (a conservative fill)
    assert np.all(np.abs(g.distance) <= np.abs(ref.distance) + 1e-6)


def test_to_mesh_is_closed():
    tree = Octree.from_solid(sphere(1.0), resolution=24)
    m = tree.to_mesh()
    assert m.n_cells > 0 and m.is_manifold
    assert m.volume == pytest.approx(4 / 3 * math.pi, rel=0.01)


def test_bad_input():
    with pytest.raises(ValueError, match="exactly one"):
        Octree.from_solid(sphere(1.0))
    with pytest.raises(ValueError, match="unbounded"):
        Octree.from_solid(halfspace((0, 0, 1)), resolution=8)
    with pytest.raises(TypeError, match="Solid"):
        Octree.from_solid(np.zeros(3), resolution=8)
    with pytest.raises(ValueError, match="empty"):
        Octree.from_solid(sphere(1.0) & sphere(1.0, center=(4, 0, 0)), resolution=8)
    with pytest.raises(ValueError, match="voxel_size"):
        Octree.from_solid(sphere(1.0), voxel_size=1e-9)
    tree = Octree.from_solid(halfspace((0, 0, 1)), resolution=8, bounds=((-1, -1, -1), (1, 1, 0)))
    lo, hi = tree.volume_bounds()
    assert lo < 4.0 < hi


def test_to_mesh_rebuilds_sharp_features_by_default():
    from implicit import box

    tree = Octree.from_solid(box(1.0), resolution=8)
    sharp, plain = tree.to_mesh(), tree.to_mesh(features=False)
    assert int((sharp.point_data["feature_rank"] == 3).sum()) == 8
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    _, closest = sharp.find_closest_cell(corners, return_closest_point=True)
    # (the faces lie in lattice planes: the corners are kept a thousandth of a voxel inside their cells)
    assert np.abs(closest - corners).max() < 2e-3 * sharp.field_data["voxel_size"][0]
    assert abs(sharp.volume - 1.0) < 1e-3 and abs(plain.volume - 1.0) > 0.05   # 5.0e-4 against 8.4e-2
    assert "feature_rank" not in plain.point_data


def test_cells_methods_load_their_providers_in_a_fresh_interpreter():
    # `import spatial` is lazy: an octree or grid made before anything imported the meshing room
    # must still mesh (its mesher is loaded on first need), and a grid must come from an octree
    import subprocess
    import sys

    script = (
        "from implicit import box\n"
        "from spatial.cells.octree import Octree\n"
        "o = Octree.from_solid(box(1.0), resolution=8)\n"
        "m = o.to_mesh()\n"
        "g = o.to_grid()\n"
        "print(m.n_cells > 0, int((m.point_data['feature_rank'] == 3).sum()), g.to_mesh().n_cells > 0)\n"
    )
    res = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.split() == ["True", "8", "True"]
