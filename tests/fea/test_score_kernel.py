"""The compiled element scores of the sliver smoothing agree with the numpy measures they replace."""

import numpy as np
from hypothesis import given, settings, strategies as st

from spatial.fea.quality import dihedral_angles, gamma, radius_edge_ratio, tet_volumes
from spatial.fea.score_kernel import element_scores, moved_scores
from spatial.fea.slivers import boundary_faces, score


def _numpy_score(points, tets, min_d, max_d, radius_edge, min_gamma):
    sc = score(dihedral_angles(points, tets), min_d, max_d)
    if radius_edge is not None:
        sc = np.minimum(sc, min_d * radius_edge / np.maximum(radius_edge_ratio(points, tets), 1e-300))
    if min_gamma:
        sc = np.minimum(sc, min_d * gamma(points, tets) / min_gamma)
    return sc


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), radius_edge=st.sampled_from([None, 2.0, 3.0]),
       min_gamma=st.sampled_from([0.0, 0.25]))
def test_kernel_scores_equal_the_numpy_measures(seed, radius_edge, min_gamma):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(60, 3))
    tets = np.array([rng.choice(60, 4, replace=False) for _ in range(200)])
    ref = _numpy_score(pts, tets, 10.0, 165.0, radius_edge, min_gamma)
    np.testing.assert_allclose(element_scores(pts, tets, 10.0, 165.0, radius_edge, min_gamma), ref, atol=1e-9)
    # a vertex moved to trial positions: the score of the moved element, -inf where it inverts
    trials = rng.normal(size=(3, len(tets), 3))
    got = moved_scores(pts, tets, tets[:, 1], np.arange(len(tets)), trials, 10.0, 165.0, radius_edge, min_gamma)
    for j in range(3):
        moved = np.repeat(pts[None], len(tets), axis=0)
        moved[np.arange(len(tets)), tets[:, 1]] = trials[j]
        x = moved[np.arange(len(tets))[:, None], tets].reshape(-1, 3)
        local = np.arange(4 * len(tets)).reshape(-1, 4)
        want = np.where(tet_volumes(x, local) > 0, _numpy_score(x, local, 10.0, 165.0, radius_edge, min_gamma), -np.inf)
        np.testing.assert_allclose(got[j], want, atol=1e-9)


def test_boundary_faces_of_two_tets_sharing_a_face():
    tets = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
    faces, elem, side = boundary_faces(tets)
    assert len(faces) == 6
    assert sorted(map(tuple, np.sort(faces, axis=1))) == sorted(
        [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 4), (1, 3, 4), (2, 3, 4)])
    assert np.bincount(elem).tolist() == [3, 3]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_corner_measures_equal_the_numpy_measures(seed):
    from spatial.fea.quality import scaled_jacobian
    from spatial.fea.score_kernel import corner_measures

    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(60, 3))
    tets = np.array([rng.choice(60, 4, replace=False) for _ in range(200)])
    dmin, dmax, re, sj, vol = corner_measures(pts, tets)
    d = dihedral_angles(pts, tets)
    np.testing.assert_allclose(dmin, d.min(axis=1), atol=1e-9)
    np.testing.assert_allclose(dmax, d.max(axis=1), atol=1e-9)
    np.testing.assert_allclose(re, radius_edge_ratio(pts, tets), rtol=1e-9)
    np.testing.assert_allclose(sj, scaled_jacobian(pts, tets), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(vol, tet_volumes(pts, tets), rtol=1e-12, atol=1e-15)
    assert ((sj > 0) == (vol > 0)).all()


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), radius_edge=st.sampled_from([None, 3.0]))
def test_best_trials_pick_what_the_full_table_picks(seed, radius_edge):
    # The pruned search returns the trial the whole (trial, element) table gives: the first whose
    # worst element beats every earlier one by more than 1e-9.
    from spatial.fea.score_kernel import best_trials

    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(40, 3))
    verts = rng.choice(40, 12, replace=False)
    counts = rng.integers(1, 7, size=12)
    seg = np.concatenate([[0], np.cumsum(counts)[:-1]])
    pair_v = np.repeat(np.arange(12), counts)
    tets = np.array([np.r_[verts[v], rng.choice(np.setdiff1d(np.arange(40), [verts[v]]), 3, replace=False)]
                     for v in pair_v])
    tets[::2] = tets[::2][:, [1, 0, 2, 3]]  # the moving node in other places too
    neg = tet_volumes(pts, tets) < 0
    tets[neg] = tets[neg][:, [0, 1, 3, 2]]  # valid at the current place
    cur = pts[verts]
    trials = np.concatenate([cur[None], cur[None] + 0.3 * rng.normal(size=(26, 12, 3))])
    table = np.minimum.reduceat(moved_scores(pts, tets, verts[pair_v], pair_v, trials, 10.0, 165.0, radius_edge),
                                seg, axis=1)
    want = np.zeros(12, dtype=np.int64)
    top = table[0].copy()
    for j in range(1, len(trials)):
        better = table[j] > top + 1e-9
        top = np.where(better, table[j], top)
        want[better] = j
    got, score = best_trials(pts, tets, verts, seg, counts, trials, 10.0, 165.0, radius_edge)
    np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal(score, top)
    assert (want > 0).any()  # some vertex found a better place, so the test can tell a wrong pick


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_smoothing_set_is_independent_and_its_means_are_the_numpy_ones(seed):
    from scipy.spatial import Delaunay

    from spatial.fea.score_kernel import smoothing_set

    rng = np.random.default_rng(seed)
    pts = rng.random((80, 3))
    tets = Delaunay(pts).simplices.astype(np.int64)
    flat = tets.reshape(-1)
    order = np.argsort(flat, kind="stable")
    starts = np.searchsorted(flat[order], np.arange(len(pts) + 1))
    cand = rng.random(len(pts)) < 0.5
    prio = rng.permutation(len(pts))
    verts, counts, pair_tet, mean, edge = smoothing_set(pts, tets, starts, order // 4, cand, prio)
    # every candidate that is the first of the candidates of all its elements, and only those
    first = np.where(cand[tets], prio[tets], len(pts)).min(axis=1)
    want = [v for v in np.flatnonzero(cand) if (first[(tets == v).any(axis=1)] == prio[v]).all()]
    assert verts.tolist() == want and len(want) > 0
    assert not np.isin(tets, verts).sum(axis=1).max() > 1  # no two in one element
    for i, v in enumerate(verts):
        around = np.flatnonzero((tets == v).any(axis=1))
        assert sorted(pair_tet[counts[:i].sum():counts[:i + 1].sum()].tolist()) == around.tolist()
        others = pts[tets[around]].reshape(-1, 3)
        np.testing.assert_allclose(mean[i], (others.sum(axis=0) - len(around) * pts[v]) / (3 * len(around)), atol=1e-12)
        np.testing.assert_allclose(edge[i], np.linalg.norm(others - pts[v], axis=1).max(), atol=1e-12)
