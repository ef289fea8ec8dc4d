"""The compiled binary STL writer and edge count: the numpy forms' results, read back by meshio and VTK."""

from __future__ import annotations

import numpy as np
import pytest

from spatial.files import meshes, save_mesh
from spatial.files.kernels import RECORD, edges_twice, stl_records
from spatial.files.surface import TriangleArrays, _edges_twice_sorted


def _octahedron():
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return points, faces


def _random_surface(seed, n_points=400, n_faces=3000):
    """Points of many magnitudes and triangles among them, degenerate ones included."""
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n_points, 3)) * 10.0 ** rng.integers(-3, 4, size=(n_points, 1))
    faces = rng.integers(0, n_points, size=(n_faces, 3))
    faces[:50, 1] = faces[:50, 0]                      # two corners on one point: zero normal
    points[-1] = points[-2]                            # two points at one place
    faces[50:60] = [n_points - 1, n_points - 2, 7]
    return points, faces


def test_the_records_of_an_octahedron_are_its_unit_normals_and_corners():
    points, faces = _octahedron()
    out = np.full(RECORD * len(faces), 255, dtype=np.uint8)
    stl_records(points, faces, 0, len(faces), out)
    rec = out.reshape(-1, RECORD)
    normals = rec[:, :12].copy().view("<f4")
    corners = rec[:, 12:48].copy().view("<f4").reshape(-1, 3, 3)
    # each face of the octahedron faces away from the centre, along (+-1, +-1, +-1) / sqrt(3)
    centres = points[faces].mean(axis=1)
    np.testing.assert_allclose(normals, centres / np.linalg.norm(centres, axis=1)[:, None], atol=1e-7)
    np.testing.assert_array_equal(corners, points[faces].astype(np.float32))
    assert not rec[:, 48:].any()


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("chunk", [1 << 17, 7])
def test_the_compiled_writer_writes_the_numpy_forms_bytes(tmp_path, seed, chunk):
    points, faces = _random_surface(seed)
    meshes._write_binary_stl(TriangleArrays(points, faces), tmp_path / "kernel.stl", chunk=chunk)
    meshes._write_binary_stl_numpy(points, faces, tmp_path / "numpy.stl", chunk=chunk)
    kernel, reference = (tmp_path / "kernel.stl").read_bytes(), (tmp_path / "numpy.stl").read_bytes()
    assert len(kernel) == 84 + RECORD * len(faces)
    assert kernel == reference
    normals = np.frombuffer(kernel[84:], dtype=np.uint8).reshape(-1, RECORD)[:, :12].copy().view("<f4")
    assert not normals[:50].any()                      # the degenerate triangles
    norms = np.linalg.norm(normals, axis=1)
    # a unit normal, or zero where the corners are collinear (random ids repeat now and then)
    assert (norms[60:] > 0.5).mean() > 0.99
    np.testing.assert_allclose(norms[norms > 0.5], 1.0, atol=1e-6)


def test_meshio_and_vtk_read_back_the_same_triangles(tmp_path):
    import meshio
    import pyvista as pv

    points, faces = _octahedron()
    points = points * 3.25 + [0.5, -2.0, 7.0]
    path = save_mesh(TriangleArrays(points, faces), tmp_path / "octahedron.stl")
    read = meshio.read(path)
    corners = read.points[read.cells_dict["triangle"]]
    np.testing.assert_array_equal(corners, points[faces].astype(np.float32))
    vtk = pv.read(path)
    assert vtk.n_cells == 8 and vtk.is_manifold
    assert vtk.volume == pytest.approx(4 / 3 * 3.25 ** 3, rel=1e-6)


def test_edges_twice_on_closed_open_and_branching_surfaces():
    points, faces = _octahedron()
    assert edges_twice(faces, 6)
    assert not edges_twice(faces[:-1], 6)                            # one face off: three open edges
    assert not edges_twice(np.vstack([faces, faces[:1]]), 6)         # one face twice: edges of three
    assert not edges_twice(np.vstack([faces, faces[:2]]), 6)         # two faces twice: edges of three or four
    two = np.vstack([faces, faces + 6])                              # two octahedra sharing nothing
    assert edges_twice(two, 12) and TriangleArrays(np.vstack([points, points + 3]), two).is_manifold


@pytest.mark.parametrize("seed", range(4))
def test_edges_twice_agrees_with_sorting_the_edge_keys(seed):
    rng = np.random.default_rng(seed)
    points, faces = _octahedron()
    closed = np.vstack([faces + 6 * k for k in range(30)])
    for _ in range(40):
        f = closed[rng.permutation(len(closed))]
        f = f[: len(f) - int(rng.integers(0, 2))]
        if rng.random() < 0.3:
            f = np.vstack([f, f[rng.integers(0, len(f), int(rng.integers(1, 3)))]])
        assert bool(edges_twice(f, 180)) is _edges_twice_sorted(f, 180)


def test_ids_outside_the_points_are_counted_by_sorting():
    points, faces = _octahedron()
    assert TriangleArrays(points[:5], faces).is_manifold is _edges_twice_sorted(faces, 5)
    assert TriangleArrays(points, faces - 1).is_manifold is _edges_twice_sorted(faces - 1, 6)
