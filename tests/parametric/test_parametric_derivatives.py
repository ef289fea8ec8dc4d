"""Exact derivative curves, difference derivatives of any order, and conversion chains."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from parametric.conics import circle, ellipse
from parametric.curves import NURBS, BSpline, FunctionCurve, Hermite
from parametric.surfaces import Surface
from parametric.tensor import BSplineSurface

EXACT = 1e-12      # exact algebraic constructions
FD_HI = 1e-5       # second-order differences of order 3 and 4 on smooth data

U = np.random.default_rng(42).uniform(0.0, 1.0, 400)


def random_nurbs(seed=0, n=9, p=3, dim=3):
    r = np.random.default_rng(seed)
    P = r.normal(size=(n, dim))
    w = r.uniform(0.3, 3.0, n)
    inner = np.sort(r.uniform(0.05, 0.95, n - p - 1))
    return NURBS(P, w, p, np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)]))


# --------------------------------------------------------------------------- NURBS derivative curve

@pytest.mark.parametrize("p", [1, 2, 3, 4])
def test_nurbs_derivative_curve_is_exact_and_recurses(p):
    c = random_nurbs(3 + p, n=p + 6, p=p) if p > 1 else NURBS([[0, 0], [1, 2]], [1.0, 3.0], 1)
    d = c.derivative_curve()
    assert isinstance(d, NURBS) and d.degree == 2 * p
    assert d.domain == pytest.approx(c.domain)
    scale = np.abs(c.derivative(U, 1)).max()
    np.testing.assert_allclose(d(U), c.derivative(U, 1), atol=EXACT * scale)
    if p > 2:  # C' is C^1 for p >= 3: the derivative of the derivative (a NURBS again) is the second derivative
        dd = d.derivative_curve()
        assert dd.degree == 4 * p
        scale2 = np.abs(c.derivative(U, 2)).max()
        np.testing.assert_allclose(dd(U), c.derivative(U, 2), atol=1e-11 * scale2)
        np.testing.assert_allclose(d.derivative(U, 1), c.derivative(U, 2), atol=1e-11 * scale2)


def test_nurbs_derivative_curve_matches_finite_differences():
    c = random_nurbs(7)
    d = c.derivative_curve()
    h = 1e-6
    u = np.clip(U, h, 1 - h)
    fd = (c(u + h) - c(u - h)) / (2 * h)
    np.testing.assert_allclose(d(u), fd, atol=1e-6 * np.abs(fd).max())


def test_nurbs_derivative_curve_keeps_continuity_of_knots():
    # a cubic with simple knots is C^2; its derivative has degree 6 and knots of
    # multiplicity p + m + 1 = 5 (C^1), the exact smoothness of C'
    c = random_nurbs(11)
    d = c.derivative_curve()
    inner = d.knots[7:-7]
    vals, counts = np.unique(inner, return_counts=True)
    np.testing.assert_allclose(vals, np.unique(c.knots[4:-4]), atol=0)
    np.testing.assert_array_equal(counts, 5)


@pytest.mark.parametrize("r", [1.0, 2.5])
def test_derivative_of_the_nurbs_circle(r):
    c = circle(r, center=(0.0, 0.0))
    d = c.derivative_curve()
    np.testing.assert_allclose(d(U), c.derivative(U), atol=EXACT * r)
    # tangent to the circle, and its speed integrates to the circumference 2 pi r
    np.testing.assert_allclose(np.einsum("nd,nd->n", d(U), c(U)), 0.0, atol=1e-11 * r * r)
    t = np.linspace(0, 1, 4001)
    speed = np.linalg.norm(d(t), axis=1)
    length = np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))
    assert length == pytest.approx(2 * np.pi * r, rel=1e-6)
    # the rational quarter arcs are not arc-length parametrized: the speed is
    # slowest at the knots, 2 (w1 / w0) |P1 - P0| / (1/4) = 4 sqrt(2) r
    assert speed.min() == pytest.approx(4 * np.sqrt(2) * r, rel=1e-12)
    assert speed.max() > 1.1 * speed.min()


def test_derivative_curve_at_a_corner_raises():
    # a C^0 knot (multiplicity p) with a real corner: the derivative jumps
    c = NURBS([[0, 0], [1, 0], [1, 1]], [1.0, 2.0, 1.0], 1)
    with pytest.raises(ValueError, match="derivative jumps at knot u=0.5"):
        c.derivative_curve()
    # the circle's derivative is only C^0 at its double knots: its own derivative jumps
    with pytest.raises(ValueError, match="derivative jumps"):
        circle(1.0, center=(0, 0)).derivative_curve().derivative_curve()


@settings(derandomize=True, max_examples=15, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 4))
def test_derivative_curve_property(seed, p):
    c = random_nurbs(seed, n=p + 5, p=p)
    d = c.derivative_curve()
    np.testing.assert_allclose(d(U), c.derivative(U, 1), atol=1e-11 * np.abs(d(U)).max())


def test_bspline_and_nurbs_derivative_curves_agree_for_unit_weights():
    c = random_nurbs(5)
    b = BSpline(c.control_points, c.degree, c.knots)
    unit = b.to_nurbs()
    np.testing.assert_allclose(unit.derivative_curve()(U), b.derivative_curve()(U), atol=EXACT)


# --------------------------------------------------------------------------- differences of any order

def test_function_curve_derivatives_of_order_three_and_four():
    c = FunctionCurve(lambda u: np.stack([np.sin(u), np.exp(0.5 * u), u ** 4], -1), (0.0, 2.0))
    u = np.linspace(0, 2, 41)  # ends included: stencils shift inside the domain
    d = c.derivatives(u, 4)
    np.testing.assert_allclose(d[:, 3, 0], -np.cos(u), atol=FD_HI * 50)
    np.testing.assert_allclose(d[:, 4, 0], np.sin(u), atol=FD_HI * 500)
    np.testing.assert_allclose(d[:, 3, 1], 0.125 * np.exp(0.5 * u), atol=FD_HI * 50)
    # the rule is exact for polynomials of degree k + 1 up to rounding
    np.testing.assert_allclose(d[:, 3, 2], 24 * u, atol=1e-4)
    np.testing.assert_allclose(d[:, 4, 2], 24.0, atol=5e-3)


def test_generic_surface_derivatives_of_order_three():
    class Wave(Surface):
        def _eval(self, u, v):
            return np.stack([u, v, np.sin(2 * u) * np.cos(v)], -1)

    s = Wave()
    u, v = np.random.default_rng(1).uniform(0, 1, (2, 30))
    d = s.derivatives(u, v, 3)
    assert d.shape == (30, 4, 4, 3)
    np.testing.assert_allclose(d[:, 3, 0, 2], -8 * np.cos(2 * u) * np.cos(v), atol=1e-3)
    np.testing.assert_allclose(d[:, 1, 2, 2], -2 * np.cos(2 * u) * np.cos(v), atol=1e-3)
    np.testing.assert_allclose(d[:, 2, 1, 2], 4 * np.sin(2 * u) * np.sin(v), atol=1e-3)
    np.testing.assert_allclose(d[:, 0, 3, 2], np.sin(2 * u) * np.sin(v), atol=1e-3)
    np.testing.assert_allclose(d[:, 1, 0, 0], 1.0, atol=1e-8)
    np.testing.assert_allclose(d[:, 3, 3, :2], 0.0, atol=1e-3)


# --------------------------------------------------------------------------- conversion chain

def test_hermite_bezier_bspline_nurbs_chain_gives_the_same_points():
    h = Hermite([0.0, 1.0, 2.0], [3.0, -1.0, 0.5], [2.0, 0.0, 1.0], [-1.0, 4.0, 0.0])
    bz = h.to_bezier()
    bs = bz.to_bspline()
    nu = bs.to_nurbs()
    ref = h(U)
    assert isinstance(h.to_bspline(), BSpline) and isinstance(h.to_nurbs(), NURBS)
    np.testing.assert_allclose(h.derivative_curve()(U), h.derivative(U, 1), atol=EXACT * 10)
    for c in (bz, bs, nu, bz.to_nurbs(), h.to_bspline(), h.to_nurbs()):
        np.testing.assert_allclose(c(U), ref, atol=EXACT)
        np.testing.assert_allclose(c.derivative(U, 1), h.derivative(U, 1), atol=EXACT * 10)
        np.testing.assert_allclose(c.derivative(U, 2), h.derivative(U, 2), atol=EXACT * 100)
    np.testing.assert_allclose(nu.weights, 1.0, atol=0)
    # derivative curves along the chain: Bezier hodograph, B-spline, rational
    np.testing.assert_allclose(bz.derivative_curve()(U), h.derivative(U, 1), atol=EXACT * 10)
    np.testing.assert_allclose(bs.derivative_curve()(U), h.derivative(U, 1), atol=EXACT * 10)
    np.testing.assert_allclose(nu.derivative_curve()(U), h.derivative(U, 1), atol=EXACT * 10)


def test_nurbs_with_unit_weights_equals_its_bspline_in_every_operation():
    c = random_nurbs(21)
    b = BSpline(c.control_points, c.degree, c.knots)
    n = NURBS(c.control_points, np.ones(9), c.degree, c.knots)
    np.testing.assert_allclose(n(U), b(U), atol=EXACT)
    np.testing.assert_allclose(n.derivatives(U, 3), b.derivatives(U, 3), atol=1e-10)
    np.testing.assert_allclose(n.insert_knot(0.3, 2)(U), b.insert_knot(0.3, 2)(U), atol=EXACT)
    np.testing.assert_allclose(n.elevate_degree(1)(U), b.elevate_degree(1)(U), atol=EXACT)
    np.testing.assert_allclose(n.insert_knot(0.3).weights, 1.0, atol=EXACT)


def test_ellipse_to_nurbs_is_itself_and_bezier_pieces_chain_back():
    e = ellipse(2.0, 1.0, center=(0.0, 0.0))
    assert e.to_nurbs() is e
    pieces = e.to_bezier_segments()
    for piece in pieces:
        a, b = piece.domain
        t = np.linspace(a, b, 17)
        np.testing.assert_allclose(piece(t), e(t), atol=EXACT)


def test_bspline_surface_to_nurbs_same_points():
    r = np.random.default_rng(3)
    s = BSplineSurface(r.normal(size=(5, 6, 3)), 3, 2)
    u, v = r.uniform(0, 1, (2, 100))
    np.testing.assert_allclose(s.to_nurbs()(u, v), s(u, v), atol=EXACT)
    np.testing.assert_allclose(s.to_nurbs().derivatives(u, v, 2), s.derivatives(u, v, 2),
                               atol=1e-10)


def test_derivative_curve_of_a_periodic_nurbs_on_another_domain():
    r = np.random.default_rng(3)
    c = NURBS.periodic(r.normal(size=(7, 3)), r.uniform(0.5, 2.0, 7), 3, domain=(2.0, 5.0))
    d = c.derivative_curve()
    u = np.linspace(2.0, 5.0, 301)
    assert d.domain == pytest.approx((2.0, 5.0))
    np.testing.assert_allclose(d(u), c.derivative(u), atol=1e-12 * np.abs(d(u)).max())
    np.testing.assert_allclose(d.derivative(u), c.derivative(u, 2),
                               atol=1e-12 * np.abs(c.derivative(u, 2)).max())
    # the derivative of a closed C^2 curve is periodic again (wrapped form)
    from parametric import _ops
    np.testing.assert_allclose(d(2.0), d(5.0), atol=1e-12 * np.abs(d(u)).max())
    assert _ops.periodic_count(d.knots, d.degree, d.homogeneous) == 7 * 5
    assert np.all(d.weights > 0)
    dd = d.derivative_curve()  # C' is C^1: its derivative is one curve, periodic again
    np.testing.assert_allclose(dd(u), c.derivative(u, 2),
                               atol=1e-11 * np.abs(c.derivative(u, 2)).max())
