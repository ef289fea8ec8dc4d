"""The feature pass's compiled stages against numpy references, and how the mesher hands it its arrays."""

import numpy as np
import pytest
from parts import benchmark_part

from spatial.meshing import mesh
from spatial.meshing.feature_collapse import finish
from spatial.meshing.feature_cells import _merge_unique, _sorted_unique, cells, group, nodes
from spatial.meshing.feature_threads import on_threads, spans
from spatial.meshing.features import COS_CANDIDATE, sharp_polydata, sharp_polydata_lent, sharpen


def _grid_mesh(n=6, seed=0):
    """A plain marching-cubes mesh of the benchmark part, as the mesher hands it to the pass."""
    from spatial.meshing import features

    got = {}
    real = features._sharpen

    def spy(solid, lent, origin, h, **kw):
        got.update(points=lent[0].copy(), faces=lent[1].copy(), origin=np.array(origin), h=float(h))
        return real(solid, lent, origin, h, **kw)

    features._sharpen = spy
    try:
        mesh(benchmark_part(), resolution=8 * n, progress=False)
    finally:
        features._sharpen = real
    return got


@pytest.fixture(scope="module")
def captured():
    return _grid_mesh()


def test_sorted_unique_is_numpy_unique():
    rng = np.random.default_rng(3)
    for size in (0, 1, 7, 1000):
        a = rng.integers(-50, 50, size)
        assert np.array_equal(_sorted_unique(a.copy()), np.unique(a))


def _runs(keys):
    start = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    return np.r_[start, keys.shape[0]].astype(np.int64), keys[start].astype(np.int64)


def test_merge_unique_is_numpy_unique():
    rng = np.random.default_rng(5)
    for na, nb in ((0, 0), (0, 4), (5, 0), (30, 40)):
        a, b = np.unique(rng.integers(0, 50, na)), np.unique(rng.integers(0, 50, nb))
        assert np.array_equal(_merge_unique(a, b), np.union1d(a, b))


@pytest.mark.parametrize("cut", [[], [0], [3], [3, 3], [1, 20, 77], [149]])
def test_group_cells_by_runs_is_the_stable_sort(cut):
    """Cells whose triangles come in several runs (not side by side) are grouped as a stable sort does,
    whatever the runs' and vertices' chunks (empty ones too)."""
    rng = np.random.default_rng(7)
    n, m = 60, 400
    faces = rng.integers(0, n, (m, 3)).astype(np.int32)
    keys = np.repeat(rng.integers(0, 40, 150), rng.integers(1, 5, 150))[:m]
    faces = faces[:keys.shape[0]]
    start, rkey = _runs(keys)
    assert np.unique(keys).shape[0] < rkey.shape[0]        # some cell is split into several runs
    cells_ = np.unique(rkey[rng.random(rkey.shape[0]) < 0.3])
    edges = [0] + [min(c, rkey.shape[0]) for c in cut] + [rkey.shape[0]]
    rspans = list(zip(edges[:-1], edges[1:]))
    index = np.full(n, -1, np.int32)
    tri, tcell, pvert, starts, verts, pinv = group(start, rkey.copy(), rspans, cells_, faces, index,
                                                   spans(n, len(rspans)))
    pcell = np.repeat(np.arange(cells_.shape[0]), np.diff(starts))
    inside = np.isin(keys, cells_)
    order = np.argsort(keys[inside], kind="stable")
    want_tri = np.flatnonzero(inside)[order]
    assert np.array_equal(tri, want_tri)
    assert np.array_equal(tcell, np.searchsorted(cells_, keys[want_tri]))
    pairs = np.unique(np.stack([np.repeat(tcell, 3), faces[tri].reshape(-1)], axis=1), axis=0)
    assert np.array_equal(pcell, pairs[:, 0]) and np.array_equal(pvert, pairs[:, 1])
    assert np.array_equal(starts, np.searchsorted(pcell, np.arange(cells_.shape[0] + 1)))
    assert np.array_equal(verts, np.unique(pvert)) and np.array_equal(verts[pinv], pvert)
    want_index = np.full(n, -1)
    want_index[verts] = np.arange(verts.shape[0])
    assert np.array_equal(index, want_index)


def _cells_of(captured, chunks, faces=None):
    pts, origin, h = captured["points"], captured["origin"], captured["h"]
    faces = captured["faces"] if faces is None else faces
    n, m = pts.shape[0], faces.shape[0]
    at, axis = np.empty(n, np.bool_), np.empty(n, np.int8)
    border = nodes(pts, faces, origin, h, 0.01, at, axis, chunks=chunks)
    vn, index = np.full((n, 3), np.nan), np.empty(n, np.int32)
    work = np.empty(m + 1, np.int64), np.empty(m, np.int64), np.empty(m, np.bool_)
    out = cells(pts, faces, origin, h, COS_CANDIDATE, at, vn, *work, index, chunks=chunks)
    return (at, axis, border, vn, index) + out


def test_candidate_runs_follow_the_triangles_cells(captured):
    """The candidate cells are those of the runs of one cell's triangles that hold a triangle departing
    from a vertex normal (numpy's sums of the triangles' normals, in triangle order), keyed as the
    cells' lexicographic order."""
    pts, faces, origin, h = captured["points"], captured["faces"], captured["origin"], captured["h"]
    n = pts.shape[0]
    at, _, _, vn, _, cand, lo, s = _cells_of(captured, 1)[:8]
    cell = np.floor(((pts[faces[:, 0]] + pts[faces[:, 1]] + pts[faces[:, 2]]) * (1.0 / 3.0) - origin) / h)
    cell = cell.astype(np.int64) - lo
    keys = (cell[:, 0] * s + cell[:, 1]) * s + cell[:, 2]
    assert lo.tolist() == (np.floor((pts.min(axis=0) - origin) / h).astype(np.int64) - 1).tolist()
    a, b, c = (pts[faces[:, j]] for j in range(3))
    tn = np.cross(b - a, c - a)
    want = np.zeros((n, 3))
    for j in range(3):
        np.add.at(want, faces[:, j], tn)      # (not the same order of sums: equal to rounding)
    want /= np.linalg.norm(want, axis=1)[:, None]
    assert np.allclose(vn, want, atol=1e-12)
    cos = (tn[:, None, :] * vn[faces]).sum(axis=2).min(axis=1) / np.linalg.norm(tn, axis=1)
    n_at = at[faces].sum(axis=1)
    marked = (cos < COS_CANDIDATE) | ((n_at > 0) & (n_at < 3))
    want_cand = np.unique(keys[marked])
    # (a cosine within rounding of the limit could go either way: none here)
    assert np.abs(cos - COS_CANDIDATE).min() > 1e-9
    assert np.array_equal(cand, want_cand)
    # the box's faces and the drills' rims give candidate cells, far fewer than all
    assert 0 < cand.shape[0] < np.unique(keys).shape[0] // 2


@pytest.mark.parametrize("chunks", [2, 3, 7])
def test_chunks_give_the_one_chunk_walk(captured, chunks):
    """Every array of the node and candidate walks is the one-chunk walk's, bit for bit, however many
    chunks (the vertex normals summed in triangle order across chunk borders)."""
    one = _cells_of(captured, 1)
    many = _cells_of(captured, chunks)
    assert len(one) == len(many)
    for a, b in zip(one, many):
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes()


def test_chunks_of_tiny_meshes(captured):
    """More chunks than triangles, one triangle, none: the same as one chunk (no triangle: no cell)."""
    for m in (0, 1, 2, 5):
        faces = captured["faces"][:m]
        one = _cells_of(captured, 1, faces)
        for chunks in (2, 8):
            many = _cells_of(captured, chunks, faces)
            for a, b in zip(one, many):
                assert np.asarray(a).tobytes() == np.asarray(b).tobytes()
    assert _cells_of(captured, 3, captured["faces"][:0])[5].shape == (0,)


def test_spans_and_threads():
    assert spans(7, 3) == [(0, 2), (2, 4), (4, 7)]
    assert spans(1, 2) == [(0, 0), (0, 1)] and spans(0, 2) == [(0, 0), (0, 0)]
    with pytest.raises(ValueError, match="chunks"):
        spans(3, 0)
    assert on_threads([lambda i=i: i * i for i in range(5)]) == [0, 1, 4, 9, 16]

    def boom():
        raise KeyError("on the second thread")

    with pytest.raises(KeyError, match="second thread"):
        on_threads([lambda: 1, boom])


def test_finish_into_int32_and_in_place_is_the_same(captured):
    sharp = sharpen(benchmark_part(), captured["points"], captured["faces"], captured["origin"], captured["h"])
    assert sharp["faces"].dtype == np.int32 and sharp["feature_cells"] > 0
    rng = np.random.default_rng(1)
    pts = rng.random((40, 3))
    faces = rng.integers(0, 36, (30, 3))
    drop = rng.random(30) < 0.3
    new = rng.integers(0, 40, (6, 3))
    ref = finish(pts, faces, drop, new, 36)
    work = pts.copy()
    got = finish(work, faces, drop, new, 36, dtype=np.int32, overwrite_points=True)
    assert got[0].dtype == np.int32 and np.array_equal(got[0], ref[0])
    assert np.array_equal(got[1], ref[1]) and got[2] == ref[2]
    assert np.array_equal(got[3], ref[3]) and np.shares_memory(got[3], work)
    # the triangles written over the input's rows where they fit, else into a new array
    mine = faces.astype(np.int32)
    fit = finish(pts, mine, drop, new, 36, dtype=np.int32, overwrite_faces=True)
    assert np.array_equal(fit[0], ref[0]) and np.shares_memory(fit[0], mine)
    # (no feature vertex, nothing dropped: six rows more than the input has)
    grow = finish(pts, faces, np.zeros(30, np.bool_), new, 40, dtype=np.int32)
    mine = faces.astype(np.int32)
    got = finish(pts, mine, np.zeros(30, np.bool_), new, 40, dtype=np.int32, overwrite_faces=True)
    assert got[0].shape == (36, 3) and np.array_equal(got[0], grow[0]) and not np.shares_memory(got[0], mine)
    wide = faces.copy()
    kept = finish(pts, wide, drop, new, 36, dtype=np.int32, overwrite_faces=True)
    assert np.array_equal(kept[0], ref[0]) and np.array_equal(wide, faces)     # int64 rows are not int32's
    # work arrays lent (of any content), or of the wrong type or size and then left alone: the same
    lent = (np.full(40, 7, np.int32), np.full(41, -3, np.int32))
    assert all(np.array_equal(a, b) for a, b in zip(finish(pts, faces, drop, new, 36, work=lent), ref))
    assert not (lent[0] == 7).all() and not (lent[1] == -3).all()
    wrong = (np.full(40, 7, np.int64), np.full(41, -3, np.int32))
    assert all(np.array_equal(a, b) for a, b in zip(finish(pts, faces, drop, new, 36, work=wrong), ref))
    assert (wrong[0] == 7).all() and (wrong[1] == -3).all()
    with pytest.raises(ValueError, match="overwrite_points"):
        finish(pts.astype(np.float32), faces, drop, new, 36, overwrite_points=True)
    with pytest.raises(ValueError, match="dtype"):
        finish(pts, faces, drop, new, 36, dtype=np.int16)


def test_sharpen_leaves_its_inputs_and_lent_arrays_are_taken(captured):
    pts, faces = captured["points"].copy(), captured["faces"].copy()
    sharpen(benchmark_part(), pts, faces, captured["origin"], captured["h"])
    assert np.array_equal(pts, captured["points"]) and np.array_equal(faces, captured["faces"])
    ref = sharp_polydata(benchmark_part(), pts, faces, captured["origin"], captured["h"])
    assert np.array_equal(pts, captured["points"]) and np.array_equal(faces, captured["faces"])
    lent = [pts, faces]
    out = sharp_polydata_lent(benchmark_part(), lent, captured["origin"], captured["h"])
    assert lent == [] and out.n_cells > 0
    # the lent triangles' rows hold the result's (no second array of every triangle)
    assert np.shares_memory(np.asarray(out.regular_faces), faces) or out.n_cells > faces.shape[0]
    assert np.array_equal(out.regular_faces, ref.regular_faces) and np.array_equal(out.points, ref.points)
    m = mesh(benchmark_part(), resolution=48, progress=False)
    assert m.regular_faces.dtype == np.int32
    assert int((m.point_data["feature_rank"] == 3).sum()) > 0


def test_cell_faces_open_the_cells_not_on_one_smooth_facet():
    """Cells whose vertices all lie on one smooth facet are closed; only the open cells' vertices are asked for."""
    from spatial.meshing.feature_kernels import _cell_faces, _cell_labels

    rng = np.random.default_rng(11)
    n_cells, n_verts = 200, 300
    sizes = rng.integers(3, 8, n_cells)
    starts = np.r_[0, np.cumsum(sizes)].astype(np.int64)
    pinv = rng.integers(0, n_verts, starts[-1]).astype(np.int64)
    decider = np.where(rng.random(n_verts) < 0.8, 0, rng.integers(1, 4, n_verts)).astype(np.int64)
    smooth = np.array([True, False, True, True])
    need = np.zeros(n_verts, np.bool_)
    labels, n_faces, open_cells = _cell_faces(pinv, decider, starts, smooth, need)
    want_labels, want_n = _cell_labels(pinv, decider, starts)
    assert np.array_equal(labels, want_labels) and np.array_equal(n_faces, want_n)
    want_open = ~((want_n == 1) & smooth[want_labels[:, 0]])
    assert np.array_equal(open_cells, want_open) and 0 < want_open.sum() < n_cells
    cell = np.repeat(np.arange(n_cells), sizes)
    assert np.array_equal(need, np.isin(np.arange(n_verts), pinv[want_open[cell]]))



def test_fans_points_in_the_normals_rows_or_appended_are_the_same(captured, monkeypatch):
    """The fans' points go in the rows after the vertex normals' when they fit, else are appended: the same."""
    from spatial.meshing import features

    pts, faces, origin, h = captured["points"], captured["faces"], captured["origin"], captured["h"]
    roomy = features._sharpen(benchmark_part(), [pts.copy(), faces.copy()], origin, h, overwrite=True)
    monkeypatch.setattr(features, "ROOM", 10 ** 9)          # 256 rows beyond the points: too few
    tight = features._sharpen(benchmark_part(), [pts.copy(), faces.copy()], origin, h, overwrite=True)
    assert tight["feature_cells"] == roomy["feature_cells"] > 256
    for key in ("points", "faces", "feature_rank", "feature_facets"):
        assert np.array_equal(tight[key], roomy[key])


def _fans_and_flips_numpy(pts, exact, borders, feature, n, n_cells, x):
    """The fans and flips as numpy formulates them (the reference of `features._fans_and_flips`)."""
    from spatial.meshing.features import COS_SHARP, _facing_badly

    b0, b1, bc = borders
    keep = feature[bc]
    b0, b1, bc = b0[keep], b1[keep], bc[keep]
    fan_cells = np.flatnonzero(feature)
    vid = np.full(n_cells, -1, np.int64)
    vid[fan_cells] = n + np.arange(fan_cells.shape[0])
    fan = np.stack([b0, b1, vid[bc]], axis=1)
    owner = np.stack([bc, np.full(bc.shape[0], -1, np.int64)], axis=1)
    ekey = np.minimum(b0, b1) * np.int64(n) + np.maximum(b0, b1)
    order = np.argsort(ekey, kind="stable")
    ks = ekey[order]
    twin = np.flatnonzero(ks[1:] == ks[:-1])
    i, j = order[twin], order[twin + 1]
    normal, index = exact
    differ = np.einsum("ij,ij->i", normal[index[b0[i]]], normal[index[b1[i]]]) < COS_SHARP
    i, j = i[differ], j[differ]
    fk = np.minimum(fan[i, 2], fan[j, 2]) * np.int64(n + n_cells) + np.maximum(fan[i, 2], fan[j, 2])
    uk, cnt = np.unique(fk, return_counts=True)
    single = cnt[np.searchsorted(uk, fk)] == 1
    i, j = i[single], j[single]
    newp = np.concatenate([pts, x[fan_cells]])
    a_, b_, f1, f2 = fan[i, 0], fan[i, 1], fan[i, 2], fan[j, 2]
    t1, t2 = np.stack([a_, f2, f1], axis=1), np.stack([f2, b_, f1], axis=1)
    good = ~(_facing_badly(newp, t1, exact, n) | _facing_badly(newp, t2, exact, n))
    i, j, t1, t2 = i[good], j[good], t1[good], t2[good]
    fan[i] = t1
    fan[j] = t2
    both = np.stack([owner[i, 0], owner[j, 0]], axis=1)
    owner[i] = both
    owner[j] = both
    return fan, owner, fan_cells, newp, _facing_badly(newp, fan, exact, n), int(good.sum())


@pytest.mark.parametrize("part", ["benchmark", "lattice"])
def test_compiled_fans_and_flips_are_numpys(part, monkeypatch):
    """`_fans_and_flips` (two compiled calls around numpy's stable sort) against the numpy formulation,
    on every round of the pass over the benchmark part and a lattice of capsules (many flips)."""
    from parts import capsule_lattice

    from spatial.meshing import features

    solid = benchmark_part() if part == "benchmark" else capsule_lattice(2)[0]
    calls = []
    real = features._fans_and_flips

    def spy(pts, exact, borders, feature, n, n_cells, x, room=None):
        want = _fans_and_flips_numpy(pts, exact, borders, feature, n, n_cells, x)
        got = real(pts, exact, borders, feature, n, n_cells, x, room)
        # (compared at once: the points are in the pass's own rows, which later stages overwrite)
        calls.append(([np.array_equal(a, b) for a, b in zip(got, want[:5])], want[5]))
        return got

    monkeypatch.setattr(features, "_fans_and_flips", spy)
    mesh(solid, resolution=64, progress=False)
    assert calls
    for same, flips in calls:
        assert all(same) and flips > 20                     # flips made in every round
