"""Loading a sparse OpenVDB level set reads its pieces, never the dense box of the whole grid."""

import tracemalloc

import numpy as np
import pytest

R = 6.0          # sphere radius, voxels
FAR = 1000       # voxels between the two spheres' centres, along each axis
H = 0.01         # voxel size
BAND = 3.0       # half width, voxels


def two_far_spheres(vdb, path):
    """A level set of two balls of radius R voxels, FAR voxels apart along x, y and z: its active box
    holds 1000**3 voxels (4 GB of floats), its band a few thousand."""
    grid = vdb.FloatGrid(background=BAND * H)
    grid.transform = vdb.createLinearTransform(voxelSize=H)
    n = 2 * int(R + BAND) + 3
    ijk = np.stack(np.meshgrid(*(np.arange(n),) * 3, indexing="ij"), -1) - n // 2
    ball = (np.linalg.norm(ijk, axis=-1) - R) * H
    block = np.clip(ball, -BAND * H, BAND * H).astype(np.float32)
    for c in (0, FAR):
        grid.copyFromArray(block, ijk=(c - n // 2,) * 3, tolerance=1e-7 * H)
    grid.pruneInactive()
    grid.signedFloodFill()
    grid.gridClass = vdb.GridClass.LEVEL_SET
    vdb.write(str(path), grids=[grid])
    return grid


def test_two_small_spheres_far_apart_load_sparse(requires_openvdb, tmp_path):
    import spatial
    from spatial.cells.sparse_grid import SparseGridSolid
    from spatial.cells.vdb import load_vdb

    vdb = requires_openvdb
    path = tmp_path / "far.vdb"
    grid = two_far_spheres(vdb, path)
    lo, hi = grid.evalActiveVoxelBoundingBox()
    assert min(b - a for a, b in zip(lo, hi)) > 990  # a dense read would take 4 GB
    tracemalloc.start()
    try:
        solid = load_vdb(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert isinstance(solid, SparseGridSolid)
    # each ball's band (18 voxels across) spans at most 4**3 tiles of 9**3 samples; the peak holds them and
    # the zero level's quads
    assert solid.tiles <= 2 * 4 ** 3 and solid.nbytes < 400_000
    assert peak < 4e6
    centres = np.array([[0.0, 0.0, 0.0], [FAR * H] * 3])
    # inside each ball, at its centre and half way out; outside between them and just beyond each
    probe = np.concatenate([centres, centres + [0.5 * R * H, 0, 0], [[0.5 * FAR * H] * 3],
                            centres + [(R + 1.5) * H, 0, 0]])
    values = solid(probe)
    np.testing.assert_allclose(values[:2], -BAND * H, rtol=1e-6)   # deep inside: the background
    np.testing.assert_allclose(values[2:4], -0.5 * R * H, atol=0.05 * H)
    # half way between: outside, and at least the distance to the band's tiles (a lower bound)
    assert np.sqrt(3) * 0.5 * FAR * H - 2 * R * H > values[4] > np.sqrt(3) * 0.5 * FAR * H - 20 * H
    np.testing.assert_allclose(values[5:], 1.5 * H, atol=0.05 * H)
    # the occupancy: the mesh over the whole box finds the two balls and nothing else
    surface = spatial.mesh(solid, voxel_size=H, progress=False)
    assert surface.is_manifold
    assert surface.n_points > 0 and len(surface.split_bodies()) == 2
    assert surface.volume == pytest.approx(2 * 4 / 3 * np.pi * (R * H) ** 3, rel=0.05)
    for c in centres:  # and each one's own, finer
        own = spatial.mesh(solid, voxel_size=H / 2, bounds=(c - 10 * H, c + 10 * H), progress=False)
        assert own.is_manifold
        assert own.volume == pytest.approx(4 / 3 * np.pi * (R * H) ** 3, rel=0.03)


def test_sparse_and_dense_reads_of_a_level_set_agree(requires_openvdb, tmp_path):
    from implicit import torus
    from implicit.fields import GridSolid
    from implicit.serialize import from_json, to_json
    from spatial.cells.sparse_grid import SparseGridSolid
    from spatial.cells.vdb import load_vdb, save_vdb

    part = torus(1.0, 0.3)
    path = save_vdb(part, tmp_path / "torus.vdb", voxel_size=0.05)
    dense, sparse = load_vdb(path), load_vdb(path, dense=False)
    assert isinstance(dense, GridSolid) and isinstance(sparse, SparseGridSolid)
    rng = np.random.default_rng(7)
    p = rng.uniform(-1.6, 1.6, (20000, 3)) * [1, 1, 0.4]
    a, b = dense(p), sparse(p)
    true = part(p)
    band = np.abs(a) < 0.1  # where the band holds values, the two interpolate the same samples
    assert band.sum() > 2000
    np.testing.assert_allclose(b[band], a[band], atol=1e-6)
    np.testing.assert_array_equal(np.sign(b[np.abs(true) > 0.02]), np.sign(true[np.abs(true) > 0.02]))
    # beyond the band (where the dense read holds the background) a lower bound of the distance: never
    # above the true distance (to the grid's own error, a voxel), so the octree stays conservative
    beyond = np.abs(b - a) > 1e-6
    assert beyond.sum() > 1000 and np.all(np.abs(a[beyond]) > 0.15 - 1e-6)
    assert np.all(np.abs(b[beyond]) <= np.abs(true[beyond]) + 0.05)
    assert np.abs(b).max() > 0.15 + 0.05  # and growing with it, which the background does not
    back = from_json(to_json(sparse))
    np.testing.assert_array_equal(back(p), b)
    with pytest.raises(TypeError, match="dense"):
        load_vdb(path, dense="yes")


def test_one_piece_reads_as_one_grid_solid(requires_openvdb, tmp_path):
    from implicit.fields import GridSolid
    from spatial.cells.vdb import load_vdb, save_vdb
    from implicit import sphere

    path = save_vdb(sphere(1.0), tmp_path / "ball.vdb", voxel_size=0.1)
    solid = load_vdb(path)
    assert isinstance(solid, GridSolid)
    assert float(solid([[0.0, 0.0, 0.0]])[0]) < -0.25
