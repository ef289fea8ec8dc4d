"""The cluster path as the single-process one: sharp features, default voxel, warnings at the caller.

On a Dask LocalCluster of two worker processes shared by the tests of this file.
"""

import warnings

import numpy as np
import pytest

from implicit import box, cylinder, sphere

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    from spatial.distributed import local_cluster

    with local_cluster(2) as cluster, distributed.Client(cluster) as c:
        yield c


def same_triangles(a, b, tol=1e-10):
    """Assert that two meshes hold the same triangles (orientation kept) up to the order of their vertices:
    every vertex of `a` within `tol` of exactly one of `b`."""
    from scipy.spatial import cKDTree

    pa, pb = np.asarray(a.points, dtype=np.float64), np.asarray(b.points, dtype=np.float64)
    assert pa.shape == pb.shape
    dist, to_b = cKDTree(pb).query(pa)
    assert dist.max() <= tol
    assert np.unique(to_b).size == to_b.size  # one to one
    ta = to_b[np.asarray(a.regular_faces)]
    tb = np.asarray(b.regular_faces)
    assert ta.shape == tb.shape

    def canonical(t):
        k = np.argmin(t, axis=1)
        r = np.arange(t.shape[0])
        t = np.stack([t[r, (k + i) % 3] for i in range(3)], axis=1)
        return t[np.lexsort(t.T[::-1])]

    np.testing.assert_array_equal(canonical(ta), canonical(tb))
    return to_b


def drilled_block():
    body = box((1.5, 1.0, 0.8)) - cylinder(0.25, 2.0, axis=(0, 0, 1)) - sphere(0.3, center=(0.75, 0.5, 0.4))
    return body


def test_sharp_features_on_the_cluster_are_the_single_process_ones(client):
    import spatial

    part = drilled_block()
    ref = spatial.mesh(part, resolution=64, features=True, progress=False)
    out = spatial.mesh(part, resolution=64, features=True, client=client, brick=32, progress=False)
    assert int(out.field_data["bricks"][0]) > 8  # the mesh was cut into bricks
    assert int(ref.field_data["feature_cells"][0]) > 100  # the box's edges and corners, the drill's rims
    assert out.n_cells == ref.n_cells
    to_b = same_triangles(out, ref)
    np.testing.assert_array_equal(np.asarray(out.point_data["feature_rank"]),
                                  np.asarray(ref.point_data["feature_rank"])[to_b])
    assert int(out.field_data["feature_cells"][0]) == int(ref.field_data["feature_cells"][0])
    assert out.is_manifold
    # the box's 7 corners the ball leaves are rank-3 vertices at their places (to the nudge of the faces that fall on
    # lattice planes, a thousandth of the voxel: 2.34e-5 here)
    corners = np.asarray(out.points)[np.asarray(out.point_data["feature_rank"]) == 3]
    for c in np.array(np.meshgrid([-0.75, 0.75], [-0.5, 0.5], [-0.4, 0.4])).reshape(3, -1).T[:-1]:
        assert np.min(np.linalg.norm(corners - c, axis=1)) < 2e-3 * 1.5 / 64


def test_features_with_parts_are_refused_before_work(tmp_path):
    from spatial.distributed import mesh

    with pytest.raises(ValueError, match="features"):
        mesh(sphere(1.0), resolution=16, workers=2, parts=tmp_path / "x.pvtp", features=True)
    with pytest.raises(TypeError, match="features"):
        mesh(sphere(1.0), resolution=16, workers=2, features="yes")


def plate():
    return box((100.0, 100.0, 1.0))


def test_default_voxel_of_a_plate_is_the_single_process_one(client):
    import spatial
    from spatial.cells.thickness import default_voxel_size

    part = plate()
    ref = spatial.mesh(part, progress=False)
    out = spatial.mesh(part, client=client, progress=False)
    h = float(ref.field_data["voxel_size"][0])
    assert h == default_voxel_size(part) <= 0.25  # four voxels through the 1-thick plate, not 100 / 128
    assert float(out.field_data["voxel_size"][0]) == h
    assert out.n_cells == ref.n_cells > 600_000
    assert out.volume == pytest.approx(ref.volume, rel=1e-12)
    assert abs(out.volume - 1e4) < 2e-3 * 1e4  # the mesh bevels the plate's edges


def test_default_levels_of_mass_properties_on_a_plate_are_the_single_process_ones(monkeypatch):
    """Both paths ask for the same cell sizes (each level's moments here are the plate's exact ones, so
    that the test stays fast: the levels are what is compared)."""
    import spatial
    from spatial.analysis import mass_solid
    from spatial.distributed import mass as dmass

    part = plate()
    exact = np.zeros(14)
    exact[0] = 1e4
    second = np.diag([1e4 * 100 ** 2 / 12, 1e4 * 100 ** 2 / 12, 1e4 / 12])
    exact[4:13] = second.ravel()
    exact[13] = 2 * (100 * 100 + 2 * 100)
    asked = {"single": [], "cluster": []}

    def single_level(solid, h, c0, mesher, correct=True, check=False):
        asked["single"].append(h)
        return exact.copy()

    def cluster_levels(c, **kwargs):
        def moments(solid, h, c0):
            asked["cluster"].append(h)
            return exact.copy()
        return moments

    monkeypatch.setattr(mass_solid, "_solid_level", single_level)
    monkeypatch.setattr(dmass, "level_moments_on", cluster_levels)
    ref = spatial.mass_properties(part)
    out = spatial.mass_properties(part, client="local", workers=1)
    assert asked["cluster"] == asked["single"]
    # the thinnest wall sets the levels: 4 * 1.2 cells across it at the coarsest, N = 480
    assert asked["single"][-1] == pytest.approx(100 / 480)
    assert out.volume == ref.volume == pytest.approx(1e4)


def thin_plate():
    return box((1.0, 1.0, 0.02))


@pytest.mark.parametrize("way", ["spatial.mesh", "spatial.distributed.mesh"])
def test_thin_wall_warning_points_at_the_caller(client, way):
    import spatial
    import spatial.distributed

    call = spatial.mesh if way == "spatial.mesh" else spatial.distributed.mesh
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call(thin_plate(), resolution=16, client=client, brick=16, block=16, progress=False)
    thin = [w for w in caught if "thinnest wall" in str(w.message)]
    assert len(thin) == 1, [str(w.message) for w in caught]
    assert thin[0].filename == __file__
    assert thin[0].category is RuntimeWarning


def test_empty_region_warning_points_at_the_caller(client):
    import spatial

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = spatial.mesh(sphere(0.5), bounds=((2, 2, 2), (3, 3, 3)), resolution=16, client=client, brick=16, block=16)
    assert out.n_cells == 0
    empty = [w for w in caught if "empty mesh" in str(w.message)]
    assert len(empty) == 1 and empty[0].filename == __file__


def test_single_process_thin_wall_warning_points_at_the_caller_too():
    import spatial

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spatial.mesh(thin_plate(), resolution=16, progress=False)
    thin = [w for w in caught if "thinnest wall" in str(w.message)]
    assert len(thin) == 1 and thin[0].filename == __file__


def test_cli_mesh_on_the_cluster_shows_dasks_progress_bar(client, tmp_path, capsys):
    from implicit.serialize import to_json
    from spatial.cli import main

    model = tmp_path / "ball.json"
    model.write_text(to_json(sphere(1.0)))
    out = tmp_path / "ball.stl"
    assert main(["mesh", str(model), "-o", str(out), "--resolution", "64", "--scheduler",
                 client.scheduler.address, "--brick", "32", "--progress"]) == 0
    text = capsys.readouterr().out
    # distributed.diagnostics.progressbar.TextProgressBar: "[####...] | 100% Completed |  0.1s"
    assert "100% Completed" in text and "#" in text
    assert "ball.stl:" in text and "watertight yes" in text
    assert main(["mesh", str(model), "-o", str(out), "--resolution", "64", "--scheduler",
                 client.scheduler.address, "--brick", "32", "--quiet"]) == 0
    assert "Completed" not in capsys.readouterr().out


def test_cli_mesh_help_documents_the_cluster_flags(capsys):
    from spatial.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["mesh", "--help"])
    assert stop.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    for flag in ("--workers N", "--scheduler ADDRESS", "--brick B"):
        assert flag in text
    assert "local Dask cluster" in text and "Dask's progress bar" in text


def test_level_moments_of_a_mesh_cut_in_parts_sum_to_the_whole():
    """The moments' sums do not drift with the number of triangles, so bricks summed on a client give
    the single-process figures to rounding at any N (a plain running sum over these 0.9 M triangles was
    off by 4.6e-12 of the volume, the bricks' sum by 8e-14)."""
    import math

    from spatial.analysis.mass_core import _faces_array
    from spatial.analysis.mass_solid import level_moments
    from spatial.meshing import mesh as single

    part = (sphere(1.0) & box(1.5)) - cylinder(0.5, 4.0, axis=(1, 0, 0)) - cylinder(0.5, 4.0, axis=(0, 1, 0)) \
        - cylinder(0.5, 4.0, axis=(0, 0, 1))
    pts, tri = _faces_array(single(part, resolution=256, progress=False))
    assert tri.shape[0] > 900_000
    lo, hi = part.bounds
    c0 = 0.5 * (lo + hi)
    whole = level_moments(part, pts, tri, c0, voxel_size=1.5 / 256, correct=False)
    # cut as bricks are: by the cell of each triangle's first vertex
    cell = np.floor((pts[tri[:, 0]] - lo) / 0.4).astype(int)
    key = (cell[:, 0] * 16 + cell[:, 1]) * 16 + cell[:, 2]
    parts = [level_moments(part, pts, tri[key == k], c0, voxel_size=1.5 / 256, correct=False)
             for k in np.unique(key)]
    assert len(parts) > 30
    summed = np.sum(parts, axis=0)
    a, b, c = (pts[tri[:, i]] - c0 for i in range(3))
    exact = math.fsum(np.einsum("ij,ij->i", a, np.cross(b - a, c - a)) / 6.0)
    for got in (whole[0], summed[0]):
        assert abs(got / exact - 1) < 1e-13
    np.testing.assert_allclose(summed, whole, rtol=1e-13, atol=1e-13 * np.abs(whole).max())


def test_mass_properties_without_holding_meshes_are_the_same(client):
    from spatial.distributed import mass_properties

    part = box(1.0) - sphere(0.25)
    held = mass_properties(part, resolution=32, client=client, brick=16, block=16)
    again = mass_properties(part, resolution=32, client=client, brick=16, block=16, hold_meshes=False)
    assert (again.volume, again.area) == (held.volume, held.area)
    np.testing.assert_array_equal(again.inertia, held.inertia)
    assert held.volume == pytest.approx(1.0 - 4 / 3 * np.pi * 0.25 ** 3, rel=1e-3)
    with pytest.raises(TypeError, match="hold_meshes"):
        mass_properties(part, resolution=32, client=client, brick=16, block=16, hold_meshes="no")
