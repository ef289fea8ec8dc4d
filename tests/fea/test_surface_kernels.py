"""The surface stage's compiled passes against the numpy and VTK forms they replace, bit for bit."""

import numpy as np
import pytest
import pyvista as pv

from spatial.fea.quality import radius_edge_ratio
from spatial.fea.score_kernel import radius_edge
from spatial.fea.surface_kernels import enclosed_volume, first_use_order, repeated_points
from spatial.fea.surface_quality import _polydata, enclosed, mesh_faces

_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])


def _numpy_radius_edge(points, tets):
    x = np.asarray(points, dtype=np.float64)[np.asarray(tets)[:, :4]]
    a, b, c = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]
    num = (np.einsum("ij,ij->i", a, a)[:, None] * np.cross(b, c) + np.einsum("ij,ij->i", b, b)[:, None] * np.cross(c, a)
           + np.einsum("ij,ij->i", c, c)[:, None] * np.cross(a, b))
    det = 2.0 * np.einsum("ij,ij->i", a, np.cross(b, c))
    r = np.linalg.norm(num, axis=1) / np.maximum(np.abs(det), 1e-300)
    e = np.linalg.norm(x[:, _EDGES[:, 1]] - x[:, _EDGES[:, 0]], axis=2)
    return r / np.maximum(e.min(axis=1), 1e-300)


def _same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture(scope="module")
def feature_mesh():
    from implicit import box, cylinder, sphere
    from spatial.meshing.boundary import mesh

    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 0, 1))
    return mesh(part, voxel_size=0.05, features=True, progress=False)


def test_radius_edge_has_numpys_bits_on_a_real_mesh():
    from implicit import box, cylinder
    from spatial.fea import tet_mesh

    m = tet_mesh(box(2.0) - cylinder(0.5, 4), size=0.3)
    got = radius_edge_ratio(m.points, m.tets)
    assert _same_bits(got, _numpy_radius_edge(m.points, m.tets))
    assert 0.6 < got.min() and got.max() < 3.0  # the regular tetrahedron's 0.612, tet_mesh's bound 3


@pytest.mark.parametrize("seed", range(4))
def test_radius_edge_has_numpys_bits_on_random_and_degenerate_elements(seed):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(400, 3)) * rng.uniform(1e-3, 1e3, size=(400, 1))
    p[:5] = [0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 2, 0]  # coplanar
    t = rng.integers(0, 400, size=(5000, 4))  # repeated corners: zero edges, zero volume
    t[:3] = [0, 1, 2, 3], [0, 1, 2, 4], [0, 0, 0, 0]
    assert _same_bits(radius_edge(p, t), _numpy_radius_edge(p, t))
    assert radius_edge(p, t[:0]).shape == (0,)


def test_radius_edge_of_a_nan_point_is_nan_like_numpys():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]])
    assert np.isnan(radius_edge(p, np.array([[0, 1, 2, 3]]))[0])
    assert np.isnan(_numpy_radius_edge(p, np.array([[0, 1, 2, 3]]))[0])


def test_enclosed_volume_has_vtks_bits(feature_mesh):
    rng = np.random.default_rng(3)
    meshes = [feature_mesh, pv.Sphere().triangulate(), pv.Icosphere(nsub=3), pv.Cube().triangulate()]
    # open soups and degenerate triangles (a repeated corner: a zero normal) too
    meshes += [_polydata(rng.normal(size=(60, 3)), rng.integers(0, 60, size=(90, 3))) for _ in range(10)]
    for m in meshes:
        assert enclosed_volume(np.asarray(m.points), mesh_faces(m)) == m.volume
        assert enclosed(m) == m.volume
    assert feature_mesh.volume == pytest.approx(1.42, abs=0.01)  # a real figure, not a zero on both sides


def test_enclosed_volume_of_nothing_and_refusals():
    assert enclosed_volume(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)) == 0.0
    assert enclosed_volume(np.zeros((3, 3)), np.zeros((0, 3), dtype=np.int64)) == 0.0
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
    assert enclosed_volume(p, np.array([[0, 0, 0]])) == _polydata(p, np.array([[0, 0, 0]])).volume
    with pytest.raises(ValueError, match=r"faces: expected point numbers in 0 \.\. 2"):
        enclosed_volume(p, np.array([[0, 1, 3]]))
    with pytest.raises(ValueError, match="points: expected shape"):
        enclosed_volume(np.zeros((3, 2)), np.array([[0, 1, 2]]))


def _sorted_repeats(points):
    ps = points[np.lexsort(points.T)]
    return bool(np.any(np.all(ps[1:] == ps[:-1], axis=1)))


def test_repeated_points_as_the_sorted_test(feature_mesh):
    pts = np.asarray(feature_mesh.points, dtype=np.float64)
    assert repeated_points(pts) is False and _sorted_repeats(pts) is False
    doubled = np.concatenate([pts, pts[[123]]])
    assert repeated_points(doubled) is True
    rng = np.random.default_rng(5)
    for _ in range(20):
        p = rng.integers(-2, 3, size=(int(rng.integers(0, 40)), 3)).astype(np.float64)
        assert repeated_points(p) == _sorted_repeats(p)
    assert repeated_points(np.array([[0.0, -0.0, 1.0], [-0.0, 0.0, 1.0]])) is True  # -0.0 == 0.0
    assert repeated_points(np.array([[np.nan, 0, 1], [np.nan, 0, 1]])) is False  # NaN equals nothing
    assert repeated_points(np.zeros((0, 3))) is False
    with pytest.raises(ValueError, match="points: expected shape"):
        repeated_points(np.zeros(3))


def test_first_use_order_as_the_argsort_of_first_uses(feature_mesh):
    faces = mesh_faces(feature_mesh)
    n = feature_mesh.n_points
    flat = faces.reshape(-1)
    first = np.empty(n, dtype=np.int64)
    first[flat[::-1]] = np.arange(flat.size - 1, -1, -1)
    ref = np.argsort(first, kind="stable")
    order, rank = first_use_order(faces, n)
    assert np.array_equal(order, ref) and np.array_equal(rank[ref], np.arange(n))
    order, rank = first_use_order(np.array([[4, 4, 1]]), 6)
    assert order.tolist() == [4, 1] and rank.tolist() == [-1, 1, -1, -1, 0, -1]
    order, rank = first_use_order(np.zeros((0, 3), dtype=np.int64), 2)
    assert order.size == 0 and rank.tolist() == [-1, -1]
    with pytest.raises(ValueError, match="faces: expected point numbers"):
        first_use_order(np.array([[0, 1, 2]]), 2)


def test_triangle_areas_have_numpys_bits(feature_mesh):
    from spatial.fea.surface_kernels import triangle_areas
    from spatial.fea.surface_quality import _normals

    rng = np.random.default_rng(7)
    cases = [(np.asarray(feature_mesh.points, dtype=np.float64), mesh_faces(feature_mesh)),
             (rng.normal(size=(50, 3)) * 1e3, rng.integers(0, 50, size=(400, 3)))]  # repeated corners: area 0
    for p, f in cases:
        assert _same_bits(triangle_areas(p, f), 0.5 * np.linalg.norm(_normals(p, f), axis=1))
    assert triangle_areas(cases[0][0], cases[0][1]).sum() == pytest.approx(13.67, abs=0.01)
    assert triangle_areas(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)).shape == (0,)
    with pytest.raises(ValueError, match="faces: expected point numbers"):
        triangle_areas(np.zeros((2, 3)), np.array([[0, 1, 2]]))


def test_corner_volumes_have_numpys_bits():
    from spatial.fea.quality import tet_volumes
    from spatial.fea.score_kernel import corner_volumes

    rng = np.random.default_rng(11)
    p = rng.normal(size=(300, 3)) * rng.uniform(1e-3, 1e3, size=(300, 1))
    t = rng.integers(0, 300, size=(4000, 4))  # some repeated corners: volume 0
    x = p[t]
    e1, e2, e3 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]
    ref = np.einsum("ij,ij->i", e1, np.cross(e2, e3)) / 6.0
    assert _same_bits(corner_volumes(p, t), ref) and _same_bits(tet_volumes(p, t), ref)
    unit = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    assert tet_volumes(unit, [[0, 1, 2, 3]]).tolist() == [1 / 6] and corner_volumes(unit, t[:0]).shape == (0,)


def test_cells_mesh_is_pyacvds_mesh_of_the_cells(feature_mesh):
    import pyacvd

    from spatial.fea.surface_clusters import _cells_mesh, _clean_input

    pts, faces, area = _clean_input(feature_mesh)
    clus = pyacvd.Clustering(_polydata(pts, faces))
    clus.cluster(int(round(1.1547 * area / 0.15 ** 2)))
    ref, got = clus.create_mesh(moveclus=False), _cells_mesh(clus)
    assert got.n_points == ref.n_points > 500
    assert _same_bits(np.asarray(got.points), np.asarray(ref.points))
    assert np.array_equal(mesh_faces(got), mesh_faces(ref))
