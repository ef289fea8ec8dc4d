"""Order-2 boundary mid-edge nodes on the true surface at hole rims and inner corners, every element's
Jacobian proven positive (Bezier bounds)."""

import warnings

import numpy as np
import pytest

from implicit import box, cylinder, sphere
from implicit.families import instance
from spatial.fea import tet_mesh
from spatial.fea.curved import OFF_SURFACE, untangle_midnodes
from spatial.fea.jacobian_bounds import jacobian_sign

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
BENCH_VOLUME = 0.988789504774
BRACKET = instance("l_bracket", width=30, leg_a=50, leg_b=40, thickness=4, hole_diameter=6, holes_per_leg=2)

_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])


def _unit_tet10():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    return np.concatenate([p, 0.5 * (p[_EDGES[:, 0]] + p[_EDGES[:, 1]])]), np.arange(10)[None]


def test_interior_mid_nodes_bend_out_of_the_way_of_a_curved_edge():
    x, t = _unit_tet10()
    x[4] = [0.5, 0.3, 0.0]  # the mid node of edge 01 bent into the element: the determinant dips below 0
    assert jacobian_sign(x, t)[0] == -1
    free = np.r_[[False] * 5, [True] * 5]
    y = untangle_midnodes(x, t, free)
    assert jacobian_sign(y, t)[0] == 1
    # the corners and the bent node stay where they were, the interior mid nodes moved
    np.testing.assert_array_equal(y[~free], x[~free])
    assert np.linalg.norm(y[free] - x[free], axis=1).max() > 0.01


def test_a_fold_no_free_node_can_undo_is_left_as_it_is():
    x, t = _unit_tet10()
    x[4] = [0.5, 0.6, 0.0]
    # The determinant at corner 1 is det(x0 + 3 x1 - 4 x4, x0 + 4 x5 - 4 x4, x0 + 4 x8 - 4 x4) = -0.8:
    # with only the mid node of the opposite edge 23 free nothing can change it.
    free = np.zeros(10, dtype=bool)
    free[9] = True
    y = untangle_midnodes(x, t, free)
    assert jacobian_sign(y, t)[0] == -1
    np.testing.assert_array_equal(y[:9], x[:9])
    # freeing the mid nodes of edges 12 and 13 (x5, x8) lets the determinant at corner 1 turn positive
    free[[5, 8]] = True
    assert jacobian_sign(untangle_midnodes(x, t, free), t)[0] == 1
    # a valid element is left alone
    z, _ = _unit_tet10()
    np.testing.assert_array_equal(untangle_midnodes(z, t, np.ones(10, dtype=bool)), z)


def test_boundary_mid_nodes_that_slide_stay_on_the_surface_and_unfold_the_element():
    x, t = _unit_tet10()
    x[4] = [0.5, 0.6, 0.0]  # the fold at corner 1 that the mid nodes of edges 12 and 13 can undo
    # both lie on a sphere about corner 1 (radius 1 / sqrt 2): sliding on it they must stay there
    ball = sphere(np.sqrt(0.5)).translate((1, 0, 0))
    slide = np.zeros(10, dtype=bool)
    slide[[5, 8]] = True
    assert np.abs(ball(x[slide])).max() < 1e-15 and jacobian_sign(x, t)[0] == -1
    y = untangle_midnodes(x, t, slide, solid=ball, slide=slide)
    assert jacobian_sign(y, t)[0] == 1
    assert np.abs(ball(y[slide])).max() < 1e-9 and np.linalg.norm(y[slide] - x[slide], axis=1).min() > 0.01
    np.testing.assert_array_equal(y[~slide], x[~slide])
    with pytest.raises(ValueError, match="slide"):
        untangle_midnodes(x, t, slide, slide=slide)


def _surface_mid_nodes_all_on(m, solid, size):
    nodes = m.node_sets["surface"]
    f = np.abs(solid(m.points[nodes]))
    return f.max(), int((f > OFF_SURFACE * size).sum())


@pytest.mark.parametrize("solid, size, volume", [(BRACKET, 3.0, None), (BENCH, 0.2, BENCH_VOLUME),
                                                 (BENCH, 0.15, BENCH_VOLUME)], ids=["l_bracket 3", "bench 0.2", "bench 0.15"])
def test_every_boundary_node_of_a_curved_mesh_lies_on_the_surface(solid, size, volume):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # (the benchmark part's linear surface at 0.2 misses the volume check, a matter of its size)
        m = tet_mesh(solid, size=size, order=2, reference_volume=volume, allow_poor=True)
    worst, off = _surface_mid_nodes_all_on(m, solid, size)
    print(f"size {size}: {m.quality.n_elements} elements, {len(m.node_sets['surface'])} surface nodes, {off} off "
          f"(max |f| {worst:.3g}), {m.info.get('removed_for_curving', 0)} flat elements removed")
    # before: l_bracket at 3 left 1 to 4 nodes off (|f| up to 0.5), the benchmark part 1 to 4 (up to 0.08);
    # on the surface started from the feature mesh the benchmark part at 0.2 left 2 (a curved edge across
    # the top's annulus, narrower than the size) until boundary mid nodes could slide on the surface
    assert off == 0 and m.info["off_surface_nodes"] == 0 and worst <= OFF_SURFACE * size
    assert np.all(jacobian_sign(m.points, m.tets) == 1)
    assert m.quality.min_scaled_jacobian > 0 and m.quality.min_dihedral >= 10.0
    if volume is not None:
        assert m.volume == pytest.approx(volume, rel=0.006)
