"""The feature pass costs no triangles: each fan's feature vertex takes one vertex of its polygon."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from meshcheck import min_area, topology, vertex_manifold
from parts import benchmark_part, holed_plate

from spatial.meshing import mesh
from spatial.meshing.feature_collapse import collapse_fans

BENCH = benchmark_part()
plate = holed_plate


@pytest.mark.parametrize("make, n", [(lambda: BENCH, 24), (lambda: BENCH, 40), (plate, 48), (plate, 64)])
def test_triangle_count_of_the_feature_mesh(make, n):
    plain = mesh(make(), resolution=n, progress=False, features=False)
    sharp = mesh(make(), resolution=n, progress=False, features=True)
    # fans alone gave 1.31 (benchmark part, N=24), 1.18 (N=40), 1.22 and 1.14 (plate, N=48 and 64);
    # with the collapses 1.081, 1.011, 1.043, 1.004
    assert sharp.n_cells <= 1.1 * plain.n_cells
    topo = topology(sharp)
    assert topo["edge_counts"] == {2} and topo["oriented"] and topo["degenerate"] == 0
    assert vertex_manifold(sharp) and min_area(sharp) > 0
    # every feature vertex is still used, at its place on the exact edge or corner
    rank = sharp.point_data["feature_rank"]
    assert int(sharp.field_data["feature_cells"][0]) == int((rank > 0).sum())


def _octahedron_fan(z):
    """An octahedron whose top vertex's star is replaced by a fan around a feature vertex at height `z`."""
    pts = np.array([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [0.2, 0.1, z]], float)
    bottom = [[1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]]
    top = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    return pts, np.array(bottom + top)


@given(st.floats(0.3, 0.95))
@settings(max_examples=25, deadline=None)
def test_collapse_keeps_a_closed_oriented_surface(z):
    pts, faces = _octahedron_fan(z)
    # split the top vertex's triangle (0, 1, 4) to the feature vertex 6: one more vertex, two more triangles
    fan = np.concatenate([faces[[0, 1, 2, 3, 5, 6, 7]], [[0, 1, 6], [1, 4, 6], [4, 0, 6]]])
    out, c = collapse_fans(pts, fan, 6)
    assert c == 1 and out.shape == (8, 3)
    used = np.unique(out)
    assert 6 in used and used.shape[0] == 6          # the feature vertex stays, one polygon vertex left
    # closed and oriented: every directed edge once, its reverse once
    e = np.concatenate([out[:, [0, 1]], out[:, [1, 2]], out[:, [2, 0]]])
    assert len({tuple(x) for x in e}) == e.shape[0]
    assert {tuple(x) for x in e} == {(b, a) for a, b in e}
    # the vertex taken was the nearest one of the fan: 4 at (0, 0, 1)
    assert 4 not in used


def test_collapse_refuses_to_turn_triangles():
    pts, faces = _octahedron_fan(0.5)
    fan = np.concatenate([faces[[0, 1, 2, 3, 5, 6, 7]], [[0, 1, 6], [1, 4, 6], [4, 0, 6]]])
    # moving any neighbour of the feature vertex turns some triangle: refused when no turn is allowed
    out, c = collapse_fans(pts, fan, 6, cos_move=1.0)
    assert c == 0 and np.array_equal(out, fan)
    # and a vertex whose triangles would turn by more than 60 degrees is passed over for the next one
    out, c = collapse_fans(pts, fan, 6, cos_move=0.999)
    assert c == 0
    out, c = collapse_fans(pts, fan, 6, cos_move=0.5)
    assert c == 1
