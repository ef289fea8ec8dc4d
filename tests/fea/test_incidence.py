"""The compiled incidences against the sorts they replace, on real meshes and random cells."""

import numpy as np
import pytest

from spatial.fea.incidence import node_cells, single_sides
from spatial.fea.model import SIDE_NODES
from spatial.fea.slivers import boundary_faces


def _sorted_incidence(cells, n):
    flat = np.asarray(cells, dtype=np.int64).reshape(-1)
    order = np.argsort(flat, kind="stable")
    return order, np.searchsorted(flat[order], np.arange(n + 1))


def _sorted_single(tets):
    key = np.sort(np.asarray(tets)[:, SIDE_NODES].reshape(-1, 3), axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return counts[inv.reshape(-1)] == 1


@pytest.fixture(scope="module")
def part_mesh():
    from implicit import box, cylinder
    from spatial.fea import tet_mesh

    return tet_mesh(box(2.0) - cylinder(0.5, 4), size=0.3)  # 4,589 elements


def test_node_cells_equal_the_stable_sort_on_a_real_mesh(part_mesh):
    for cells in (part_mesh.tets, part_mesh.boundary):
        order, starts = node_cells(cells, len(part_mesh.points))
        ref_order, ref_starts = _sorted_incidence(cells, len(part_mesh.points))
        assert np.array_equal(order, ref_order) and np.array_equal(starts, ref_starts)


@pytest.mark.parametrize("seed", range(5))
def test_node_cells_equal_the_stable_sort_on_random_cells(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    cells = rng.integers(0, n, size=(int(rng.integers(0, 300)), int(rng.integers(1, 7))))
    # nodes past the last used one (no cells) and repeated nodes within a cell are allowed
    order, starts = node_cells(cells, n + 3)
    ref_order, ref_starts = _sorted_incidence(cells, n + 3)
    assert np.array_equal(order, ref_order) and np.array_equal(starts, ref_starts)
    assert starts[-1] == cells.size and np.all(np.diff(starts) >= 0)


def test_node_cells_of_nothing_and_refusals():
    order, starts = node_cells(np.zeros((0, 4), dtype=np.int64), 3)
    assert order.size == 0 and starts.tolist() == [0, 0, 0, 0]
    order, starts = node_cells(np.zeros((0, 4), dtype=np.int64), 0)
    assert order.size == 0 and starts.tolist() == [0]
    with pytest.raises(ValueError, match=r"cells: expected node numbers in 0 \.\. 2, got 0 \.\. 3"):
        node_cells(np.array([[0, 1, 3]]), 3)
    with pytest.raises(ValueError, match="cells: expected node numbers"):
        node_cells(np.array([[0, -1, 2]]), 3)
    with pytest.raises(ValueError, match="n: expected a number of nodes"):
        node_cells(np.array([[0]]), -1)


def test_single_sides_equal_the_sorted_count_on_a_real_mesh(part_mesh):
    once = single_sides(part_mesh.tets, SIDE_NODES)
    assert np.array_equal(once, _sorted_single(part_mesh.tets))
    assert once.sum() == len(part_mesh.boundary)


@pytest.mark.parametrize("seed", range(6))
def test_single_sides_equal_the_sorted_count_on_random_elements(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 12))  # few nodes: many sides shared twice or more, some elements repeated
    tets = rng.integers(0, n, size=(int(rng.integers(1, 200)), 4)) + int(rng.integers(0, 5))
    assert np.array_equal(single_sides(tets, SIDE_NODES), _sorted_single(tets))


def test_single_sides_of_degenerate_and_empty_input():
    # a side with a repeated node, an element given twice, sides in another corner order
    tets = np.array([[0, 0, 1, 2], [3, 4, 5, 6], [3, 4, 5, 6], [6, 5, 4, 7]])
    assert np.array_equal(single_sides(tets, SIDE_NODES), _sorted_single(tets))
    assert single_sides(np.zeros((0, 4), dtype=np.int64), SIDE_NODES).shape == (0,)
    with pytest.raises(ValueError, match="side_nodes: expected"):
        single_sides(np.array([[0, 1, 2]]), SIDE_NODES)


def test_boundary_faces_of_two_elements():
    faces, elem, side = boundary_faces(np.array([[0, 1, 2, 3], [1, 2, 3, 4]]))
    assert elem.tolist() == [0, 0, 0, 1, 1, 1] and side.tolist() == [0, 1, 3, 1, 2, 3]
    assert faces.tolist() == [[0, 2, 1], [0, 1, 3], [2, 0, 3], [1, 2, 4], [2, 3, 4], [3, 1, 4]]
    faces, elem, side = boundary_faces(np.zeros((0, 4), dtype=np.int64))
    assert faces.shape == (0, 3) and elem.size == 0 and side.size == 0
