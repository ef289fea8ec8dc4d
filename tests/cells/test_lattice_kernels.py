"""The compiled steps of the classification's last levels against the numpy they replace."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st

from spatial.cells import lattice_kernels as K
from spatial.cells.lattice import CHILD_OFFSETS


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(0, 300), st.sampled_from([2, 4]))
def test_upper_edge_split_and_centre_nodes(seed, n, size):
    rng = np.random.default_rng(seed)
    limit = rng.integers(3, 40, size=3).astype(np.int32)
    parents = np.stack([rng.integers(0, (limit[a] + 1) // 2, size=n) for a in range(3)], axis=1).astype(np.int32)
    edge = (2 * parents + 1 >= limit).any(axis=1)
    inner, at_edge = K.at_upper_edge(parents, limit)
    assert np.array_equal(inner, np.flatnonzero(~edge)) and np.array_equal(at_edge, np.flatnonzero(edge))
    children = (2 * parents[edge][:, None, :] + CHILD_OFFSETS).reshape(-1, 3)
    outer = np.ascontiguousarray(children[(children < limit).all(axis=1)])
    total = 8 * inner.size + outer.shape[0]
    listed = K.children(parents, inner, outer, CHILD_OFFSETS, 0, total)
    # the children of the inner parents in CHILD_OFFSETS order, then the outer rows
    want = np.concatenate([(2 * parents[inner][:, None, :] + CHILD_OFFSETS).reshape(-1, 3), outer]).astype(np.int32)
    assert np.array_equal(listed, want)
    nodes = K.centre_nodes(parents, inner, outer, CHILD_OFFSETS, 0, total, size)
    assert nodes.dtype == np.int32 and np.array_equal(nodes, size * want + size // 2)
