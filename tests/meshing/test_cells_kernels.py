"""The compiled bookkeeping of `mesh_cells` against the numpy it replaces, and a mesh that does not
depend on the order its cells and rings come in."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from parts import benchmark_part

from spatial.cells.lattice import make_lattice
from spatial.meshing.arrays import REFINE_ACCEPT, ZERO_NUDGE, _nudge
from spatial.meshing.blocks import INTERIOR
from spatial.meshing.boundary import boundary_cells_2h
from spatial.meshing.cells import mesh_cells
from spatial.meshing.cells_kernels import (min_max, min_max_rows, order_by_key, take_entries, take_nudged, take_rows,
                                           ties)
from spatial.meshing.refine import _certified


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.sampled_from([1, 3, 16]), st.integers(1, 2000))
def test_order_by_key_is_the_stable_argsort(seed, div, n):
    rng = np.random.default_rng(seed)
    x = rng.integers(5, 90, size=n).astype(np.int32)
    rows = rng.integers(-3, 1000, size=(n, 3)).astype(np.int32)
    lo, hi = min_max(x)
    assert (lo, hi) == (x.min(), x.max())
    assert min_max_rows(rows) == (rows.min(), rows.max())
    first = int(lo) // div
    order, start = order_by_key(x, div, first, int(hi) // div - first + 1)
    want = np.argsort(x // div, kind="stable")
    assert np.array_equal(order, want)
    # where each key starts: the searchsorted of the sorted keys
    keys = np.arange(first, int(hi) // div + 2)
    assert np.array_equal(start, np.searchsorted((x // div)[want], keys))
    # a strided column sorts the same as a contiguous one
    wide = np.stack([x, x, x], axis=1)
    assert np.array_equal(order_by_key(wide[:, 1], div, first, int(hi) // div - first + 1)[0], want)
    a, b = int(start[1]), int(start[-1])
    out = np.empty((b - a, 3), np.int64)
    take_rows(rows, order, a, b, out)
    assert np.array_equal(out, rows[want[a:b]]) and out.dtype == np.int64
    signs = rng.integers(-1, 2, size=n).astype(np.int8)
    got = np.empty(b - a, np.int8)
    take_entries(signs, order, a, b, got)
    assert np.array_equal(got, signs[want[a:b]])


def test_take_nudged_is_the_nudge_in_single_precision():
    h = 0.01
    eps = ZERO_NUDGE * h
    v = np.array([0.0, -0.0, 1e-9, -1e-9, eps, -eps, eps * (1 - 1e-12), 0.3, -0.3, np.nan, 1.0 / 3.0, np.inf])
    order = np.arange(v.size)[::-1].copy()
    out = np.empty(v.size, np.float32)
    take_nudged(v, order, 0, v.size, eps, out)
    want = _nudge(v[order].copy(), h).astype(np.float32)
    assert np.array_equal(out.view(np.uint32), want.view(np.uint32))
    # 0.0 -> +eps, NaN -> +eps, infinity kept
    assert out[-1] == np.float32(eps) and out[2] == np.float32(eps) and out[0] == np.inf
    assert np.array_equal(ties(v, 1e-7 * h), np.flatnonzero(np.abs(v) <= 1e-7 * h))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.booleans(), st.booleans(), st.sampled_from([1.0, 1.5, np.inf]))
def test_vertex_stage_is_the_numpy_formulation(seed, refine, split, lip):
    import spatial.meshing.cells as cells_module

    rng = np.random.default_rng(seed)
    n = 500
    h = 0.05
    f0 = (-rng.random(n) * h).astype(np.float32)
    f1 = (rng.random(n) * h).astype(np.float32)
    # square-on crossings (certified), ends on the nudge (ties), vertices inside a cube
    f1[::7] = np.float32(h) + f0[::7]
    f0[::11] = -np.float32(ZERO_NUDGE * h)
    axis = rng.integers(0, 3, size=n).astype(np.uint8)
    axis[::13] = INTERIOR
    # the numpy of the vertex stage as `mesh_cells` had it
    F0, F1, A = f0.copy(), f1.copy(), axis.copy()
    inner = np.flatnonzero(A == INTERIOR)
    F1[inner] = -F0[inner]
    A[inner] = 0
    t = F0 / (F0.astype(np.float64) - F1)
    free = ~_certified(F0, F1, h, lip)
    free[inner] = False
    rows = np.flatnonzero(free).astype(np.int32)
    floor = np.float32(ZERO_NUDGE * h * (1 + 1e-3))
    tied = (np.abs(F0[rows]) <= floor) | (np.abs(F1[rows]) <= floor)
    certify = bool(np.isfinite(lip))
    least = np.float32(lip * h - REFINE_ACCEPT * h) if certify else np.float32(0.0)
    args = (INTERIOR, refine, certify, floor, least, split)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(cells_module, "EVAL_CHUNK", 77)   # several chunks on two threads, the last one short
        got_t, got_inner, got_tied, got_rest, finite = cells_module._vertex_stage(f0, f1, axis, args, 2)
    assert finite
    assert np.array_equal(got_t.view(np.uint64), t.view(np.uint64))
    assert np.array_equal(got_inner, inner)
    assert np.array_equal(f1, F1) and np.array_equal(axis, A)
    if not refine:
        assert got_tied.size == 0 and got_rest.size == 0
    elif split:
        assert np.array_equal(got_tied, rows[tied]) and np.array_equal(got_rest, rows[~tied])
        assert got_tied.size > 0
    else:
        assert got_tied.size == 0 and np.array_equal(got_rest, rows)
    assert got_rest.dtype == np.int32
    # a field's NaN is reported
    f0[3] = np.nan
    assert not cells_module._vertex_stage(f0, f1, axis, args, 1)[4]


def test_mesh_does_not_depend_on_the_order_of_its_cells():
    # the cells, rings and nodes shuffled: the slabs take the same shares, the mesh is the same
    lat = make_lattice(benchmark_part(), resolution=48)
    found = boundary_cells_2h(lat, False)
    kwargs = dict(cell_size=2, progress=False, features=False, evaluations=found["evaluations"])

    def run(found):
        m = mesh_cells(lat.solid, lat.origin, lat.voxel_size, found["cells"], centre_values=found["centres"],
                       uniform_cells=found["uniform"], uniform_parents=found["uniform_parents"],
                       node_values=found["nodes"], **kwargs)
        return np.asarray(m.points), np.asarray(m.faces).reshape(-1, 4)[:, 1:], m

    points, faces, m = run(found)
    rng = np.random.default_rng(7)
    perm = rng.permutation(found["cells"].shape[0])
    mixed = dict(found, cells=found["cells"][perm], centres=found["centres"][perm])
    for key in ("uniform", "uniform_parents", "nodes"):
        idx, val = found[key]
        p = rng.permutation(idx.shape[0])
        mixed[key] = (idx[p], val[p])
    points2, faces2, m2 = run(mixed)
    # the same vertices, bit for bit, and the same triangles with their winding (numbered in another order)
    assert faces.shape == faces2.shape and faces.shape[0] > 1000
    (p1, t1), (p2, t2) = _canonical(points, faces), _canonical(points2, faces2)
    assert np.array_equal(p1, p2) and np.array_equal(t1, t2)
    assert m.field_data["evaluations"][0] == m2.field_data["evaluations"][0]


def _canonical(points, faces):
    order = np.lexsort(points.T[::-1])
    rank = np.empty(order.size, np.int64)
    rank[order] = np.arange(order.size)
    f = rank[faces]
    first = np.argmin(f, axis=1)
    f = np.stack([f[np.arange(f.shape[0]), (first + k) % 3] for k in range(3)], axis=1)
    return points[order], f[np.lexsort(f.T[::-1])]
