"""The FEA surface is clustered from the feature mesh: every CSG corner a node, one marching-cubes mesh."""

import os
import runpy

import numpy as np
import pytest
from scipy.spatial import cKDTree

from implicit import box, cylinder, sphere
from spatial.fea.surface import folded_triangles, mesh_faces, surface_for_fea, surface_quality
from spatial.fea.surface_start import start_mesh, usable_start

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
# The benchmark part's only corners: where the three bores meet, x^2 = y^2 = z^2 = 0.5^2 / 2.
BENCH_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * np.sqrt(0.125)
TOUCHING = box((10, 10, 10), center=(5, 5, 5)) | box((5, 10, 5), center=(12.5, 5, 2.5))
# The 12 corners of the step: six of the cube, four of the small box's far end, two of the inner edge
# (the cube's corners at x = 10, z = 0 lie on the straight bottom edges, not corners).
TOUCHING_CORNERS = np.array([[x, y, z] for y in (0, 10) for x, z in
                             ((0, 0), (0, 10), (10, 10), (15, 0), (15, 5), (10, 5))], dtype=float)


def _nodes_on(surface, points, size):
    dist, _ = cKDTree(np.asarray(surface.points)).query(points)
    return int((dist <= 1e-6 * size).sum())


def test_benchmark_part_starts_from_the_feature_mesh_with_its_corners_as_nodes():
    size = 0.15
    s = surface_for_fea(BENCH, size=size)
    assert s.field_data["start"][0] == "features"
    assert _nodes_on(s, BENCH_CORNERS, size) == 8
    # exact to the corners' facet solve
    dist, _ = cKDTree(np.asarray(s.points)).query(BENCH_CORNERS)
    assert dist.max() < 1e-9
    q = surface_quality(s, BENCH)
    assert q.closed and q.min_angle > 9.0 and abs(abs(s.volume) - 0.988789504774) / 0.988789504774 < 0.01


@pytest.mark.parametrize("size", [1.0, 2.0])
def test_touching_boxes_keep_their_volume_exactly(size):
    """Nodes on the coplanar faces of the two boxes are not taken for nodes on an edge: every node next
    to the small box's edges goes onto them (5.1e-4 of the volume was lost at size 2)."""
    s = surface_for_fea(TOUCHING, size=size)
    assert s.field_data["start"][0] == "features"
    assert abs(abs(s.volume) - 1250.0) < 1e-9 * 1250.0
    assert _nodes_on(s, TOUCHING_CORNERS, size) == 12
    assert np.abs(TOUCHING(np.asarray(s.points))).max() < 1e-9


def test_the_plain_start_keeps_the_touching_boxes_volume_too():
    s = surface_for_fea(TOUCHING, size=2.0, start="plain")
    assert s.field_data["start"][0] == "plain"
    assert abs(abs(s.volume) - 1250.0) < 1e-9 * 1250.0


def test_part_family_bracket_starts_from_the_feature_mesh():
    solid = runpy.run_path(os.path.join(EXAMPLES, "bracket.py"))["solid"]
    start, corners, kind = start_mesh(solid, 0.5)
    assert kind == "features" and start is corners
    # the L profile's 6 corners at both ends (the holes' rims are circles, no corners): the feature mesh
    # lists 10 of them, the surface's own corner snapping finds the two others
    profile = [(0, 0), (50, 0), (50, 4), (4, 4), (4, 40), (0, 40)]
    want = np.array([[x, y, z] for y in (0.0, 30.0) for x, z in profile], dtype=float)
    listed = start.points[np.asarray(start.point_data["feature_rank"]) == 3]
    assert 10 <= listed.shape[0] <= 12 and cKDTree(want).query(listed)[0].max() < 0.5
    s = surface_for_fea(solid, size=2.0)
    assert s.field_data["start"][0] == "features"
    assert _nodes_on(s, want, 2.0) == 12


@pytest.mark.parametrize("size", [5.0, 10.0])
def test_beam_meshes_from_the_feature_mesh_with_its_corners_and_volume(size):
    from spatial.fea import tet_mesh

    beam = box((100.0, 10.0, 10.0), center=(50.0, 0.0, 0.0))
    m = tet_mesh(beam, size=size, reference_volume=1e4)
    corners = np.array([[x, y, z] for x in (0, 100) for y in (-5, 5) for z in (-5, 5)], dtype=float)
    dist, _ = cKDTree(m.points[np.unique(m.boundary)]).query(corners)
    assert dist.max() < 1e-9
    assert m.volume == pytest.approx(1e4, rel=1e-9)
    assert m.quality.min_dihedral >= 10.0
    # at 10 too the surface is made at the asked size (clusters kept to the faces there)
    assert m.info["surface_size"] == size
    assert m.info["surface_clusters"] == ("faces" if size == 10.0 else "free")


def test_an_unusable_feature_mesh_falls_back_to_the_plain_start():
    import pyvista as pv

    assert not usable_start(pv.Sphere())  # no feature point data
    assert not usable_start(pv.PolyData())
    start, corners, kind = start_mesh(box(1.0), 0.1, "plain")
    assert kind == "plain" and start is not corners and "feature_rank" not in start.point_data


def test_start_is_checked():
    with pytest.raises(ValueError, match="start: expected 'features' or 'plain'"):
        surface_for_fea(box(1.0), size=0.3, start="feature")


def test_folded_triangles_count_a_face_turned_over():
    s = surface_for_fea(box(2.0), size=0.5)
    p, f = np.asarray(s.points), mesh_faces(s)
    assert folded_triangles(box(2.0), p, f) == 0
    f[3] = f[3, ::-1]
    assert folded_triangles(box(2.0), p, f) == 1
