"""Clusters confined to the CSG faces: parts as thin as the size keep their volume, corners and edges."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from implicit import box
from spatial.fea import tet_mesh
from spatial.fea.facets import FacetField
from spatial.fea.surface import FACE_VOLUME_MISS, surface_for_fea, surface_quality
from spatial.fea.surface_faces import _merge_smooth, _unfolded, face_clusters
from spatial.fea.surface_start import start_mesh

BEAM = box((100.0, 10.0, 10.0), center=(50.0, 0.0, 0.0))
PLATE = box((100.0, 60.0, 5.0))
TOUCHING = box((10, 10, 10), center=(5, 5, 5)) | box((5, 10, 5), center=(12.5, 5, 2.5))
# the step's corners: six of the cube, four of the small box's far end, two of the inner edge
TOUCHING_CORNERS = np.array([[x, y, z] for y in (0, 10) for x, z in
                             ((0, 0), (0, 10), (10, 10), (15, 0), (15, 5), (10, 5))], dtype=float)


def _box_corners(lo, hi):
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])], float)


def _nodes_on(surface, points):
    dist, _ = cKDTree(np.asarray(surface.points)).query(points)
    return int((dist <= 1e-9).sum())


def _triangles_off_one_face(solid, surface):
    """Triangles whose three nodes lie on no common facet (a cell spanning two faces)."""
    ff = FacetField(solid)
    _, _, fv = ff(np.asarray(surface.points))
    on = np.abs(fv) < 1e-9  # (facets, nodes)
    f = np.asarray(surface.faces).reshape(-1, 4)[:, 1:]
    common = on[:, f[:, 0]] & on[:, f[:, 1]] & on[:, f[:, 2]]
    return int((~common.any(axis=0)).sum())


@pytest.mark.parametrize("solid, size, volume, corners", [
    (BEAM, 10.0, 1e4, _box_corners((0, -5, -5), (100, 5, 5))),
    (PLATE, 5.0, 3e4, _box_corners((-50, -30, -2.5), (50, 30, 2.5))),
    (TOUCHING, 5.0, 1250.0, TOUCHING_CORNERS),
])
def test_a_part_as_thin_as_the_size_keeps_its_volume_corners_and_faces(solid, size, volume, corners):
    s = surface_for_fea(solid, size=size)
    assert s.field_data["clusters"][0] == "faces" and s.field_data["size"][0] == size
    q = surface_quality(s, solid)
    assert q.closed and q.max_deviation < 1e-9 and q.min_angle > 15.0
    assert abs(abs(s.volume) - volume) / volume < 1e-9
    assert _nodes_on(s, corners) == len(corners)
    assert _triangles_off_one_face(solid, s) == 0


def test_the_beam_at_its_thickness_has_its_long_edges_as_chains_of_nodes():
    s = surface_for_fea(BEAM, size=10.0)
    p = np.asarray(s.points)
    # every node on one of the four long edges, ten pieces of 10 each
    assert np.allclose(np.abs(p[:, 1:]), 5.0, atol=1e-9)
    for y in (-5.0, 5.0):
        for z in (-5.0, 5.0):
            x = np.sort(p[(p[:, 1] == y) & (p[:, 2] == z), 0])
            np.testing.assert_allclose(x, np.arange(0.0, 101.0, 10.0), atol=1e-9)


def test_free_clusters_stay_where_they_keep_the_volume():
    # a cube of 10 at size 2: the free clusters miss its volume by less than FACE_VOLUME_MISS
    s = surface_for_fea(box(10.0), size=2.0)
    assert s.field_data["clusters"][0] == "free"
    assert abs(abs(s.volume) - 1000.0) / 1000.0 <= FACE_VOLUME_MISS


@pytest.mark.parametrize("solid, size, volume", [(BEAM, 10.0, 1e4), (PLATE, 5.0, 3e4), (TOUCHING, 5.0, 1250.0)])
@pytest.mark.parametrize("order", [1, 2])
def test_thin_parts_tet_mesh_at_the_asked_size(solid, size, volume, order):
    m = tet_mesh(solid, size=size, order=order, reference_volume=volume)
    assert m.info["surface_size"] == size and m.info["surface_clusters"] == "faces"
    assert m.volume == pytest.approx(volume, rel=1e-9)
    assert m.quality.min_dihedral >= 10.0 and m.quality.min_scaled_jacobian > 0
    assert m.info["problems"] == []


def test_face_clusters_of_a_cube_at_its_edge_length():
    part = box(10.0)
    feature, _, _ = start_mesh(part, 2.5)
    p, f, fixed = face_clusters(feature, FacetField(part), 10.0)
    # the cube's own 8 corners and 12 triangles: every edge one piece
    assert len(p) == 8 and len(f) == 12 and fixed.all()
    np.testing.assert_allclose(np.abs(p), 5.0, atol=1e-12)


def test_touching_coplanar_faces_make_one_face():
    feature, _, _ = start_mesh(TOUCHING, 1.25)
    ff = FacetField(TOUCHING)
    tris = np.asarray(feature.faces).reshape(-1, 4)[:, 1:]
    pts = np.asarray(feature.points)
    _, region, _ = ff(pts[tris].mean(axis=1))
    merged = _merge_smooth(ff, pts, tris, np.asarray(region, dtype=np.int64), len(pts))
    names = np.array(ff.names)
    # the -y sides of both boxes lie in one plane: one face, named by the first
    assert set(names[merged[np.isin(names[region], ["box_0.-y", "box_1.-y"])]]) == {"box_0.-y"}
    # the crease between the cube's +x side and the small box's top stays
    assert {"box_0.+x", "box_1.+z"} <= set(names[merged])


def test_a_path_turning_back_loses_its_fold():
    q = np.array([[0, 0, 5.0], [0, 0, 3.75], [0, 0, 3.125], [0, 0, 4.375], [0, 0, 5.625], [0, 0, 10.0]])
    assert _unfolded(q).tolist() == [True, False, False, False, True, True]
    straight = np.c_[np.zeros(5), np.zeros(5), np.arange(5.0)]
    assert _unfolded(straight).all()
