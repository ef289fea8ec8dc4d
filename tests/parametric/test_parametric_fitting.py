"""Fitting, lofting and closest-point projection."""

import numpy as np
import pytest

from parametric.conics import circle, ellipse
from parametric.curves import NURBS, Bezier, BSpline
from parametric.fitting import (approximate_curve, approximate_surface, fit_curve,
                                fit_periodic_curve, fit_periodic_surface, interpolate_curve,
                                interpolate_surface, loft, make_compatible, parametrize)
from parametric.projection import project_to_curve, project_to_surface
from parametric.tensor import BSplineSurface, NURBSSurface, sphere, torus

EXACT = 1e-12
SOLVE = 1e-10      # linear solves of interpolation systems


def rng(seed=0):
    return np.random.default_rng(seed)


def helix(n=60):
    t = np.linspace(0, 4 * np.pi, n)
    return np.stack([np.cos(t), np.sin(t), 0.2 * t], 1)


# --------------------------------------------------------------------------- parameters

def test_parametrize_methods():
    Q = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    np.testing.assert_allclose(parametrize(Q), [0, 3 / 7, 1])
    np.testing.assert_allclose(parametrize(Q, "centripetal"),
                               [0, np.sqrt(3) / (np.sqrt(3) + 2), 1])
    np.testing.assert_allclose(parametrize(Q, "uniform"), [0, 0.5, 1])
    np.testing.assert_allclose(parametrize(Q, closed=True), [0, 3 / 12, 7 / 12])
    with pytest.raises(ValueError, match="method must be one of"):
        parametrize(Q, "arc")
    with pytest.raises(ValueError, match="must not all coincide"):
        parametrize(np.zeros((3, 2)))


# --------------------------------------------------------------------------- curves

@pytest.mark.parametrize("method", ["chord", "centripetal", "uniform"])
@pytest.mark.parametrize("degree", [2, 3, 5])
def test_interpolation_passes_through_points(method, degree):
    Q = helix()
    c = interpolate_curve(Q, degree, method=method)
    assert c.degree == degree and c.control_points.shape == Q.shape
    np.testing.assert_allclose(c(parametrize(Q, method)), Q, atol=SOLVE)


def test_least_squares_fit_interpolates_ends_and_reproduces_its_space():
    truth = BSpline(rng(1).normal(size=(8, 3)), 3)
    t = np.linspace(0, 1, 200)
    Q = truth(t)
    a = approximate_curve(Q, 8, 3, params=t)
    np.testing.assert_allclose(a(0.0), Q[0], atol=0)
    np.testing.assert_allclose(a(1.0), Q[-1], atol=0)
    assert np.max(np.linalg.norm(a(t) - Q, axis=1)) < 0.05
    with pytest.raises(ValueError, match="n_control must lie in"):
        approximate_curve(Q, 3, 3)


@pytest.mark.parametrize("tol", [1e-2, 1e-4])
def test_fit_curve_reaches_tolerance(tol):
    Q = helix(200)
    c, dev = fit_curve(Q, 3, tolerance=tol)
    assert dev <= tol
    assert c.control_points.shape[0] < Q.shape[0]
    t = parametrize(Q)
    assert np.max(np.linalg.norm(c(t) - Q, axis=1)) == pytest.approx(dev)
    # projected distances never exceed the reported deviation
    _, _, d = project_to_curve(c, Q)
    assert np.all(d <= dev + 1e-12)


def test_fit_curve_fixed_count_and_interpolation_default():
    Q = helix(40)
    c, dev = fit_curve(Q, 3)
    assert dev < SOLVE and c.control_points.shape[0] == 40
    c, dev = fit_curve(Q, 3, n_control=10)
    assert c.control_points.shape[0] == 10 and dev > 0
    with pytest.raises(ValueError, match="tolerance must be > 0"):
        fit_curve(Q, tolerance=0.0)
    with pytest.raises(TypeError, match="n_control must be an int"):
        fit_curve(Q, n_control=5.0)


def test_closed_fit_is_periodic_and_accurate():
    th = np.linspace(0, 2 * np.pi, 240, endpoint=False)
    Q = np.stack([2 * np.cos(th), np.sin(th)], 1)
    c, dev = fit_curve(Q, 3, tolerance=1e-4, closed=True)
    assert dev <= 1e-4
    np.testing.assert_allclose(c.derivatives(0.0, 2), c.derivatives(1.0, 2), atol=1e-9)
    p = c(np.linspace(0, 1, 1000))
    assert np.max(np.abs(p[:, 0] ** 2 / 4 + p[:, 1] ** 2 - 1)) < 1e-3
    c2 = fit_periodic_curve(Q, 30, 3)
    np.testing.assert_allclose(c2(0.0), c2(1.0), atol=1e-14)


# --------------------------------------------------------------------------- surfaces

def grid_points(nu=12, nv=9):
    u, v = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    return np.stack([2 * u, v + 0.1 * u, np.sin(3 * u) * np.cos(2 * v)], -1)


def test_surface_interpolation_through_grid():
    G = grid_points()
    s = interpolate_surface(G, 3, 3)
    tu = np.mean([parametrize(G[:, j]) for j in range(G.shape[1])], axis=0)
    tv = np.mean([parametrize(G[i]) for i in range(G.shape[0])], axis=0)
    np.testing.assert_allclose(s.grid(tu, tv), G, atol=SOLVE)


def test_surface_least_squares_error_falls_with_control_count():
    G = grid_points(30, 25)
    tu = np.mean([parametrize(G[:, j]) for j in range(G.shape[1])], axis=0)
    tv = np.mean([parametrize(G[i]) for i in range(G.shape[0])], axis=0)
    errs = []
    for n in ((5, 5), (8, 7), (14, 12)):
        s = approximate_surface(G, n, 3, 3)
        assert s.control_points.shape[:2] == n
        errs.append(np.max(np.linalg.norm(s.grid(tu, tv) - G, axis=-1)))
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-3
    with pytest.raises(ValueError, match="n_control must lie in"):
        approximate_surface(G, (40, 5))


def test_loft_through_compatible_sections():
    c1 = BSpline([[0, 0, 0], [1, 0, 1], [2, 0, 0]], 2)
    c2 = NURBS([[0, 1, 0], [1, 1, 2], [2, 1, 1], [3, 1, 0]], [1, 2, 1, 1], 3,
               [0, 0, 0, 0, 2, 2, 2, 2])
    c3 = Bezier([[0, 2, 0], [2, 2, 1], [3, 2, 0]])
    compat = make_compatible([c1, c2, c3])
    t = rng(3).uniform(0, 1, 200)
    for c, orig, scale in zip(compat, [c1, c2, c3], [1.0, 2.0, 1.0]):
        assert c.degree == 3
        np.testing.assert_allclose(c.knots, compat[0].knots, atol=0)
        np.testing.assert_allclose(c(t), orig(t * scale), atol=EXACT)
    s = loft([c1, c2, c3], degree_v=2)
    assert isinstance(s, NURBSSurface) and s.degree_v == 2
    # each section is an isocurve of the lofted surface
    np.testing.assert_allclose(s(t, np.zeros_like(t)), c1(t), atol=EXACT)
    np.testing.assert_allclose(s(t, np.ones_like(t)), c3(t), atol=EXACT)
    # the middle section sits at an interior v
    from scipy.optimize import minimize_scalar
    res = minimize_scalar(lambda v: np.abs(s(t[:20], np.full(20, v)) - c2(2 * t[:20])).max(),
                          bounds=(0, 1), method="bounded", options={"xatol": 1e-13})
    assert res.fun < 1e-9 and 0 < res.x < 1


def test_loft_point_sections_and_errors():
    th = np.linspace(0, np.pi, 15)
    S = np.stack([np.stack([np.cos(th), np.sin(th), np.full(15, z)], 1) * (1 + z)
                  for z in (0.0, 0.5, 1.0, 1.5)])
    s = loft(S, 3)
    assert isinstance(s, BSplineSurface)
    np.testing.assert_allclose(s(0.0, 0.0), S[0, 0], atol=EXACT)
    np.testing.assert_allclose(s(1.0, 1.0), S[-1, -1], atol=EXACT)
    with pytest.raises(ValueError, match="at least 2 sections"):
        loft([circle(1.0)])
    with pytest.raises(TypeError, match="sections\\[1\\] must be a Bezier, BSpline or NURBS"):
        loft([circle(1.0), lambda u: u])


def test_fit_periodic_surface_closes_at_seam_and_poles():
    r = lambda th, ph: 1.0 + 0.2 * np.cos(2 * th) * np.sin(ph) ** 2  # noqa: E731
    s, dev = fit_periodic_surface(r, n_control=(24, 14), samples=(96, 49))
    assert dev < 2e-3
    v = np.linspace(0, 1, 50)
    np.testing.assert_allclose(s(np.zeros(50), v), s(np.ones(50), v), atol=1e-13)
    u = np.linspace(0, 1, 50)
    south, north = s(u, np.zeros(50)), s(u, np.ones(50))
    assert np.ptp(south, axis=0).max() < 1e-14 and np.ptp(north, axis=0).max() < 1e-14
    np.testing.assert_allclose(north[0], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(south[0], [0, 0, -1], atol=1e-12)
    # outward normals (south pole at v = 0)
    uu, vv = rng(4).uniform(0.05, 0.95, (2, 100))
    assert np.all(np.einsum("nd,nd->n", s.normal(uu, vv), s(uu, vv)) > 0)
    with pytest.raises(ValueError, match="n_control\\[0\\] must lie in"):
        fit_periodic_surface(np.ones((10, 9)), n_control=(20, 5))


# --------------------------------------------------------------------------- projection

def test_projection_onto_circle_is_exact():
    P = rng(5).normal(size=(5000, 2)) * 2
    u, x, d = project_to_curve(circle(1.0, center=(0, 0)), P)
    np.testing.assert_allclose(d, np.abs(np.linalg.norm(P, axis=1) - 1), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(x, axis=1), 1.0, atol=1e-14 * 10)
    assert u.shape == (5000,) and x.shape == (5000, 2)


def test_projection_onto_curve_recovers_parameters():
    c = BSpline(rng(6).normal(size=(9, 3)), 3)
    t = rng(7).uniform(0, 1, 2000)
    u, x, d = project_to_curve(c, c(t))
    assert np.max(d) < 1e-12
    np.testing.assert_allclose(x, c(t), atol=1e-12)
    u0, x0, d0 = project_to_curve(ellipse(2.0, 1.0, center=(0, 0)), [3.0, 0.0])
    assert d0 == pytest.approx(1.0, abs=1e-12) and np.ndim(u0) == 0


def test_projection_onto_sphere_and_torus_is_exact():
    P = rng(8).normal(size=(4000, 3)) * 2
    uv, x, d = project_to_surface(sphere(1.0), P)
    np.testing.assert_allclose(d, np.abs(np.linalg.norm(P, axis=1) - 1), atol=1e-12)
    P = rng(9).normal(size=(4000, 3)) * [1.5, 1.5, 0.4]
    uv, x, d = project_to_surface(torus(2.0, 0.5), P)
    exact = np.abs(np.hypot(np.hypot(P[:, 0], P[:, 1]) - 2.0, P[:, 2]) - 0.5)
    np.testing.assert_allclose(d, exact, atol=1e-12)


def test_projection_along_normals_recovers_surface_parameters():
    g = np.stack(np.meshgrid(np.linspace(0, 1, 8), np.linspace(0, 1, 8), indexing="ij"), -1)
    net = np.concatenate([g, 0.2 * rng(10).random((8, 8, 1))], -1)
    s = BSplineSurface(net, 3, 3)
    uv0 = rng(11).uniform(0.02, 0.98, (3000, 2))
    base = s(uv0[:, 0], uv0[:, 1])
    off = 0.01 * rng(12).uniform(-1, 1, (3000, 1))
    P = base + off * s.normal(uv0[:, 0], uv0[:, 1])
    uv, x, d = project_to_surface(s, P)
    np.testing.assert_allclose(d, np.abs(off[:, 0]), atol=1e-12)
    np.testing.assert_allclose(uv, uv0, atol=1e-8)


def test_projection_beyond_the_boundary_lands_on_the_edge():
    s = BSplineSurface(np.stack(np.meshgrid([0.0, 1.0], [0.0, 1.0], indexing="ij")
                                + [np.zeros((2, 2))], -1), 1, 1)
    P = np.array([[2.0, 0.5, 1.0], [-1.0, -1.0, 0.0], [0.3, 0.4, -2.0]])
    uv, x, d = project_to_surface(s, P)
    np.testing.assert_allclose(uv, [[1.0, 0.5], [0.0, 0.0], [0.3, 0.4]], atol=1e-12)
    np.testing.assert_allclose(d, [np.sqrt(2.0), np.sqrt(2.0), 2.0], atol=1e-12)


def test_projection_errors():
    with pytest.raises(ValueError, match="points must have shape \\(n, 3\\)"):
        project_to_surface(sphere(1.0), np.zeros((4, 2)))
    with pytest.raises(TypeError, match="curve must be a Curve"):
        project_to_curve(sphere(1.0), np.zeros((4, 3)))
