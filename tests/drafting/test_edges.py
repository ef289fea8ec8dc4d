"""Feature edges snapped onto the CSG faces, silhouettes, visibility, hatching, scales."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import spatial
from implicit import box, cylinder, sphere
from spatial.drafting.edges import silhouettes, surface_edges
from spatial.drafting.layout import place_grid
from spatial.drafting.part_views import part_mesh
from spatial.drafting.section_view import hatch_segments
from spatial.drafting.views import scale_text, view_frame
from spatial.drafting.visibility import DepthBuffer


def length(lines):
    return sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in lines)


def test_box_edges_are_single_and_exact():
    part = box((4, 2, 1))
    m = part_mesh(part, resolution=40)
    e = surface_edges(m, part)
    assert length(e.polylines) == pytest.approx(4 * (4 + 2 + 1), rel=0.01)
    pts = np.concatenate(e.polylines)
    # Every point lies on one of the twelve edges (two coordinates at their extremes), within a
    # tenth of a voxel near the corners and far closer along the edges.
    dist = np.sort(np.abs(np.abs(pts) - [2.0, 1.0, 0.5]), axis=1)[:, 1]
    assert dist.max() < 0.1 * e.voxel_size
    assert np.median(dist) < 1e-6
    # On a plain marching-cubes mesh the mesh normals alone draw the chamfered edges twice.
    plain = spatial.mesh(part, resolution=40, progress=False, features=False)
    assert length(surface_edges(plain).polylines) > 1.5 * length(e.polylines)


def test_hole_rims_are_circles_of_the_hole_radius():
    part = box((20, 20, 4)) - cylinder(3, 10)
    m = part_mesh(part, resolution=64)
    e = surface_edges(m, part)
    rims = [p for p in e.polylines if np.hypot(p[:, 0], p[:, 1]).max() < 4]
    assert len(rims) == 2
    for p in rims:
        # The feature mesh's rim vertices are on the circle, but for the few at the joins of its
        # curve pieces (within an eighth of a voxel, h = 0.31).
        r = np.hypot(p[:, 0], p[:, 1])
        assert np.median(np.abs(r - 3.0)) < 1e-6 and np.abs(r - 3.0).max() < 0.04
        assert np.abs(np.abs(p[:, 2]) - 2.0).max() < 1e-3


def test_cylinder_silhouettes_from_the_side():
    part = cylinder(2, 6)
    m = part_mesh(part, resolution=48)
    e = surface_edges(m, part)
    sil = silhouettes(e, (0, 1, 0))
    assert len(sil) == 2
    xs = sorted(float(np.median(p[:, 0])) for p in sil)
    assert xs == pytest.approx([-2.0, 2.0], abs=0.01)
    # Seen along its axis a cylinder has no silhouette on its side: the cap edges are the outline.
    assert silhouettes(e, (0, 0, 1)) == []
    # A sphere has one, a circle of its radius.
    ball = sphere(1.0)
    eb = surface_edges(part_mesh(ball, resolution=32), ball)
    (ring,) = silhouettes(eb, (1, 0, 0))
    assert np.abs(np.hypot(ring[:, 1], ring[:, 2]) - 1.0).max() < 0.01


def test_depth_buffer_hides_what_lies_behind_a_face():
    part = box((2, 2, 2))
    m = spatial.mesh(part, resolution=16, progress=False)
    tris = np.asarray(m.faces).reshape(-1, 4)[:, 1:]
    buf = DepthBuffer(np.asarray(m.points), tris, view_frame("front"), pixel=0.05)
    front_face = np.array([[0.2, -1.0, 0.3], [-0.5, -1.0, 0.0]])
    inside = np.array([[0.0, 0.0, 0.0], [0.5, 0.9, 0.5]])
    outline = np.array([[1.0, 0.5, 1.0]])          # on the top-right edge, behind: seen past the outline
    assert buf.visible(front_face, 0.05).all()
    assert not buf.visible(inside, 0.05).any()
    assert buf.visible(outline, 0.05).all()


@settings(max_examples=25, deadline=None)
@given(w=st.floats(1, 50), h=st.floats(1, 50), spacing=st.floats(0.3, 5), angle=st.sampled_from([45.0, -45.0, 30.0]))
def test_hatching_fills_the_area(w, h, spacing, angle):
    rect = [np.array([[0, 0], [w, 0], [w, h], [0, h]], float)]
    segs = hatch_segments(rect, spacing, angle)
    total = float(np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum()) if len(segs) else 0.0
    # Each line stands for a strip `spacing` wide; the error is at most a strip along the outline.
    assert abs(total * spacing - w * h) <= spacing * (w + h) * 1.5 + 1e-9
    if len(segs):
        assert segs[..., 0].min() >= -1e-9 and segs[..., 0].max() <= w + 1e-9
        assert segs[..., 1].min() >= -1e-9 and segs[..., 1].max() <= h + 1e-9


def test_hatching_leaves_holes_empty():
    outer = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    hole = np.array([[3, 3], [3, 7], [7, 7], [7, 3]], float)
    segs = hatch_segments([outer, hole], 0.5)
    mid = 0.5 * (segs[:, 0] + segs[:, 1])
    inside_hole = (np.abs(mid - 5.0) < 2.0 - 1e-6).all(axis=1)
    assert not inside_hole.any()
    total = float(np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum())
    assert total * 0.5 == pytest.approx(100 - 16, rel=0.05)


def test_the_scale_is_the_largest_standard_one_that_fits():
    def cells(size):
        return {"front": ((0, 0), (0, 0, size, size), (10, 10, 10, 10))}

    assert scale_text(place_grid(cells(40), (0, 0, 200, 200))[0]) == "2:1"     # 80 + 20 fits, 200 + 20 does not
    assert scale_text(place_grid(cells(100), (0, 0, 200, 200))[0]) == "1:1"
    assert scale_text(place_grid(cells(1000), (0, 0, 200, 200))[0]) == "1:10"
    assert scale_text(place_grid(cells(3), (0, 0, 200, 200))[0]) == "50:1"
