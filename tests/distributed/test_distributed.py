"""Meshing, mass properties and sparse level sets on a Dask LocalCluster of two worker processes.

The cluster (loopback, no dashboard) is shared by the tests of this file.  The
reference is always the single-process path at the same lattice.
"""

import os

import numpy as np
import pytest

from implicit import box, cylinder, sphere

distributed = pytest.importorskip("distributed")

#: Vertices of the two paths may differ by the rounding of the evaluator (block sizes change its batches).
POSITION_TOL = 1e-12
#: Mass properties (the true area included): the same triangles, summed in another order.
MASS_RTOL = 1e-12


def benchmark_part():
    body = sphere(1.0) & box(1.5)
    drills = [cylinder(0.5, 4.0, axis=a) for a in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    return body - drills[0] - drills[1] - drills[2]


@pytest.fixture(scope="module")
def client():
    from spatial.distributed import local_cluster

    with local_cluster(2) as cluster, distributed.Client(cluster) as c:
        yield c


def edge_keys(points, faces, origin, h, stride):
    """Each vertex's lattice edge id (from its position) and each triangle as edge ids, rotated to start
    at its smallest (orientation kept), rows sorted: a mesh's triangles independent of vertex order."""
    q = (np.asarray(points) - origin) / h
    r = np.rint(q)
    rows = np.arange(q.shape[0])
    axis = np.argmax(np.abs(q - r), axis=1)
    node = r.astype(np.int64)
    node[rows, axis] = np.floor(q[rows, axis]).astype(np.int64)
    edges = ((node[:, 0] * stride + node[:, 1]) * stride + node[:, 2]) * 3 + axis
    tri = edges[np.asarray(faces)]
    k = np.argmin(tri, axis=1)
    tri = np.stack([tri[np.arange(tri.shape[0]), (k + i) % 3] for i in range(3)], axis=1)
    return edges, tri[np.lexsort(tri.T[::-1])]


def test_mesh_is_the_single_process_mesh_triangle_for_triangle(client):
    import spatial
    from spatial.distributed.plan import plan_bricks
    from spatial.meshing import mesh as single

    part = benchmark_part()
    # the plain path: vertices keyed by their lattice edge (the feature mesh: test_distributed_exact)
    ref = single(part, resolution=128, progress=False, features=False)
    out = spatial.mesh(part, resolution=128, client=client, brick=64, progress=False, features=False)
    plan = plan_bricks(part, resolution=128, brick=64)
    assert int(out.field_data["bricks"][0]) == plan.bricks.shape[0] > 20
    origin, h, stride = np.array(plan.spec.origin), plan.spec.voxel_size, plan.spec.stride
    e_ref, t_ref = edge_keys(ref.points, ref.regular_faces, origin, h, stride)
    e_out, t_out = edge_keys(out.points, out.regular_faces, origin, h, stride)
    assert out.n_cells == ref.n_cells == 227632
    assert out.n_points == ref.n_points
    np.testing.assert_array_equal(t_out, t_ref)
    a, b = np.argsort(e_ref), np.argsort(e_out)
    np.testing.assert_array_equal(e_ref[a], e_out[b])
    assert np.abs(np.asarray(ref.points)[a] - np.asarray(out.points)[b]).max() <= POSITION_TOL
    assert out.is_manifold
    assert abs(out.volume - 0.988789504774) < 2e-3


def test_mass_properties_are_the_single_process_ones(client):
    import spatial
    from spatial.analysis import mass_properties as single

    part = benchmark_part()
    ref = single(part, resolution=64)
    out = spatial.mass_properties(part, resolution=64, client=client, brick=32, block=16)
    # the true area weighs triangles by their vertices' normals, summed over the bricks where bricks meet
    for name in ("volume", "mass", "area"):
        assert getattr(out, name) == pytest.approx(getattr(ref, name), rel=MASS_RTOL, abs=0)
    assert out.area == pytest.approx(12.327770219, rel=2e-3)
    np.testing.assert_allclose(out.inertia, ref.inertia, rtol=MASS_RTOL, atol=MASS_RTOL * abs(ref.inertia).max())
    # the centroid lies at the origin: held to the part's size (1.5)
    np.testing.assert_allclose(out.centroid, ref.centroid, rtol=0, atol=MASS_RTOL * 1.5)
    assert out.volume == pytest.approx(0.988789504774, rel=1e-4)


def read_pvtp(path):
    import pyvista as pv
    import vtk

    reader = vtk.vtkXMLPPolyDataReader()  # what ParaView uses for .pvtp
    reader.SetFileName(str(path))
    reader.Update()
    return pv.wrap(reader.GetOutput())


def test_parts_on_disk_open_as_one_dataset_and_gather_closed(client, tmp_path):
    from spatial.distributed import PartitionedMesh, mesh
    from spatial.meshing import mesh as single

    part = benchmark_part()
    ref = single(part, resolution=64, progress=False, features=False)   # parts on disk are plain
    index = tmp_path / "part.pvtp"
    out = mesh(part, resolution=64, client=client, brick=32, parts=index)
    assert isinstance(out, PartitionedMesh)
    assert len(out.parts) > 8 and all(os.path.exists(p) for p in out.parts)
    whole = read_pvtp(index)  # every piece
    assert whole.n_cells == out.triangles == ref.n_cells
    assert whole.n_points == out.part_points > ref.n_points  # vertices on brick faces once per part
    assert set(whole.point_data.keys()) >= {"edge_id", "shared"}
    merged = out.gather()
    assert merged.n_cells == ref.n_cells
    assert merged.n_points == ref.n_points == ref.n_cells // 2 - 8  # closed, genus 5: V = F/2 + 2 - 2g
    assert merged.is_manifold
    with pytest.raises(ValueError, match="max_triangles"):
        out.gather(max_triangles=1000)


def test_sparse_level_set_holds_the_band_only(client, tmp_path, requires_openvdb):
    from spatial.distributed import save_level_set_vdb

    vdb = requires_openvdb
    part = benchmark_part()
    n = 256  # a dense float grid would take 258**3 * 4 B = 69 MB
    path = save_level_set_vdb(part, str(tmp_path / "part.vdb"), resolution=n, client=client, brick=64)
    assert os.path.getsize(path) < 69e6 / 8
    grid = vdb.readAll(path)[0][0]
    h = 1.5 / n
    active = grid.activeVoxelCount()
    # nodes of the cells of 2h the surface may cross: a band about 3 to 4 voxels thick
    assert 2.5 < active / (12.327770219 / h ** 2) < 6.0
    assert grid["voxel_size"] == pytest.approx(h)
    # a box of voxels around a point of the top face, across a plane between bricks (which both
    # bricks write): its values are the field's at those nodes
    origin = np.array(grid.transform.indexToWorld((0, 0, 0)))
    top = np.rint((np.array([0.25, 0.6, 0.75]) - origin) / h).astype(int)
    top[0] = 64 * round(top[0] / 64)
    lo = top - 8
    arr = np.empty((17, 17, 17), np.float32)
    grid.copyToArray(arr, ijk=tuple(int(v) for v in lo))
    ijk = np.stack(np.meshgrid(*(np.arange(17),) * 3, indexing="ij"), -1).reshape(-1, 3) + lo
    truth = part(origin + ijk * h)
    band = 3.0 * h
    near = np.abs(truth) < h  # every such node lies in a boundary cell: active, exact
    assert near.sum() > 200
    np.testing.assert_allclose(arr.reshape(-1)[near], truth[near], atol=1e-6 * h + 1e-7)
    far = np.abs(truth) > 4 * h
    np.testing.assert_array_equal(arr.reshape(-1)[far], np.where(truth[far] < 0, -band, band).astype(np.float32))


def test_each_worker_builds_the_solid_once(client):
    from implicit.serialize import to_json
    from spatial.distributed.worker import solid_from_json

    text = to_json(sphere(0.5))

    def twice(text=text):
        return solid_from_json(text) is solid_from_json(text)

    assert all(client.run(twice).values())


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(client="nowhere"), ValueError, "client"),
    (dict(client=3), TypeError, "client"),
    (dict(workers=0), ValueError, "workers"),
    (dict(client="tcp://127.0.0.1:1", workers=2), ValueError, "workers"),
    (dict(workers=2, brick=48), ValueError, "brick"),
    (dict(workers=2, brick=16, block=32), ValueError, "brick"),
    (dict(workers=2, parts="out.stl"), ValueError, "parts"),
])
def test_bad_input_is_refused_before_any_cluster_starts(kwargs, error, match, monkeypatch):
    from spatial.distributed import cluster, mesh

    def no_cluster(*a, **k):
        raise AssertionError("a cluster was started")
    monkeypatch.setattr(cluster, "local_cluster", no_cluster)
    with pytest.raises(error, match=match):
        mesh(sphere(1.0), resolution=16, **kwargs)


def test_cli_meshes_on_a_scheduler_and_refuses_bad_workers(client, tmp_path, capsys):
    import pyvista as pv

    from implicit.serialize import to_json
    from spatial.cli import main

    model = tmp_path / "part.json"
    model.write_text(to_json(benchmark_part()))
    out = tmp_path / "part.stl"
    address = client.scheduler.address
    assert main(["mesh", str(model), "-o", str(out), "--resolution", "64", "--scheduler", address,
                 "--brick", "32", "--quiet", "--no-features"]) == 0
    line = capsys.readouterr().out
    assert "55936 triangles" in line and "watertight yes" in line  # as the single-process test above
    assert pv.read(str(out)).n_cells == 55936
    assert main(["mesh", str(model), "-o", str(out), "--resolution", "64", "--workers", "0"]) == 2
    err = capsys.readouterr().err
    assert "workers" in err and "Traceback" not in err
