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
    assert peak < 8e6  # two pieces of 31**3 float32 / float64 and the zero level's quads
    centres = np.array([[0.0, 0.0, 0.0], [FAR * H] * 3])
    # inside each ball, at its centre and half way out; outside between them and just beyond each
    probe = np.concatenate([centres, centres + [0.5 * R * H, 0, 0], [[0.5 * FAR * H] * 3],
                            centres + [(R + 1.5) * H, 0, 0]])
    values = solid(probe)
    np.testing.assert_allclose(values[:2], -BAND * H, rtol=1e-6)   # deep inside: the background
    np.testing.assert_allclose(values[2:4], -0.5 * R * H, atol=0.05 * H)
    assert values[4] > 0
    np.testing.assert_allclose(values[5:], 1.5 * H, atol=0.05 * H)
    # the occupancy of each ball: its own mesh, in its own small box
    for c in centres:
        surface = spatial.mesh(solid, voxel_size=H / 2, bounds=(c - 10 * H, c + 10 * H), progress=False)
        assert surface.is_manifold
        assert surface.volume == pytest.approx(4 / 3 * np.pi * (R * H) ** 3, rel=0.03)


def test_one_piece_reads_as_one_grid_solid(requires_openvdb, tmp_path):
    from implicit.fields import GridSolid
    from spatial.cells.vdb import load_vdb, save_vdb
    from implicit import sphere

    path = save_vdb(sphere(1.0), tmp_path / "ball.vdb", voxel_size=0.1)
    solid = load_vdb(path)
    assert isinstance(solid, GridSolid)
    assert float(solid([[0.0, 0.0, 0.0]])[0]) < -0.25
