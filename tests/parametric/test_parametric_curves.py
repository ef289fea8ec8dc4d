"""Curves: the lecture notes' properties of Bezier, B-spline and NURBS curves as tests."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

from parametric import basis
from parametric.curves import NURBS, Bezier, BSpline, FunctionCurve, Hermite

EXACT = 1e-12      # invariance under exact algebraic edits
ROUND = 1e-14      # a few ulps of unit-sized values
FD = 1e-6          # central finite differences with h = 1e-6


def rng(seed=0):
    return np.random.default_rng(seed)


def random_bspline(seed=0, n=9, p=3, dim=3, knots="random"):
    r = rng(seed)
    P = r.normal(size=(n, dim))
    if knots == "random":
        inner = np.sort(r.uniform(0.05, 0.95, n - p - 1))
        U = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    else:
        U = None
    return BSpline(P, p, U)


def random_nurbs(seed=0, n=9, p=3, dim=3):
    b = random_bspline(seed, n, p, dim)
    w = rng(seed + 100).uniform(0.3, 3.0, n)
    return NURBS(b.control_points, w, p, b.knots)


U_TEST = rng(42).uniform(0.0, 1.0, 500)


# --------------------------------------------------------------------------- basis

def test_bernstein_partition_of_unity_and_values():
    u = np.linspace(0, 1, 101)
    B = basis.bernstein(5, u)
    assert B.shape == (101, 6)
    assert np.max(np.abs(B.sum(axis=1) - 1.0)) < ROUND * 10
    assert np.all(B >= 0)
    np.testing.assert_allclose(basis.bernstein(2, 0.5), [0.25, 0.5, 0.25], atol=ROUND)


@settings(derandomize=True, max_examples=60, deadline=None)
@given(p=st.integers(1, 6), extra=st.integers(0, 8), seed=st.integers(0, 10_000),
       clamped=st.booleans())
def test_bspline_basis_partition_of_unity(p, extra, seed, clamped):
    r = rng(seed)
    n = p + 1 + extra
    if clamped:
        inner = np.sort(r.uniform(0, 1, n - p - 1))
        U = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    else:
        U = np.sort(r.uniform(-1, 2, n + p + 1))
        U[p], U[n] = 0.0, 1.0
        U = np.sort(U)
    a, b = U[p], U[n]
    if not a < b or np.any(np.unique(U[p + 1:n], return_counts=True)[1] > p) or not U[n - 1] < b:
        return
    u = r.uniform(a, b, 200)
    u[:2] = a, b
    N = basis.basis_matrix(U, p, n, u)
    assert np.max(np.abs(N.sum(axis=1) - 1.0)) < 1e-12
    assert np.all(N >= -1e-15)
    # derivatives of a partition of unity sum to zero
    D = basis.basis_matrix(U, p, n, u, n_ders=2)
    scale = 1.0 / max(np.min(np.diff(np.unique(U[p:n + 1]))), 1e-3) ** 2
    assert np.max(np.abs(D[1].sum(axis=1))) < 1e-9 * scale
    assert np.max(np.abs(D[2].sum(axis=1))) < 1e-8 * scale


@pytest.mark.parametrize("p", [1, 2, 3, 5])
def test_derivative_recurrence_matches_literal_a23(p):
    r = rng(p)
    n = p + 6
    inner = np.sort(r.uniform(0, 1, n - p - 1))
    inner[1] = inner[0]  # a double knot
    U = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    u = np.concatenate([[0.0, 1.0, inner[0]], r.uniform(0, 1, 300)])
    span = basis.find_span(U, p, n, u)
    for nd in (0, 1, 2, p + 1):
        fast = basis.ders_basis_funs(U, p, span, u, nd)
        ref = basis._ders_basis_funs_a23(U, p, span, u, nd)
        np.testing.assert_allclose(fast, ref, atol=1e-12 * max(1.0, np.abs(ref).max()))
    np.testing.assert_allclose(basis.ders_basis_funs(U, p, span, u, 0)[:, 0],
                               basis.basis_funs(U, p, span, u), atol=0)


def test_find_span_matches_definition():
    U = np.array([0, 0, 0, 0.3, 0.3, 0.6, 1, 1, 1.0])
    u = np.array([0.0, 0.1, 0.3, 0.45, 0.6, 0.99, 1.0])
    span = basis.find_span(U, 2, 6, u)
    np.testing.assert_array_equal(span, [2, 2, 4, 4, 5, 5, 5])


def test_knot_vectors():
    np.testing.assert_allclose(basis.clamped_knots(4, 2), [0, 0, 0, 0.5, 1, 1, 1])
    np.testing.assert_allclose(basis.uniform_knots(4, 2), [-1, -0.5, 0, 0.5, 1, 1.5, 2])
    U = basis.periodic_knots(5, 3)
    assert U.size == 5 + 2 * 3 + 1 and U[3] == 0.0 and U[8] == 1.0


@pytest.mark.parametrize("knots, n_control, match", [
    ([0, 0, 0, 1, 1], 4, "must have n_control \\+ degree \\+ 1 = 7"),
    ([0, 0, 0, 0.7, 0.5, 1, 1, 1], 5, "non-decreasing"),
    ([0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1], 6, "repeats 3 times"),
    ([0, 0, 0, 0, 0, 0, 1, 1], 5, "empty domain"),
])
def test_validate_knots_errors(knots, n_control, match):
    with pytest.raises(ValueError, match=match):
        basis.validate_knots(knots, 2, n_control)


def test_degree_type_error():
    with pytest.raises(TypeError, match="degree must be an int"):
        BSpline(np.zeros((4, 2)), 2.0)


# --------------------------------------------------------------------------- evaluation contract

def test_call_shapes_and_domain_error():
    c = random_bspline()
    assert c(0.5).shape == (3,)
    assert c(np.array([0.1, 0.2])).shape == (2, 3)
    with pytest.raises(ValueError, match="u must lie in the domain"):
        c(1.5)
    with pytest.raises(ValueError, match="u must lie in the domain"):
        c([0.2, -0.1])


def test_objects_are_immutable():
    c = random_bspline()
    with pytest.raises(ValueError, match="read-only"):
        c.control_points[0, 0] = 1.0
    with pytest.raises(TypeError, match="ambiguous"):
        bool(c)


@pytest.mark.parametrize("knots", ["random", "uniform", "clustered"])
def test_fast_path_matches_cox_de_boor(knots):
    c = random_nurbs(3)
    if knots == "uniform":
        c = NURBS(c.control_points, c.weights, 3)
    elif knots == "clustered":
        U = np.array(c.knots)
        U[5:8] = 0.4 + np.array([0.0, 1e-7, 2e-7])
        c = NURBS(c.control_points, c.weights, 3, U)
    u = np.concatenate([rng(9).uniform(0, 1, 20_000), c.knots[3:-3], [0.4 + 5e-8]])
    # 20 000 points take the power-table path, chunks of 2 000 take Cox-de Boor
    slow = np.concatenate([c(chunk) for chunk in np.array_split(u, 11)])
    np.testing.assert_allclose(c(u), slow, atol=EXACT)


# --------------------------------------------------------------------------- Bezier properties

def test_bezier_end_point_interpolation_and_tangency():
    P = rng(1).normal(size=(6, 3))
    b = Bezier(P)
    np.testing.assert_allclose(b(0.0), P[0], atol=ROUND)
    np.testing.assert_allclose(b(1.0), P[-1], atol=ROUND)
    n = 5
    np.testing.assert_allclose(b.derivative(0.0), n * (P[1] - P[0]), atol=EXACT)
    np.testing.assert_allclose(b.derivative(1.0), n * (P[-1] - P[-2]), atol=EXACT)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_bezier_kth_end_derivative_fixed_by_first_k_plus_1_points(k):
    P = rng(2).normal(size=(7, 2))
    n = 6
    b = Bezier(P)
    forward = np.diff(P, n=k, axis=0)[0]
    expected = np.prod(np.arange(n - k + 1, n + 1)) * forward
    np.testing.assert_allclose(b.derivative(0.0, order=k), expected, atol=1e-10)
    Q = P.copy()
    Q[k + 1:] += 5.0  # moving the other points leaves the k-th derivative at 0 alone
    np.testing.assert_allclose(Bezier(Q).derivative(0.0, order=k), expected, atol=1e-10)
    assert np.linalg.norm(Bezier(Q).derivative(0.0, order=k + 1)
                          - b.derivative(0.0, order=k + 1)) > 1.0


def test_bezier_convex_hull():
    P = rng(3).normal(size=(7, 3))
    pts = Bezier(P)(np.linspace(0, 1, 400))
    assert np.all(Delaunay(P).find_simplex(pts) >= 0)


def test_bspline_and_nurbs_convex_hull():
    for c in (random_bspline(4), random_nurbs(4)):
        pts = c(np.linspace(0, 1, 600))
        assert np.all(Delaunay(c.control_points).find_simplex(pts) >= 0)


def test_bezier_de_casteljau_split_elevate():
    b = Bezier(rng(4).normal(size=(5, 3)))
    np.testing.assert_allclose(b.de_casteljau(U_TEST), b(U_TEST), atol=EXACT)
    left, right = b.split(0.3)
    np.testing.assert_allclose(left(U_TEST), b(0.3 * U_TEST), atol=EXACT)
    np.testing.assert_allclose(right(U_TEST), b(0.3 + 0.7 * U_TEST), atol=EXACT)
    e = b.elevate_degree(3)
    assert e.degree == 7
    np.testing.assert_allclose(e(U_TEST), b(U_TEST), atol=EXACT)
    np.testing.assert_allclose(b.to_bspline()(U_TEST), b(U_TEST), atol=EXACT)
    np.testing.assert_allclose(b.derivative_curve()(U_TEST), b.derivative(U_TEST), atol=EXACT)
    with pytest.raises(ValueError, match="strictly inside"):
        b.split(1.0)


def test_coincident_control_points_pull_curve_to_vertex():
    P = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]])
    target = P[1]
    dists = []
    for k in range(1, 5):
        Q = np.concatenate([P[:1], np.repeat(P[1:2], k, axis=0), P[2:]])
        pts = Bezier(Q)(np.linspace(0, 1, 2001))
        dists.append(np.min(np.linalg.norm(pts - target, axis=1)))
    assert all(d1 > d2 for d1, d2 in zip(dists, dists[1:]))
    assert dists[0] == pytest.approx(1.0)  # quadratic: apex at (1, 1)


# --------------------------------------------------------------------------- Hermite

def test_hermite_blending_and_end_conditions():
    h = Hermite([0, 0, 0], [1, 2, 0], [3, 0, 1], [0, -1, 2])
    u = np.linspace(0, 1, 11)
    F = Hermite.blending_functions(u)
    np.testing.assert_allclose(F[:, 0] + F[:, 1], 1.0, atol=ROUND)
    np.testing.assert_allclose(F[5], [0.5, 0.5, 0.125, -0.125], atol=ROUND)
    np.testing.assert_allclose(h(0.0), [0, 0, 0], atol=ROUND)
    np.testing.assert_allclose(h(1.0), [1, 2, 0], atol=ROUND)
    np.testing.assert_allclose(h.derivative([0.0, 1.0]), [[3, 0, 1], [0, -1, 2]], atol=EXACT)
    np.testing.assert_allclose(h.to_bezier()(U_TEST), h(U_TEST), atol=EXACT)


def test_hermite_dimension_mismatch():
    with pytest.raises(ValueError, match="share one dimension"):
        Hermite([0, 0], [1, 0, 0], [1, 0], [1, 0])


# --------------------------------------------------------------------------- B-spline properties

def test_clamped_bspline_end_interpolation_and_tangency():
    c = random_bspline(5)
    P, U, p = c.control_points, c.knots, c.degree
    np.testing.assert_allclose(c(0.0), P[0], atol=ROUND)
    np.testing.assert_allclose(c(1.0), P[-1], atol=ROUND)
    np.testing.assert_allclose(c.derivative(0.0), p / (U[p + 1] - U[1]) * (P[1] - P[0]),
                               atol=1e-10)
    n = P.shape[0] - 1
    np.testing.assert_allclose(c.derivative(1.0), p / (U[n + p] - U[n]) * (P[n] - P[n - 1]),
                               atol=1e-10)


def test_local_control():
    c = random_bspline(6, n=10, p=3)
    U, p, k = c.knots, c.degree, 4
    P = np.array(c.control_points)
    P[k] += [0.3, -0.2, 0.5]
    moved = BSpline(P, p, U)
    u = np.linspace(0, 1, 2001)
    inside = (u >= U[k]) & (u < U[k + p + 1])
    diff = np.linalg.norm(moved(u) - c(u), axis=1)
    assert np.max(diff[~inside]) == 0.0
    assert np.min(diff[inside][1:-1]) > 0.0
    assert np.unique(np.searchsorted(U, u[inside], side="right") - 1).size <= p + 1


@pytest.mark.parametrize("m", [2, 3, 4])
def test_continuity_at_simple_knots(m):
    c = random_bspline(7, n=8, p=m)
    segs = c.to_bezier_segments()
    breaks = np.unique(c.knots)
    for i in range(len(segs) - 1):
        h0 = breaks[i + 1] - breaks[i]
        h1 = breaks[i + 2] - breaks[i + 1]
        for order in range(m + 1):
            left = segs[i].derivative(1.0, order) / h0 ** order
            right = segs[i + 1].derivative(0.0, order) / h1 ** order
            jump = np.linalg.norm(left - right)
            scale = 1.0 + np.linalg.norm(left)
            if order < m:
                assert jump < 1e-9 * scale, (order, jump)
            else:
                assert jump > 1e-3, (order, jump)


def test_bspline_derivatives_match_derivative_curve_and_differences():
    c = random_bspline(8, p=4)
    d = c.derivatives(U_TEST, 3)
    dc = c.derivative_curve()
    np.testing.assert_allclose(d[:, 1], dc(U_TEST), atol=1e-9)
    np.testing.assert_allclose(d[:, 2], dc.derivative_curve()(U_TEST), atol=1e-7)
    u = np.clip(U_TEST, 1e-5, 1 - 1e-5)
    fd = (c(u + 1e-6) - c(u - 1e-6)) / 2e-6
    np.testing.assert_allclose(c.derivative(u), fd, atol=1e-5 * np.abs(fd).max())


def test_periodic_bspline_closes_smoothly():
    c = BSpline.periodic(rng(9).normal(size=(7, 2)), 3)
    d0 = c.derivatives(0.0, 2)
    d1 = c.derivatives(1.0, 2)
    np.testing.assert_allclose(d0, d1, atol=1e-11)


# --------------------------------------------------------------------------- editing invariance

CURVES = {
    "bspline": lambda: random_bspline(10),
    "nurbs": lambda: random_nurbs(11),
    "uniform-unclamped": lambda: BSpline(rng(12).normal(size=(8, 3)), 3,
                                         basis.uniform_knots(8, 3)),
    "periodic": lambda: BSpline.periodic(rng(13).normal(size=(6, 3)), 3),
    "degree-1": lambda: random_bspline(14, n=5, p=1),
}


def _params_in(c, n=400):
    a, b = c.domain
    return a + (b - a) * rng(15).uniform(0, 1, n)


@pytest.mark.parametrize("name", sorted(CURVES))
def test_insert_knot_invariance(name):
    c = CURVES[name]()
    a, b = c.domain
    u = _params_in(c)
    for x, times in ((a + 0.37 * (b - a), 1), (a + 0.61 * (b - a), c.degree)):
        d = c.insert_knot(x, times)
        assert len(d.knots) == len(c.knots) + times
        assert type(d) is type(c)
        np.testing.assert_allclose(d(u), c(u), atol=EXACT)


@pytest.mark.parametrize("name", sorted(CURVES))
def test_refine_knots_invariance(name):
    c = CURVES[name]()
    a, b = c.domain
    X = a + (b - a) * np.array([0.05, 0.2, 0.2, 0.5, 0.77, 0.9])
    if c.degree == 1:
        X = np.unique(X)
    d = c.refine_knots(X)
    assert len(d.knots) == len(c.knots) + X.size
    np.testing.assert_allclose(d(_params_in(c)), c(_params_in(c)), atol=EXACT)
    # refinement equals repeated single insertion
    e = c
    for x in X:
        e = e.insert_knot(x)
    np.testing.assert_allclose(d.knots, e.knots, atol=0)
    ctrl = getattr(d, "homogeneous", d.control_points)
    ctrl_e = getattr(e, "homogeneous", e.control_points)
    np.testing.assert_allclose(ctrl, ctrl_e, atol=EXACT)


@pytest.mark.parametrize("name", sorted(CURVES))
@pytest.mark.parametrize("times", [1, 2])
def test_elevate_degree_invariance(name, times):
    c = CURVES[name]()
    d = c.elevate_degree(times)
    assert d.degree == c.degree + times
    assert d.domain == pytest.approx(c.domain)
    u = _params_in(c)
    np.testing.assert_allclose(d(u), c(u), atol=EXACT)
    # every distinct interior knot gains `times` in multiplicity (continuity kept)
    def inner(curve):  # knots strictly inside the domain, with multiplicities
        a, b = curve.domain
        k = np.asarray(curve.knots)
        return np.unique(k[(k > a) & (k < b)], return_counts=True)

    v0, m0 = inner(c)
    v1, m1 = inner(d)
    np.testing.assert_allclose(v0, v1, atol=1e-12)
    np.testing.assert_array_equal(m1, m0 + times)


def test_elevating_a_periodic_curve_keeps_it_periodic():
    from parametric import _ops
    for c in (BSpline.periodic(rng(13).normal(size=(6, 3)), 3),
              NURBS.periodic(rng(14).normal(size=(5, 2)), rng(15).uniform(0.5, 2, 5), 2)):
        for times in (1, 2):
            d = c.elevate_degree(times)
            assert type(d) is type(c) and d.degree == c.degree + times
            assert d.domain == pytest.approx(c.domain)
            # wrapped form: first q control points repeated at the end, periodic knots
            ctrl = getattr(d, "homogeneous", d.control_points)
            k = _ops.periodic_count(d.knots, d.degree, ctrl)
            assert k == ctrl.shape[0] - d.degree > 0
            np.testing.assert_allclose(ctrl[k:], ctrl[:d.degree], atol=0)
            a, b = d.domain
            assert d.knots[0] < a and d.knots[-1] > b  # not clamped
            u = np.linspace(a, b, 301)
            np.testing.assert_allclose(d(u), c(u), atol=EXACT)
            # the seam keeps C^(p-1): derivatives up to p - 1 agree at both ends
            ends = d.derivatives(np.array([a, b]), c.degree - 1)
            np.testing.assert_allclose(ends[0], ends[1], atol=1e-10)
    # clamped curves stay clamped
    clamped = random_bspline(3).elevate_degree(1)
    assert np.all(clamped.knots[:5] == 0.0)


@pytest.mark.parametrize("name", ["bspline", "nurbs"])
def test_remove_knot_undoes_insertion(name):
    c = CURVES[name]()
    for x, times in ((0.37, 1), (0.37, 3), (float(c.knots[5]), 2)):
        d = c.insert_knot(x, times).remove_knot(x, times)
        np.testing.assert_allclose(d.knots, c.knots, atol=0)
        np.testing.assert_allclose(d.control_points, c.control_points, atol=EXACT)
        if name == "nurbs":
            np.testing.assert_allclose(d.weights, c.weights, atol=EXACT)


def test_remove_knot_refuses_to_change_the_curve():
    c = random_bspline(22)
    with pytest.raises(ValueError, match="can be removed only 0 of 1"):
        c.remove_knot(float(c.knots[5]))
    with pytest.raises(ValueError, match="is not a knot"):
        c.remove_knot(0.123456)


def test_elevation_routes_agree():
    """Decomposition + Bezier elevation + knot removal equals collocation in the
    elevated spline space (both give the unique representation)."""
    from parametric import _ops
    c = random_nurbs(23, n=12, p=3)
    U = np.array(c.knots)
    U[6] = U[5]  # a double knot, continuity C1 there
    c = NURBS(c.control_points, c.weights, 3, U)
    for t in (1, 2):
        Ua, Qa = _ops.elevate_by_decomposition(c.knots, 3, c.homogeneous, t)
        Ub, Qb = _ops.elevate_collocation(c.knots, 3, c.homogeneous, t)
        np.testing.assert_allclose(Ua, Ub, atol=0)
        np.testing.assert_allclose(Qa, Qb, atol=1e-11)


@settings(derandomize=True, max_examples=40, deadline=None)
@given(x=st.floats(0.01, 0.99), times=st.integers(1, 3), seed=st.integers(0, 1000),
       rational=st.booleans())
def test_insertion_invariance_property(x, times, seed, rational):
    c = random_nurbs(seed) if rational else random_bspline(seed)
    if basis.knot_multiplicity(c.knots, x) + times > c.degree:
        return
    u = rng(seed).uniform(0, 1, 100)
    np.testing.assert_allclose(c.insert_knot(x, times)(u), c(u), atol=EXACT)


def test_insert_knot_errors():
    c = random_bspline(16)
    with pytest.raises(ValueError, match="strictly inside the domain"):
        c.insert_knot(1.0)
    with pytest.raises(ValueError, match="multiplicity"):
        c.insert_knot(0.5, 4)
    with pytest.raises(ValueError, match="strictly inside the domain"):
        c.refine_knots([0.5, 1.2])


def test_bezier_segments_reproduce_curve():
    for c in (random_bspline(17), random_nurbs(18)):
        segs = c.to_bezier_segments()
        br = np.unique(c.knots)
        assert len(segs) == br.size - 1
        t = np.linspace(0, 1, 50)
        for i, s in enumerate(segs):
            u = br[i] + t * (br[i + 1] - br[i])
            pts = s(t) if isinstance(s, Bezier) else s(u)
            np.testing.assert_allclose(pts, c(u), atol=EXACT)


# --------------------------------------------------------------------------- NURBS

def test_nurbs_with_unit_weights_is_its_bspline():
    b = random_bspline(19)
    n = b.to_nurbs()
    np.testing.assert_allclose(n(U_TEST), b(U_TEST), atol=EXACT)
    np.testing.assert_allclose(n.derivatives(U_TEST, 3), b.derivatives(U_TEST, 3), atol=1e-9)


def test_raising_a_weight_pulls_curve_toward_its_control_point():
    c = random_nurbs(20)
    k = 4
    u0 = float(basis.greville(c.knots, c.degree)[k])
    dists = []
    for wk in (0.25, 1.0, 4.0, 16.0, 256.0):
        w = np.array(c.weights)
        w[k] = wk
        dists.append(np.linalg.norm(c.with_weights(w)(u0) - c.control_points[k]))
    assert all(d1 > d2 for d1, d2 in zip(dists, dists[1:]))
    assert dists[-1] < 0.05 * dists[0]


def test_nurbs_derivatives_rational_rule():
    c = random_nurbs(21)
    u = np.clip(U_TEST[:50], 1e-4, 1 - 1e-4)
    h = 1e-6
    d = c.derivatives(u, 2)
    fd1 = (c(u + h) - c(u - h)) / (2 * h)
    np.testing.assert_allclose(d[:, 1], fd1, atol=FD * np.abs(fd1).max())
    fd2 = (c.derivative(u + h) - c.derivative(u - h)) / (2 * h)
    np.testing.assert_allclose(d[:, 2], fd2, atol=FD * np.abs(fd2).max())


def test_nurbs_errors():
    with pytest.raises(ValueError, match="weights must be > 0"):
        NURBS(np.zeros((3, 2)), [1, 0, 1], 2)
    with pytest.raises(ValueError, match="one value per control point"):
        NURBS(np.zeros((3, 2)), [1, 1], 2)


def test_function_curve_wraps_callables():
    c = FunctionCurve(lambda u: np.stack([u, u ** 2], axis=-1), (0.0, 2.0))
    np.testing.assert_allclose(c(1.5), [1.5, 2.25])
    np.testing.assert_allclose(c.derivative(1.0), [1.0, 2.0], atol=1e-6)
    with pytest.raises(TypeError, match="func must be callable"):
        FunctionCurve(3.0)
