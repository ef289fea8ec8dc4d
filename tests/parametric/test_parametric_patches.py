"""Bicubically blended Coons patches, welded tessellations and robust projection."""

import numpy as np
import pytest

from parametric.curves import Bezier, BSpline
from parametric.surfaces import CoonsPatch
from parametric.tensor import BezierSurface

EXACT = 1e-12

T = np.linspace(0.0, 1.0, 201)
ZERO, ONE = np.zeros_like(T), np.ones_like(T)


def rng(seed=0):
    return np.random.default_rng(seed)


def bezier_frame(P):
    """Boundaries and cross-boundary derivative curves of a Bezier net (m+1, n+1, 3)."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    bounds = (Bezier(P[:, 0]), Bezier(P[:, -1]), Bezier(P[0]), Bezier(P[-1]))
    cross = (Bezier(n * (P[:, 1] - P[:, 0])), Bezier(n * (P[:, -1] - P[:, -2])),
             Bezier(m * (P[1] - P[0])), Bezier(m * (P[-1] - P[-2])))
    return bounds, cross


# --------------------------------------------------------------------------- bicubic Coons

def test_cubic_coons_reproduces_boundaries_and_given_cross_tangents():
    P = rng(1).normal(size=(5, 6, 3))
    surf = BezierSurface(P)
    (c0, c1, d0, d1), cross = bezier_frame(P)
    patch = CoonsPatch(c0, c1, d0, d1, blend="cubic", cross_tangents=cross)
    for u, v in ((T, ZERO), (T, ONE), (ZERO, T), (ONE, T)):
        got = patch.derivatives(u, v, 1)
        ref = surf.derivatives(u, v, 1)
        np.testing.assert_allclose(got[:, 0, 0], ref[:, 0, 0], atol=EXACT)
        np.testing.assert_allclose(got[:, 1, 0], ref[:, 1, 0], atol=EXACT)
        np.testing.assert_allclose(got[:, 0, 1], ref[:, 0, 1], atol=EXACT)
    np.testing.assert_allclose(patch.twists[0, 0], surf.derivatives(0.0, 0.0, 1)[1, 1],
                               atol=EXACT * 100)


def test_cubic_coons_reproduces_a_bicubic_surface_exactly():
    # the Boolean sum of cubic Hermite interpolants is exact on bicubic polynomials
    P = rng(2).normal(size=(4, 4, 3))
    surf = BezierSurface(P)
    bounds, cross = bezier_frame(P)
    patch = CoonsPatch(*bounds, blend="cubic", cross_tangents=cross)
    u, v = rng(3).uniform(0, 1, (2, 500))
    np.testing.assert_allclose(patch(u, v), surf(u, v), atol=EXACT)
    np.testing.assert_allclose(patch.derivatives(u, v, 2), surf.derivatives(u, v, 2),
                               atol=1e-10)
    # the linear Coons patch is not exact on it
    lin = CoonsPatch(*bounds)
    assert np.abs(lin(u, v) - surf(u, v)).max() > 1e-3


def test_cubic_coons_with_some_cross_tangents_estimates_the_others_compatibly():
    P = rng(4).normal(size=(4, 5, 3))
    surf = BezierSurface(P)
    bounds, cross = bezier_frame(P)
    patch = CoonsPatch(*bounds, blend="cubic", cross_tangents=(cross[0], None, cross[2], None))
    d = patch.derivatives(T, ZERO, 1)
    np.testing.assert_allclose(d[:, 0, 1], surf.derivatives(T, ZERO, 1)[:, 0, 1], atol=EXACT * 10)
    d = patch.derivatives(ZERO, T, 1)
    np.testing.assert_allclose(d[:, 1, 0], surf.derivatives(ZERO, T, 1)[:, 1, 0], atol=EXACT * 10)
    for u, v, ref in ((T, ONE, bounds[1]), (ONE, T, bounds[3])):
        np.testing.assert_allclose(patch(u, v), ref(T), atol=EXACT)
    # the estimated T1 meets the boundary tangents and takes the twists of E0 at p01
    d1 = patch.derivatives(np.array([0.0, 1.0]), np.array([1.0, 1.0]), 1)
    np.testing.assert_allclose(d1[:, 0, 1], [bounds[2].derivative(1.0), bounds[3].derivative(1.0)],
                               atol=EXACT * 10)
    np.testing.assert_allclose(d1[0, 1, 1], surf.derivatives(0.0, 1.0, 1)[1, 1], atol=1e-10)


def test_cubic_coons_without_cross_tangents_is_the_linear_patch():
    c0 = BSpline([[0, 0, 0], [1, 0, 1], [2, 0, 0]], 2)
    c1 = BSpline([[0, 2, 0], [1, 2, -1], [2, 2, 0]], 2)
    d0 = BSpline([[0, 0, 0], [0.3, 1, 0.5], [0, 2, 0]], 2)
    d1 = BSpline([[2, 0, 0], [2, 2, 0]], 1)
    cub = CoonsPatch(c0, c1, d0, d1, blend="cubic")
    lin = CoonsPatch(c0, c1, d0, d1)
    for u, v in ((T, ZERO), (T, ONE), (ZERO, T), (ONE, T)):
        np.testing.assert_allclose(cub.derivatives(u, v, 1)[:, :2, :2],
                                   lin.derivatives(u, v, 1)[:, :2, :2], atol=EXACT)
    # and the Boolean sum of Hermite projectors reproduces the linear patch from
    # its own boundary data: (I - Hu)(I - Hv) kills functions linear in u or v
    u, v = rng(5).uniform(0.0, 1.0, (2, 200))
    np.testing.assert_allclose(cub(u, v), lin(u, v), atol=EXACT)


def test_cubic_coons_errors():
    P = rng(6).normal(size=(4, 4, 3))
    bounds, cross = bezier_frame(P)
    with pytest.raises(ValueError, match="cross_tangents needs blend='cubic'"):
        CoonsPatch(*bounds, cross_tangents=cross)
    with pytest.raises(ValueError, match="must be 4 entries"):
        CoonsPatch(*bounds, blend="cubic", cross_tangents=cross[:3])
    off = Bezier(cross[0].control_points + [0.0, 0.0, 0.5])
    with pytest.raises(ValueError, match="cross_tangents T0 at corner p00"):
        CoonsPatch(*bounds, blend="cubic", cross_tangents=(off,) + cross[1:])
    # a T0 with the right end values but another slope at u = 0: twists disagree
    Q = cross[0].elevate_degree(2).control_points.copy()
    Q[1] += [0.0, 0.0, 1.0]
    bent = Bezier(Q)
    with pytest.raises(ValueError, match="give different twists at corner p00"):
        CoonsPatch(*bounds, blend="cubic", cross_tangents=(bent,) + cross[1:])
    with pytest.raises(TypeError, match="T1 must be a curve or a callable"):
        CoonsPatch(*bounds, blend="cubic", cross_tangents=(None, 3.0, None, None))


# --------------------------------------------------------------------------- welded tessellation

def edge_counts(tris):
    """Undirected edges (e, 2) with how many triangles use each, and directed edges."""
    directed = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    und, counts = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    return und, counts, directed


def enclosed_volume(pts, tris):
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    return float(np.einsum("nd,nd->n", a, np.cross(b, c)).sum() / 6.0)


@pytest.mark.parametrize("nu, nv", [(9, 5), (33, 17), (4, 3)])
def test_sphere_tessellates_to_a_closed_two_manifold(nu, nv):
    from parametric.tensor import sphere
    s = sphere(2.0, center=(1.0, 0.0, 0.0))
    pts, tris = s.tessellate(nu, nv)
    und, counts, directed = edge_counts(tris)
    assert pts.shape == ((nu - 1) * (nv - 2) + 2, 3)
    assert tris.shape == (2 * (nu - 1) * (nv - 2), 3)
    assert len(pts) - len(und) + len(tris) == 2             # Euler characteristic
    assert np.all(counts == 2)                              # closed, manifold edges
    assert np.unique(directed, axis=0).shape[0] == directed.shape[0]  # consistent winding
    assert np.all(np.isin(np.arange(len(pts)), tris))       # no unused vertex
    # no duplicate points and no zero-area triangle
    d = np.linalg.norm(pts[:, None] - pts[None], axis=-1) + np.eye(len(pts)) * 10
    assert d.min() > 1e-3
    area = np.linalg.norm(np.cross(pts[tris[:, 1]] - pts[tris[:, 0]],
                                   pts[tris[:, 2]] - pts[tris[:, 0]]), axis=1)
    assert area.min() > 1e-6
    assert enclosed_volume(pts - [1.0, 0.0, 0.0], tris) > 0  # outward normals


def test_torus_cylinder_and_open_patches_weld_by_topology():
    from parametric.tensor import BSplineSurface, cylinder, torus
    pts, tris = torus(2.0, 0.5).tessellate(17, 9)
    und, counts, _ = edge_counts(tris)
    assert pts.shape[0] == 16 * 8 and np.all(counts == 2)
    assert len(pts) - len(und) + len(tris) == 0
    pts, tris = cylinder(1.0, 2.0).tessellate(17, 5)
    und, counts, _ = edge_counts(tris)
    assert pts.shape[0] == 16 * 5 and np.sum(counts == 1) == 2 * 16  # two boundary loops
    assert len(pts) - len(und) + len(tris) == 0
    # an open patch is unchanged, and merge_seams=False keeps the raw grid
    net = rng(7).normal(size=(5, 4, 3))
    b = BSplineSurface(net, 3, 2)
    p1, t1 = b.tessellate(6, 7)
    p0, t0 = b.tessellate(6, 7, merge_seams=False)
    np.testing.assert_array_equal(p1, p0)
    np.testing.assert_array_equal(t1, t0)
    p0, t0 = cylinder().tessellate(5, 4, merge_seams=False)
    assert p0.shape == (20, 3) and t0.shape == (24, 3)


def test_periodic_surface_and_generic_surface_weld():
    from parametric.surfaces import Surface
    from parametric.tensor import BSplineSurface
    from parametric.basis import periodic_knots

    # a closed tube from a wrapped periodic B-spline: closed by its knots and net
    ang = np.linspace(0, 2 * np.pi, 6, endpoint=False)
    ring = np.stack([np.cos(ang), np.sin(ang), np.zeros(6)], -1)
    net = np.stack([ring + [0, 0, z] for z in (0.0, 1.0, 2.0)], axis=1)   # (6, 3, 3)
    net = np.concatenate([net, net[:3]])                                 # wrap 3
    tube = BSplineSurface(net, 3, 2, periodic_knots(6, 3), None)
    pts, tris = tube.tessellate(13, 4)
    assert pts.shape[0] == 12 * 4
    _, counts, _ = edge_counts(tris)
    assert np.sum(counts == 1) == 2 * 12

    class Cone(Surface):  # apex at v = 1, closed in u: decided from the sampled edges
        def _eval(self, u, v):
            a = 2 * np.pi * u
            return np.stack([(1 - v) * np.cos(a), (1 - v) * np.sin(a), v], -1)

    pts, tris = Cone().tessellate(9, 5)
    und, counts, _ = edge_counts(tris)
    assert pts.shape[0] == 8 * 4 + 1
    assert np.sum(counts == 1) == 8            # only the base circle is a boundary
    assert len(pts) - len(und) + len(tris) == 1  # a disc


# --------------------------------------------------------------------------- robust projection

def wavy_patch(amplitude=0.3):
    x = np.linspace(0, 1, 24)
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = amplitude * np.sin(6 * np.pi * X) * np.cos(5 * np.pi * Y)
    from parametric.tensor import BSplineSurface
    return BSplineSurface(np.stack([X, Y, Z], -1), 3, 3)


def test_projection_onto_a_wavy_patch_is_never_worse_than_a_dense_sample():
    from scipy.spatial import cKDTree
    from parametric.projection import project_to_surface
    s = wavy_patch()
    r = rng(0)
    P = np.concatenate([r.uniform(-0.2, 1.2, (3000, 2)), r.uniform(-1.5, 1.5, (3000, 1))], 1)
    uv, X, d = project_to_surface(s, P)
    t = np.linspace(0, 1, 600)
    dense, _ = cKDTree(s.grid(t, t).reshape(-1, 3)).query(P)
    assert np.all(d <= dense + 1e-9)
    np.testing.assert_allclose(X, s(uv[:, 0], uv[:, 1]), atol=EXACT)
    np.testing.assert_allclose(d, np.linalg.norm(X - P, axis=1), atol=EXACT)
    # a single seed is what used to be done: it stops in side valleys
    _, _, d1 = project_to_surface(s, P, seeds=1)
    assert np.sum(d1 > dense + 1e-9) > 0
    assert np.all(d <= d1 + 1e-12)


def test_projection_onto_a_wavy_curve_is_never_worse_than_a_dense_sample():
    from scipy.spatial import cKDTree
    from parametric.projection import project_to_curve
    x = np.linspace(0, 1, 40)
    c = BSpline(np.stack([x, 0.25 * np.sin(9 * np.pi * x)], -1), 3)
    r = rng(1)
    P = np.stack([r.uniform(-0.2, 1.2, 4000), r.uniform(-1.0, 1.0, 4000)], 1)
    dense, _ = cKDTree(c(np.linspace(0, 1, 200_001))).query(P)
    for samples in (None, 60, 100):  # coarse seed samples: about 13 per wave
        u, X, d = project_to_curve(c, P, samples=samples)
        assert np.all(d <= dense + 1e-9)
        np.testing.assert_allclose(X, c(u), atol=EXACT)
    u, X, d = project_to_curve(c, P, samples=60)
    _, _, d1 = project_to_curve(c, P, samples=60, seeds=1)
    assert np.sum(d1 > dense + 1e-9) > 0
    assert np.all(d <= d1 + 1e-12)


def test_projection_seed_argument_errors():
    from parametric.projection import project_to_curve, project_to_surface
    with pytest.raises(ValueError, match="seeds must be >= 1"):
        project_to_surface(wavy_patch(), [[0.5, 0.5, 1.0]], seeds=0)
    with pytest.raises(TypeError, match="seeds must be an int"):
        project_to_curve(BSpline([[0, 0], [1, 1]], 1), [[0.5, 0.0]], seeds=2.5)


def test_elevating_a_periodic_surface_direction_keeps_it_closed():
    from parametric import _ops
    from parametric.basis import periodic_knots
    from parametric.tensor import BSplineSurface
    ang = np.linspace(0, 2 * np.pi, 6, endpoint=False)
    ring = np.stack([np.cos(ang), np.sin(ang), np.zeros(6)], -1)
    net = np.stack([ring * (1 + 0.2 * z) + [0, 0, z] for z in (0.0, 1.0, 2.0)], axis=1)
    tube = BSplineSurface(np.concatenate([net, net[:3]]), 3, 2, periodic_knots(6, 3), None)
    up = tube.elevate_degree(1, 1)
    assert (up.degree_u, up.degree_v) == (4, 3)
    assert _ops.periodic_count(up.knots_u, 4, up.control_points) > 0
    u, v = rng(8).uniform(0, 1, (2, 300))
    np.testing.assert_allclose(up(u, v), tube(u, v), atol=EXACT)
    pts, tris = up.tessellate(13, 4)
    assert pts.shape[0] == 12 * 4  # still welded along the closed direction
