"""Parts with voids inside: TetGen must leave the void empty."""

import math

import numpy as np
import pytest
import pyvista as pv

from implicit import box, sphere
from spatial.fea import tet_mesh
from spatial.fea.cavities import cavity_points


def _shells(*spheres):
    """Concentric UV spheres, (radius, outward) each, merged into one surface."""
    parts = []
    for radius, outward in spheres:
        s = pv.Sphere(radius=radius, theta_resolution=24, phi_resolution=24).triangulate().clean()
        parts.append(s if outward else s.flip_faces())
    merged = parts[0]
    for p in parts[1:]:
        merged = merged.merge(p, merge_points=False)
    return np.asarray(merged.points), merged.faces.reshape(-1, 4)[:, 1:]


def test_no_point_for_one_shell():
    pts, faces = _shells((1.0, True))
    assert cavity_points(pts, faces).shape == (0, 3)


def test_one_point_per_void_and_none_in_a_nested_ball():
    # ball of 3 with a void of 2 holding a ball of 1: one void, between radii 1 and 2.
    pts, faces = _shells((3.0, True), (2.0, False), (1.0, True))
    holes = cavity_points(pts, faces)
    assert holes.shape == (1, 3)
    r = np.linalg.norm(holes[0])
    assert 1.0 < r < 2.0
    # The point lies just inside the void's own chord surface, not far from it.
    assert r > 1.95


def test_box_with_a_spherical_void_is_meshed_hollow():
    solid = box(20) - sphere(5)
    mesh = tet_mesh(solid, size=2)
    exact = 8000 - 4 / 3 * math.pi * 125
    assert mesh.volume == pytest.approx(exact, rel=0.01)
    centroids = mesh.points[mesh.tets[:, :4]].mean(axis=1)
    # No element in the void: every centroid at least a chord's sag short of the radius away.
    assert np.linalg.norm(centroids, axis=1).min() > 4.5


def test_hollow_ball_is_meshed_hollow():
    # Filled, its mesh measured 520 against the solid's 255.5 and tet_mesh refused it.
    mesh = tet_mesh(sphere(5) - sphere(4), size=1)
    assert mesh.volume == pytest.approx(4 / 3 * math.pi * 61, rel=0.01)
    assert np.linalg.norm(mesh.points[mesh.tets[:, :4]].mean(axis=1), axis=1).min() > 3.9
