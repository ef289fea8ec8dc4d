"""The surface measures' fast forms agree with the plain ones they replace."""

import numpy as np
import pyvista as pv
import pytest

from spatial.fea.surface_quality import _is_closed_manifold, _is_closed_manifold_sorted, _normals, mesh_faces


def _sphere_faces():
    return mesh_faces(pv.Sphere(theta_resolution=12, phi_resolution=10).triangulate().clean())


@pytest.mark.parametrize("change", ["none", "drop", "repeat", "split"])
def test_closed_manifold_check_agrees_with_the_sorted_edges(change):
    faces = _sphere_faces()
    if change == "drop":      # a hole: three edges in one triangle only
        faces = faces[1:]
    elif change == "repeat":  # a triangle twice: its edges in three or four
        faces = np.concatenate([faces, faces[:1]])
    elif change == "split":   # a triangle's edge used by a stray triangle
        faces = np.concatenate([faces, [[faces[0, 0], faces[0, 1], faces.max() + 1]]])
    want = change == "none"
    assert _is_closed_manifold(faces) is want
    assert _is_closed_manifold_sorted(faces) is want
    assert _is_closed_manifold(np.zeros((0, 3), dtype=np.int64)) is True


def test_normals_are_numpys_cross_products_bit_for_bit():
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(300, 3))
    faces = rng.integers(0, 300, size=(2000, 3))
    a, b, c = (pts[faces[:, i]] for i in range(3))
    np.testing.assert_array_equal(_normals(pts, faces), np.cross(b - a, c - a))
