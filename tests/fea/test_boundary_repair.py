"""Radius-edge repair at the boundary: a skinny boundary triangle's node slid on the true surface."""

import numpy as np

from implicit import box, cylinder
from spatial.fea.boundary_repair import slide_boundary_nodes
from spatial.fea.quality import radius_edge_ratio, tet_volumes

RADIUS_EDGE = 3.0


def _tet_on(a, b, c, inner):
    p = np.array([a, b, c, inner], dtype=float)
    t = np.array([[0, 1, 2, 3]])
    if tet_volumes(p, t)[0] < 0:
        t = t[:, [0, 2, 1, 3]]
    return p, t


def test_a_skinny_triangle_on_a_flat_face_is_opened_on_the_face():
    # the corners 0, 1, 2 on the top face z = 0 of the box, 2 only 0.05 off the edge 0-1: radius-edge 6.3
    solid = box((4.0, 4.0, 2.0), center=(0.0, 0.0, -1.0))
    p, t = _tet_on([0, 0, 0], [1, 0, 0], [0.5, 0.05, 0], [0.5, 0.5, -0.8])
    assert radius_edge_ratio(p, t)[0] > 6.0
    q, moves = slide_boundary_nodes(p, t, solid, np.array([False, False, True, False]), 10.0, 165.0, RADIUS_EDGE)
    assert moves >= 1 and radius_edge_ratio(q, t)[0] <= RADIUS_EDGE and tet_volumes(q, t)[0] > 0
    assert q[2, 2] == 0.0 and abs(solid(q[2:3])[0]) < 1e-12          # still on the face
    np.testing.assert_array_equal(q[[0, 1, 3]], p[[0, 1, 3]])        # the nodes that may not slide stay
    # none may slide: nothing moves
    r, none = slide_boundary_nodes(p, t, solid, np.zeros(4, dtype=bool), 10.0, 165.0, RADIUS_EDGE)
    assert none == 0 and np.array_equal(r, p)


def test_a_skinny_triangle_on_a_hole_wall_stays_on_the_cylinder():
    # the wall of a hole of radius 3 (a box minus a cylinder): two corners 0.8 apart on the wall, the
    # third between them 0.04 closer to the axis' chord, the fourth node in the material
    solid = box(20.0) - cylinder(3.0, 30.0)
    ang = np.array([-0.14, 0.14, 0.0])
    z = np.array([0.0, 0.0, 0.05])
    wall = np.column_stack([3.0 * np.cos(ang), 3.0 * np.sin(ang), z])
    p, t = _tet_on(wall[0], wall[1], wall[2], [3.5, 0.0, 0.4])
    before = radius_edge_ratio(p, t)[0]
    assert before > RADIUS_EDGE
    q, moves = slide_boundary_nodes(p, t, solid, np.array([False, False, True, False]), 10.0, 165.0, RADIUS_EDGE)
    assert moves >= 1 and radius_edge_ratio(q, t)[0] <= RADIUS_EDGE and tet_volumes(q, t)[0] > 0
    assert abs(np.hypot(q[2, 0], q[2, 1]) - 3.0) < 1e-9               # on the wall
