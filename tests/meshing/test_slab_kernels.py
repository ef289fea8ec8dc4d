"""The compiled per-slab kernels against the whole-array numpy they replace, and slab arrays lent
from slab to slab leaving no trace in the mesh."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import box, cylinder, sphere
from spatial import mesh
from spatial.meshing.arrays import _repeat2
from spatial.meshing.kernels import block_input, count_needed, needed_nodes, paint_parents


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.sampled_from([2, 4, 8]), st.integers(1, 3))
def test_needed_nodes_is_the_numpy_formulation(seed, B, nb):
    rng = np.random.default_rng(seed)
    n1 = B + 1
    code = rng.integers(0, 8, size=nb * n1 ** 3).astype(np.uint8)
    flat0 = np.flatnonzero(code & 1)
    rest = flat0 % n1 ** 3
    i, j, k = np.unravel_index(rest, (n1, n1, n1))
    s0 = ((code[flat0] >> 1) & 1).astype(np.int8) - ((code[flat0] >> 2) & 1).astype(np.int8)
    n = count_needed(code)
    assert n == flat0.size
    flat = np.empty(n, np.int32)
    s_n = np.empty(n, np.int8)
    maybe = np.empty(n, np.bool_)
    upper = np.empty(n, np.bool_)
    needed_nodes(code, B, flat, s_n, maybe, upper)
    assert np.array_equal(flat, flat0)
    assert np.array_equal(s_n, s0)
    assert np.array_equal(maybe, (j % B == 0) | (k % B == 0) | (i == 0))
    assert np.array_equal(upper, i == B)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.booleans())
def test_block_input_is_the_sliced_box_and_its_voxels(seed, with_values):
    rng = np.random.default_rng(seed)
    P, c = 4, 2
    B = P * c
    nb = 2
    values = rng.standard_normal((nb, B + 1, B + 1, B + 1)).astype(np.float32)
    cells = rng.random((nb, P, P, P)) < 0.3
    b = int(rng.integers(nb))
    lo = rng.integers(0, P, size=3)
    hi = np.array([rng.integers(l + 1, P + 1) for l in lo])
    xs, ys, zs = (lo * c).tolist()
    nx, ny, nz = ((hi - lo) * c).tolist()
    voxels = cells
    for ax in (1, 2, 3):
        voxels = _repeat2(voxels, ax)
    want_vol = values[b, xs:xs + nx + 1, ys:ys + ny + 1, zs:zs + nz + 1]
    want_mask = np.zeros(want_vol.shape, bool)
    want_mask[1:, 1:, 1:] = voxels[b, xs:xs + nx, ys:ys + ny, zs:zs + nz]
    # scratch full of garbage: every entry the box uses must be written
    vol = np.full((B + 1) ** 3, np.nan, np.float32)
    mask = np.ones((B + 1) ** 3, np.bool_)
    block_input(values, cells, b, xs, ys, zs, nx, ny, nz, c, vol, mask, with_values)
    size = want_vol.size
    assert np.array_equal(mask[:size].reshape(want_vol.shape), want_mask)
    if with_values:
        assert np.array_equal(vol[:size].reshape(want_vol.shape), want_vol)
    else:
        assert np.isnan(vol).all()


@pytest.mark.parametrize("overlap", [False, True])
def test_lent_slab_arrays_leave_no_trace(monkeypatch, overlap):
    """A mesh made after a larger one (whose slabs filled the lent arrays with other samples) and
    after a smaller one is the mesh a fresh process makes; with one slab thread or two."""
    import spatial.meshing.cells as cells_mod
    from spatial.meshing.slab import run_slabs

    monkeypatch.setattr(cells_mod, "run_slabs", lambda tasks, parts, overlap=False, _o=overlap: run_slabs(
        tasks, parts, overlap=_o))
    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0))
    first = mesh(part, resolution=36, block=8, progress=False)
    mesh(sphere(0.7), resolution=60, block=8, progress=False)
    mesh(box(1.0), resolution=12, block=8, progress=False)
    again = mesh(part, resolution=36, block=8, progress=False)
    assert first.n_cells > 0
    assert np.array_equal(np.asarray(first.points), np.asarray(again.points))
    assert np.array_equal(np.asarray(first.faces), np.asarray(again.faces))


def test_lent_arrays_are_written_before_read(monkeypatch):
    """Every slab array lent by `_Scratch` handed out full of garbage: the same mesh (nothing of an
    earlier slab can show through)."""
    from spatial.meshing import slab as slab_mod

    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(0, 0, 1))
    clean = mesh(part, resolution=40, block=8, progress=False)
    take = slab_mod._Scratch.take

    def dirty(self, name, shape, dtype):
        arr = take(self, name, shape, dtype)
        arr.view(np.uint8)[...] = 0xFF  # NaN floats, all code bits, True masks
        return arr

    monkeypatch.setattr(slab_mod._Scratch, "take", dirty)
    soiled = mesh(part, resolution=40, block=8, progress=False)
    assert np.array_equal(np.asarray(clean.points), np.asarray(soiled.points))
    assert np.array_equal(np.asarray(clean.faces), np.asarray(soiled.faces))


def test_lent_or_fresh_slab_arrays_give_the_same_mesh(monkeypatch):
    """Scratch arrays lent across slabs of very different sizes, and fresh arrays for every slab: one
    mesh, bit for bit, and one evaluation count."""
    from spatial.meshing import slab as slab_mod

    part = sphere(1) - cylinder(0.5, 4, axis=(0, 0, 1)) - cylinder(0.3, 4, axis=(1, 0, 0))
    sizes = []
    take = slab_mod._Scratch.take

    def spy(self, name, shape, dtype):
        if name == "values":
            sizes.append(int(np.prod(shape)))
        return take(self, name, shape, dtype)

    monkeypatch.setattr(slab_mod._Scratch, "take", spy)
    lent = mesh(part, resolution=48, block=8, features=False, progress=False)
    assert len(sizes) >= 12 and max(sizes) >= 3 * min(sizes)   # slabs of very different sizes
    monkeypatch.setattr(slab_mod, "_take", lambda scratch, name, shape, dtype: np.empty(shape, dtype))
    fresh = mesh(part, resolution=48, block=8, features=False, progress=False)
    assert np.array_equal(np.asarray(lent.points), np.asarray(fresh.points))
    assert np.array_equal(np.asarray(lent.faces), np.asarray(fresh.faces))
    assert int(lent.field_data["evaluations"][0]) == int(fresh.field_data["evaluations"][0])


def test_mesh_samples_slabs_on_two_threads_and_mesh_cells_checks_the_count(monkeypatch):
    import spatial.meshing.cells as cells_mod
    from spatial.meshing.cells import mesh_cells
    from spatial.meshing.slab import run_slabs

    seen = []

    def spy(tasks, parts, overlap=False):
        seen.append(overlap)
        return run_slabs(tasks, parts, overlap=overlap)

    monkeypatch.setattr(cells_mod, "run_slabs", spy)
    mesh(sphere(1.0), resolution=40, block=8, progress=False)    # 6 slabs: two threads
    mesh(sphere(1.0), resolution=12, block=8, progress=False)    # 2 slabs: one
    assert seen == [True, False]
    with pytest.raises(ValueError, match="slab_threads"):
        mesh_cells(sphere(1.0), (0.0, 0.0, 0.0), 0.1, [[0, 0, 0]], slab_threads=3)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(1, 6), st.integers(1, 6), st.integers(1, 6))
def test_paint_parents_is_the_coarse_numpy_painting(seed, s0, s1, s2):
    """The uniform parents' signs over their children inside a slab's state array, against the
    painting at the parents' scale, repeated twice along each axis and cut out."""
    rng = np.random.default_rng(seed)
    origin = rng.integers(-3, 4, size=3)
    lo_p, hi_p = (origin - 2) // 2, (origin + np.array([s0, s1, s2]) + 2) // 2
    cand = np.stack(np.meshgrid(*[np.arange(a, b) for a, b in zip(lo_p, hi_p)], indexing="ij"), -1).reshape(-1, 3)
    idx = cand[rng.random(cand.shape[0]) < 0.4].astype(np.int32)
    sgn = rng.choice(np.array([-1, 1], np.int8), size=idx.shape[0])
    state = rng.integers(0, 2, size=(s0, s1, s2)).astype(np.uint8)  # NEEDED bits already there
    expect = state.copy()
    lo = origin // 2
    hi = -(-(origin + np.array([s0, s1, s2])) // 2)
    sel = ((idx >= lo) & (idx < hi)).all(axis=1)
    coarse = np.zeros(tuple((hi - lo).tolist()), np.uint8)
    coarse[tuple((idx[sel] - lo).T)] = np.where(sgn[sel] < 0, 4, 2)
    for ax in range(3):
        coarse = np.repeat(coarse, 2, axis=ax)
    shift = origin - 2 * lo
    expect |= coarse[shift[0]:shift[0] + s0, shift[1]:shift[1] + s1, shift[2]:shift[2] + s2]
    paint_parents(state, idx, sgn, int(origin[0]), int(origin[1]), int(origin[2]), np.uint8(4), np.uint8(2))
    assert np.array_equal(state, expect)


def _random_parts(rng, n_parts):
    """Parts as `merge_blocks` takes them: shared vertices keyed by ids some parts have in common."""
    parts = []
    for _ in range(n_parts):
        nv = int(rng.integers(3, 40))
        shared = rng.random(nv) < 0.4
        edge = rng.integers(0, 30, size=int(shared.sum())).astype(np.int64)
        # a vertex's data is a function of its id when shared (the same in every part holding it)
        node = rng.integers(0, 100, size=(nv, 3)).astype(np.int32)
        node[shared] = np.stack([edge, edge + 1, edge + 2], axis=1).astype(np.int32)
        f0 = rng.standard_normal(nv).astype(np.float32)
        f0[shared] = edge.astype(np.float32)
        faces = rng.integers(0, nv, size=(int(rng.integers(1, 30)), 3)).astype(np.int32)
        parts.append((edge, shared, (node, f0), faces))
    return parts


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_merge_blocks_on_two_threads_is_the_one_thread_merge(seed):
    from spatial.meshing.blocks import merge_blocks

    one = merge_blocks(_random_parts(np.random.default_rng(seed), 9), threads=1)
    two = merge_blocks(_random_parts(np.random.default_rng(seed), 9), threads=2)
    assert np.array_equal(one[1], two[1])
    for a, b in zip(one[0], two[0]):
        assert np.array_equal(a, b)
    # the shared ids are merged: 30 possible ids, so fewer vertices than the parts hold
    parts = _random_parts(np.random.default_rng(seed), 9)
    held = sum(p[1].shape[0] for p in parts)
    ids = np.unique(np.concatenate([p[0] for p in parts]))
    private = sum(int((~p[1]).sum()) for p in parts)
    assert one[0][0].shape[0] == private + ids.size < held
    # the shared vertices follow the private ones, in the order of their ids
    assert np.array_equal(one[0][1][private:], ids.astype(np.float32))


def test_merge_blocks_refuses_a_bad_thread_count():
    from spatial.meshing.blocks import merge_blocks

    with pytest.raises(ValueError, match="threads"):
        merge_blocks([], threads=0)


@pytest.mark.parametrize("seed", [0, 1])
def test_put_sampled_is_the_sorted_search_and_ignores_stale_rows(seed):
    from spatial.meshing.kernels import index_positions, put_sampled

    rng = np.random.default_rng(seed)
    n1, nb = 5, 3
    size = nb * n1 ** 3
    flat = np.sort(rng.choice(size, size=60, replace=False)).astype(np.int32)
    # stale rows everywhere, some of them in range: only a needed node's own row may be taken
    where = rng.integers(-5, 70, size=size).astype(np.int32)
    index_positions(flat, where)
    b_, x_, y_, z_ = (rng.integers(0, m, size=200) for m in (nb, n1, n1, n1))
    v = rng.standard_normal(200).astype(np.float32)
    got = np.full(flat.shape[0], np.nan, np.float32)
    put_sampled(flat, where, b_, x_, y_, z_, v, n1, got)
    want = np.full(flat.shape[0], np.nan, np.float32)
    at = ((b_ * n1 + x_) * n1 + y_) * n1 + z_
    pos = np.minimum(np.searchsorted(flat, at), flat.shape[0] - 1)
    hit = flat[pos] == at
    for p, val in zip(pos[hit], v[hit]):   # in the samples' order: the last of a repeated node wins
        want[p] = val
    assert np.array_equal(got, want, equal_nan=True)
    assert 0 < np.count_nonzero(~np.isnan(got)) < flat.shape[0]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.sampled_from([1, 2, 5, 100, 20000]), st.sampled_from([3, 2 ** 20, 2 ** 40]))
def test_stable_argsort_is_numpys_stable_sort(seed, n, top):
    from spatial.meshing.slab_kernels import _unique_first, stable_argsort, unique_inverse

    keys = np.random.default_rng(seed).integers(0, top, n).astype(np.int64)
    assert np.array_equal(stable_argsort(keys), np.argsort(keys, kind="stable"))
    uniq, first, back = _unique_first(keys)
    want = np.unique(keys, return_index=True, return_inverse=True)
    for got, ref in zip((uniq, first, back), want):
        assert np.array_equal(got, ref)
    for got, ref in zip(unique_inverse(keys), np.unique(keys, return_inverse=True)):
        assert np.array_equal(got, ref)


def test_has_tie_is_the_tie_finder_on_tie_rich_blocks():
    """`slab_kernels.has_tie` is True exactly where `saddles`' finder marks something (rows longer than 64
    nodes too), and `blocks_with_ties` asks it of each block's box."""
    from spatial.meshing.slab_kernels import blocks_with_ties, has_tie
    from spatial.meshing.saddles import _kernel

    rng = np.random.default_rng(3)
    with_tie = 0
    for trial in range(600):
        shape = tuple(int(s) for s in rng.integers(2, 8, 3))
        if trial % 40 == 0:
            shape = (3, 3, int(rng.integers(60, 70)))
        v = rng.choice([-1.0, 1.0, -0.5, 0.5, -0.25, 2.0] if trial % 2 else [-1.0, 1.0], size=shape)
        v = v.astype(np.float32)
        if trial % 3 == 0:
            v[rng.random(shape) < 0.7] = 1.0   # few cubes of both signs
        ref = _kernel()(v, np.zeros(shape, bool)) > 0
        assert has_tie(v) == ref
        with_tie += ref
    assert 100 < with_tie < 590   # both answers were tested
    # a slab of three 4^3 blocks: a tie in block 1 only, inside its box
    values = np.ones((3, 5, 5, 5), np.float32)
    values[:, :, :, :2] = -1.0
    values[1, 2, 2, 2] = values[1, 3, 3, 2] = -0.5
    values[1, 3, 2, 2] = values[1, 2, 3, 2] = 0.5
    lows = np.zeros((3, 3), np.int64)
    highs = np.full((3, 3), 2, np.int64)
    assert blocks_with_ties(values, lows, highs, 2).tolist() == [False, True, False]
    highs[1] = (1, 2, 2)   # the box of block 1 now ends at node 2 along x: the tie's face is left out
    assert blocks_with_ties(values, lows, highs, 2).tolist() == [False, False, False]


def test_nudged_float32_is_the_nudge_or_declines_at_a_tie():
    from spatial.meshing.arrays import ZERO_NUDGE, ZERO_TIE, _nudge
    from spatial.meshing.slab_kernels import nudged_float32

    h = 0.01
    rng = np.random.default_rng(5)
    vals = rng.normal(0.0, 3 * ZERO_NUDGE * h, 5000)
    vals[::97] = np.nan
    vals[1] = -0.5 * ZERO_NUDGE * h
    vals = np.where(np.abs(vals) <= ZERO_TIE * h, 1.0, vals)   # no tie yet
    out, clean = nudged_float32(vals, ZERO_NUDGE * h, ZERO_TIE * h)
    assert clean
    assert out.dtype == np.float32 and np.array_equal(out, _nudge(vals.copy(), h).astype(np.float32))
    assert out[1] == np.float32(-ZERO_NUDGE * h) and out[0] == np.float32(ZERO_NUDGE * h)   # NaN pushed outside
    vals[7] = 0.0   # a tie: left to `_settle_ties`
    out, clean = nudged_float32(vals, ZERO_NUDGE * h, ZERO_TIE * h)
    assert not clean and out.size == 0
