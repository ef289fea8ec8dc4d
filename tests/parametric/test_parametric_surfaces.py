"""Conics and surfaces: exact NURBS shapes, Coons, bicubic and tensor-product patches."""

import numpy as np
import pytest

from parametric.conics import arc, circle, conic_arc, ellipse, hyperbola, parabola
from parametric.curves import Bezier, BSpline, NURBS
from parametric.surfaces import BicubicPatch, CoonsPatch, RuledSurface
from parametric.tensor import (BezierSurface, BSplineSurface, NURBSSurface, cylinder, sphere,
                               surface_of_revolution, torus)

EXACT = 1e-12
CONIC = 1e-14      # radius error of exact NURBS conics of unit size
FD = 1e-6

U_DENSE = np.linspace(0.0, 1.0, 100_001)


def rng(seed=0):
    return np.random.default_rng(seed)


UV = rng(7).uniform(0, 1, (2, 2000))


# --------------------------------------------------------------------------- conics

def test_circle_radius_is_exact_everywhere():
    p = circle(1.0)(U_DENSE)
    assert p.shape == (U_DENSE.size, 3)
    assert np.max(np.abs(np.linalg.norm(p, axis=1) - 1.0)) < CONIC
    assert np.max(np.abs(p[:, 2])) == 0.0


def test_circle_in_any_plane():
    c = circle(2.5, center=(1, 2, 3), normal=(1, 1, 1))
    p = c(U_DENSE) - [1, 2, 3]
    assert np.max(np.abs(np.linalg.norm(p, axis=1) - 2.5)) < 2.5 * CONIC * 10
    assert np.max(np.abs(p @ np.array([1, 1, 1]))) < 1e-13
    np.testing.assert_allclose(c(0.0), c(1.0), atol=0)


def test_circle_derivatives_are_tangent():
    c = circle(1.0, center=(0, 0))
    d = c.derivatives(UV[0], 2)
    # |C| = 1  =>  C . C' = 0  and  C . C'' = -|C'|^2 (exact rational derivatives, A4.2)
    assert np.max(np.abs(np.einsum("nd,nd->n", d[:, 0], d[:, 1]))) < EXACT
    lhs = np.einsum("nd,nd->n", d[:, 0], d[:, 2])
    rhs = -np.einsum("nd,nd->n", d[:, 1], d[:, 1])
    assert np.max(np.abs(lhs - rhs)) < 1e-10 * np.abs(rhs).max()


@pytest.mark.parametrize("sweep, segments", [(0.5, 1), (np.pi / 2, 1), (2.0, 2), (3.5, 3),
                                             (5.9, 4), (-1.0, 1)])
def test_arc_of_any_sweep(sweep, segments):
    a = arc(1.0, 0.2, sweep, center=(0, 0))
    assert a.control_points.shape[0] == 2 * segments + 1
    p = a(U_DENSE[::10])
    assert np.max(np.abs(np.linalg.norm(p, axis=1) - 1.0)) < CONIC * 10
    ang = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
    assert ang[0] == pytest.approx(0.2, abs=1e-14)
    assert ang[-1] - ang[0] == pytest.approx(sweep, abs=1e-13)
    assert np.all(np.diff(ang) * np.sign(sweep) > 0)
    np.testing.assert_allclose(a.weights[1::2], np.cos(sweep / segments / 2), atol=1e-15)


def test_ellipse_equation():
    p = ellipse(3.0, 2.0, center=(0, 0))(U_DENSE)
    assert np.max(np.abs(p[:, 0] ** 2 / 9 + p[:, 1] ** 2 / 4 - 1)) < 1e-14 * 10
    assert np.all(ellipse(3.0, 2.0, center=(0, 0)).weights[1::2] < 1)


def test_parabola_and_hyperbola_weights_and_equations():
    pa = parabola(2.0, (-1.0, 3.0))
    np.testing.assert_array_equal(pa.weights, [1, 1, 1])
    p = pa(U_DENSE)
    assert np.max(np.abs(p[:, 1] - 2.0 * p[:, 0] ** 2)) < 1e-13
    hy = hyperbola(2.0, 3.0, (-1.0, 2.0))
    assert hy.weights[1] == pytest.approx(np.cosh(1.5))
    assert hy.weights[1] > 1
    p = hy(U_DENSE)
    assert np.max(np.abs(p[:, 0] ** 2 / 4 - p[:, 1] ** 2 / 9 - 1)) < 1e-13
    np.testing.assert_allclose(p[0], [2 * np.cosh(-1), 3 * np.sinh(-1)], atol=1e-14)


def test_conic_weight_classifies_the_conic():
    # (1, w, 1) with w < 1 stays inside the parabola's arc, w > 1 outside (hyperbola)
    P0, P1, P2 = [-1.0, 1.0], [0.0, -1.0], [1.0, 1.0]
    mid = {w: conic_arc(P0, P1, P2, w)(0.5)[1] for w in (0.5, 1.0, 2.0)}
    assert mid[1.0] == pytest.approx(0.0)
    assert mid[0.5] > mid[1.0] > mid[2.0]
    with pytest.raises(ValueError, match="w must be > 0"):
        conic_arc(P0, P1, P2, 0.0)


def test_conic_errors():
    with pytest.raises(ValueError, match="radius must be > 0"):
        circle(0.0)
    with pytest.raises(ValueError, match="sweep_angle"):
        arc(1.0, 0.0, 7.0)
    with pytest.raises(ValueError, match="a and b must be > 0"):
        ellipse(1.0, -1.0)


# --------------------------------------------------------------------------- base contract

def test_surface_call_grid_shapes_and_domain_errors():
    s = sphere(1.0)
    assert s(0.3, 0.4).shape == (3,)
    assert s(np.zeros((4, 5)), 0.5).shape == (4, 5, 3)
    g = s.grid(np.linspace(0, 1, 7), np.linspace(0, 1, 9))
    assert g.shape == (7, 9, 3)
    U, V = np.meshgrid(np.linspace(0, 1, 7), np.linspace(0, 1, 9), indexing="ij")
    np.testing.assert_allclose(g, s(U, V), atol=EXACT)
    with pytest.raises(ValueError, match="v must lie in"):
        s(0.5, 1.5)
    with pytest.raises(ValueError, match="equal \\(broadcastable\\) shapes"):
        s(np.zeros(3), np.zeros(4))


def test_isoparametric_lines_and_tessellation():
    s = torus(2.0, 0.5)
    u_lines, v_lines = s.isoparametric_lines(step=0.1, samples=30)
    assert u_lines.shape == (11, 30, 3) and v_lines.shape == (11, 30, 3)
    np.testing.assert_allclose(u_lines[3], s(np.full(30, 0.3), np.linspace(0, 1, 30)),
                               atol=EXACT)
    pts, tris = s.tessellate(12, 10, merge_seams=False)
    assert pts.shape == (120, 3) and tris.shape == (2 * 11 * 9, 3)
    assert tris.dtype.kind == "i" and tris.max() == 119
    welded, wtris = s.tessellate(12, 10)  # both seams welded: 11 x 9 distinct points
    assert welded.shape == (99, 3) and wtris.shape == tris.shape and wtris.max() == 98
    np.testing.assert_allclose(welded[wtris], pts[tris], atol=EXACT)
    # triangle winding follows Su x Sv: outward on the torus
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    n = np.cross(b - a, c - a)
    centre = (a + b + c) / 3
    ring = centre.copy()
    ring[:, 2] = 0
    ring = 2.0 * ring / np.linalg.norm(ring, axis=1, keepdims=True)
    assert np.all(np.einsum("nd,nd->n", n, centre - ring) > 0)


# --------------------------------------------------------------------------- exact quadrics

def test_sphere_radius_exact_everywhere_and_normals():
    s = sphere(1.0)
    g = s.grid(np.linspace(0, 1, 317), np.linspace(0, 1, 317))
    assert np.max(np.abs(np.linalg.norm(g, axis=-1) - 1.0)) < CONIC
    p = s(UV[0], UV[1])
    assert np.max(np.abs(np.linalg.norm(p, axis=-1) - 1.0)) < CONIC
    inner = (UV[1] > 0.01) & (UV[1] < 0.99)
    np.testing.assert_allclose(s.normal(UV[0][inner], UV[1][inner]), p[inner], atol=1e-12)
    # rational surface derivatives (A4.4): S.Su = S.Sv = 0 and S.Suv = -Su.Sv
    d = s.derivatives(UV[0], UV[1], 2)
    dot = lambda a, b: np.einsum("nd,nd->n", a, b)  # noqa: E731
    assert np.max(np.abs(dot(d[:, 0, 0], d[:, 1, 0]))) < EXACT
    assert np.max(np.abs(dot(d[:, 0, 0], d[:, 0, 1]))) < EXACT
    assert np.max(np.abs(dot(d[:, 0, 0], d[:, 1, 1]) + dot(d[:, 1, 0], d[:, 0, 1]))) < 1e-10


def test_sphere_torus_cylinder_equations():
    s = sphere(2.0, center=(1, -1, 0.5))
    assert np.max(np.abs(np.linalg.norm(s(*UV) - [1, -1, 0.5], axis=-1) - 2.0)) < 1e-14 * 4
    p = torus(2.0, 0.5)(*UV)
    assert np.max(np.abs((np.hypot(p[:, 0], p[:, 1]) - 2) ** 2 + p[:, 2] ** 2 - 0.25)) < 1e-14 * 4
    p = cylinder(1.5, 2.0, center=(0, 0, 1))(*UV)
    assert np.max(np.abs(np.hypot(p[:, 0], p[:, 1]) - 1.5)) < 1e-14 * 4
    np.testing.assert_allclose(p[:, 2], 1.0 + 2.0 * UV[1], atol=1e-14)


def test_surface_of_revolution_of_a_line_is_a_cone():
    prof = BSpline([[1.0, 0.0, 0.0], [0.0, 0.0, 2.0]], 1)
    cone = surface_of_revolution(prof, axis=(0, 0, 1))
    p = cone(*UV)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 1.0 - p[:, 2] / 2.0, atol=1e-14)
    with pytest.raises(TypeError, match="profile must be a BSpline or NURBS"):
        surface_of_revolution(lambda u: u)


def test_partial_revolution_about_an_offset_axis():
    prof = NURBS([[0.0, 2.0, 0.0], [1.0, 2.0, 1.0], [2.0, 3.0, 0.0]], [1.0, 0.5, 1.0], 2)
    A, a = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    s = surface_of_revolution(prof, a, axis_point=A, angle=np.pi / 2)
    u, v = UV
    p = s(u, v)
    q = prof(v)
    # every point keeps its axial coordinate and its distance to the axis
    np.testing.assert_allclose(p[:, 0], q[:, 0], atol=1e-14 * 10)
    rad = lambda x: np.linalg.norm((x - A) - np.outer((x - A) @ a, a), axis=1)  # noqa: E731
    np.testing.assert_allclose(rad(p), rad(q), atol=1e-13)
    np.testing.assert_allclose(s(np.zeros_like(v), v), q, atol=1e-13)
    # a quarter turn counter-clockwise about +x maps (y - 1, z) to (-z, y - 1)
    end = s(np.ones_like(v), v)
    np.testing.assert_allclose(end[:, 1] - 1.0, -q[:, 2], atol=1e-13)
    np.testing.assert_allclose(end[:, 2], q[:, 1] - 1.0, atol=1e-13)


# --------------------------------------------------------------------------- tensor products

def random_surface(seed=0, rational=False, nu=7, nv=6, p=3, q=2):
    r = rng(seed)
    P = r.normal(size=(nu, nv, 3))
    ku = np.concatenate([np.zeros(p + 1), np.sort(r.uniform(0.1, 0.9, nu - p - 1)), np.ones(p + 1)])
    kv = np.concatenate([np.zeros(q + 1), np.sort(r.uniform(0.1, 0.9, nv - q - 1)), np.ones(q + 1)])
    if rational:
        return NURBSSurface(P, r.uniform(0.4, 2.5, (nu, nv)), p, q, ku, kv)
    return BSplineSurface(P, p, q, ku, kv)


@pytest.mark.parametrize("rational", [False, True])
def test_surface_editing_invariance(rational):
    s = random_surface(1, rational)
    u, v = UV
    edits = [s.insert_knot_u(0.37), s.insert_knot_u(0.55, 3), s.insert_knot_v(0.42, 2),
             s.refine_knots([0.05, 0.5, 0.5], [0.3, 0.81]), s.elevate_degree(1, 2)]
    for e in edits:
        assert type(e) is type(s)
        np.testing.assert_allclose(e(u, v), s(u, v), atol=EXACT)
    assert edits[-1].degree_u == 4 and edits[-1].degree_v == 4


@pytest.mark.parametrize("rational", [False, True])
def test_surface_derivatives_match_differences(rational):
    s = random_surface(2, rational)
    u, v = 0.05 + 0.9 * UV[:, :200]
    d = s.derivatives(u, v, 2)
    h = 1e-6
    fu = (s(u + h, v) - s(u - h, v)) / (2 * h)
    fv = (s(u, v + h) - s(u, v - h)) / (2 * h)
    np.testing.assert_allclose(d[:, 1, 0], fu, atol=FD * np.abs(fu).max())
    np.testing.assert_allclose(d[:, 0, 1], fv, atol=FD * np.abs(fv).max())
    fuv = (s.derivatives(u, v + h, 1)[:, 1, 0] - s.derivatives(u, v - h, 1)[:, 1, 0]) / (2 * h)
    np.testing.assert_allclose(d[:, 1, 1], fuv, atol=FD * np.abs(fuv).max())


def test_tensor_surface_end_interpolation_and_isocurves():
    s = random_surface(3, True)
    P = s.control_points
    np.testing.assert_allclose(s(0, 0), P[0, 0], atol=1e-14 * 10)
    np.testing.assert_allclose(s(1, 1), P[-1, -1], atol=1e-14 * 10)
    v = np.linspace(0, 1, 50)
    cu = s.isocurve_u(0.3)
    assert isinstance(cu, NURBS)
    np.testing.assert_allclose(cu(v), s(0.3, v), atol=EXACT)
    np.testing.assert_allclose(s.isocurve_v(0.8)(v), s(v, 0.8), atol=EXACT)
    np.testing.assert_allclose(s.to_nurbs()(*UV), s(*UV), atol=0)
    b = random_surface(4, False)
    np.testing.assert_allclose(b.to_nurbs()(*UV), b(*UV), atol=EXACT)


def test_bezier_surface_is_bernstein_tensor_product():
    P = rng(5).normal(size=(4, 3, 3))
    s = BezierSurface(P)
    u, v = UV[:, :50]
    from parametric.basis import bernstein
    expected = np.einsum("ni,ijd,nj->nd", bernstein(3, u), P, bernstein(2, v))
    np.testing.assert_allclose(s(u, v), expected, atol=EXACT)
    e = s.elevate_degree(1, 2)
    assert isinstance(e, BezierSurface) and e.control_points.shape[:2] == (5, 5)
    np.testing.assert_allclose(e(u, v), s(u, v), atol=EXACT)
    c = s.isocurve_u(0.25)
    np.testing.assert_allclose(c(v), Bezier(np.einsum("i,ijd->jd", bernstein(3, 0.25), P))(v),
                               atol=EXACT)


def test_tensor_surface_errors():
    with pytest.raises(ValueError, match="shape \\(n_u >= 2, n_v >= 2, dim\\)"):
        BSplineSurface(np.zeros((4, 3)), 2, 2)
    with pytest.raises(ValueError, match="too small for degrees"):
        BSplineSurface(np.zeros((3, 3, 3)), 3, 2)
    with pytest.raises(ValueError, match="weights must have shape"):
        NURBSSurface(np.zeros((3, 3, 3)), np.ones((3, 2)), 2, 2)


# --------------------------------------------------------------------------- Coons

def coons_boundaries():
    c0 = BSpline([[0, 0, 0], [1, 0, 1], [2, 0, 0]], 2)
    c1 = NURBS([[0, 2, 0], [1, 2, -1], [2, 2, 0.5]], [1, 2, 1], 2)
    d0 = Bezier([[0, 0, 0], [-0.5, 1, 0.5], [0, 2, 0]])
    d1 = lambda v: np.stack([2 + 0.3 * np.sin(np.pi * v), 2 * v, 0.5 * v ** 2], -1)  # noqa
    return c0, c1, d0, d1


@pytest.mark.parametrize("blend", ["linear", "cubic"])
def test_coons_reproduces_its_four_boundaries(blend):
    c0, c1, d0, d1 = coons_boundaries()
    s = CoonsPatch(c0, c1, d0, d1, blend=blend)
    t = np.linspace(0, 1, 301)
    np.testing.assert_allclose(s(t, 0.0), c0(t), atol=EXACT)
    np.testing.assert_allclose(s(t, 1.0), c1(t), atol=EXACT)
    np.testing.assert_allclose(s(0.0, t), d0(t), atol=EXACT)
    np.testing.assert_allclose(s(1.0, t), d1(t), atol=EXACT)


def test_coons_linear_formula_and_bilinear_case():
    # four straight edges of a skew quadrilateral: the Coons patch is the bilinear patch
    A, B, C, D = (np.array(x, float) for x in ([0, 0, 0], [2, 0, 1], [0, 3, 0.5], [2, 3, -1]))
    lin = lambda a, b: BSpline([a, b], 1)  # noqa: E731
    s = CoonsPatch(lin(A, B), lin(C, D), lin(A, C), lin(B, D))
    u, v = UV
    bil = ((1 - u) * (1 - v))[:, None] * A + (u * (1 - v))[:, None] * B \
        + ((1 - u) * v)[:, None] * C + (u * v)[:, None] * D
    np.testing.assert_allclose(s(u, v), bil, atol=EXACT)
    d = s.derivatives(u, v, 1)
    np.testing.assert_allclose(d[:, 1, 1], np.broadcast_to(A - B - C + D, (u.size, 3)), atol=EXACT)


def test_coons_corner_mismatch_names_the_corner():
    c0, c1, d0, _ = coons_boundaries()
    bad_d1 = BSpline([[2, 0, 0], [2, 2, 0.7]], 1)
    with pytest.raises(ValueError, match="corner p11 does not match"):
        CoonsPatch(c0, c1, d0, bad_d1)
    with pytest.raises(ValueError, match="blend must be"):
        CoonsPatch(*coons_boundaries(), blend="quintic")
    with pytest.raises(TypeError, match="c0 must be a curve or a callable"):
        CoonsPatch(1.0, c1, d0, bad_d1)


def test_ruled_surface():
    c0 = BSpline([[0, 0, 0], [1, 1, 0], [2, 0, 0]], 2)
    c1 = BSpline([[0, 0, 1], [2, 0, 1]], 1)
    s = RuledSurface(c0, c1)
    u, v = UV
    np.testing.assert_allclose(s(u, v), (1 - v)[:, None] * c0(u) + v[:, None] * c1(u), atol=EXACT)
    np.testing.assert_allclose(s.derivatives(u, v, 1)[:, 0, 1], c1(u) - c0(u), atol=EXACT)


# --------------------------------------------------------------------------- bicubic

def test_bicubic_passes_through_its_16_points():
    G = rng(6).normal(size=(4, 4, 3))
    t = np.linspace(0, 1, 4)
    np.testing.assert_allclose(BicubicPatch(G).grid(t, t), G, atol=EXACT)
    us, vs = [0.0, 0.2, 0.7, 1.0], [0.1, 0.3, 0.5, 0.95]
    np.testing.assert_allclose(BicubicPatch(G, us, vs).grid(us, vs), G, atol=1e-11)
    with pytest.raises(ValueError, match="u_params must be 4 distinct values"):
        BicubicPatch(G, [0, 0, 0.5, 1])
    with pytest.raises(ValueError, match="shape \\(4, 4, dim\\)"):
        BicubicPatch(G[:3])


def test_bicubic_reproduces_a_bicubic_polynomial_and_bezier_form():
    K = rng(7).normal(size=(4, 4, 3))
    exact = BicubicPatch.from_coefficients(K)
    t = np.linspace(0, 1, 4)
    fitted = BicubicPatch(exact.grid(t, t))
    np.testing.assert_allclose(fitted.coefficients, K, atol=1e-11)
    bez = BezierSurface(exact.bezier_control_points())
    np.testing.assert_allclose(bez(*UV), exact(*UV), atol=EXACT)
    np.testing.assert_allclose(exact.isocurve_u(0.3)(t), exact(0.3, t), atol=EXACT)
    np.testing.assert_allclose(exact.isocurve_v(0.6)(t), exact(t, 0.6), atol=EXACT)


def test_bicubic_hermite_corner_data():
    r = rng(8)
    P, Pu, Pv, Puv = (r.normal(size=(2, 2, 3)) for _ in range(4))
    s = BicubicPatch.hermite(P, Pu, Pv, Puv)
    cu = np.array([0.0, 1.0, 0.0, 1.0])
    cv = np.array([0.0, 0.0, 1.0, 1.0])
    d = s.derivatives(cu, cv, 1)
    idx = (cu.astype(int), cv.astype(int))
    np.testing.assert_allclose(d[:, 0, 0], P[idx], atol=EXACT)
    np.testing.assert_allclose(d[:, 1, 0], Pu[idx], atol=EXACT)
    np.testing.assert_allclose(d[:, 0, 1], Pv[idx], atol=EXACT)
    np.testing.assert_allclose(d[:, 1, 1], Puv[idx], atol=EXACT)
