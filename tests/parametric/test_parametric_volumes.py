"""Parametric solids: trivariate volumes, Jacobians, faces and mass properties."""

import numpy as np
import pytest

from parametric.tensor import NURBSSurface
from parametric.volumes import BezierVolume, BSplineVolume, NURBSVolume

EXACT = 1e-12
QUAD = 1e-12       # Gauss rule exact for polynomial maps (relative)
RATIONAL = 1e-11   # default rule on rational maps (relative)


def rng(seed=0):
    return np.random.default_rng(seed)


def cube_net(n=3, size=(1.0, 1.0, 1.0)):
    t = np.linspace(0.0, 1.0, n)
    return np.stack(np.meshgrid(t, t, t, indexing="ij"), -1) * np.asarray(size)


def box_inertia(a, b, c, m):
    return np.diag([m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12])


def test_unit_cube_map_volume_and_inertia():
    mp = BezierVolume(cube_net(3)).mass_properties()
    assert mp.volume == pytest.approx(1.0, rel=QUAD)
    np.testing.assert_allclose(mp.centroid, [0.5, 0.5, 0.5], atol=EXACT)
    np.testing.assert_allclose(mp.inertia, box_inertia(1, 1, 1, 1.0), atol=EXACT)


def test_box_with_warped_interior_parametrization():
    """Moving interior control points changes the map, not the box it fills."""
    a, b, c, rho = 2.0, 3.0, 5.0, 7.8
    net = cube_net(4, (a, b, c))
    net[1:3, 1:3, 1:3] += rng(1).uniform(-0.2, 0.2, (2, 2, 2, 3))
    vol = BezierVolume(net)
    assert np.all(vol.det_jacobian(*rng(2).uniform(0, 1, (3, 500))) > 0)
    mp = vol.mass_properties(density=rho)
    assert mp.volume == pytest.approx(a * b * c, rel=QUAD)
    assert mp.mass == pytest.approx(rho * a * b * c, rel=QUAD)
    np.testing.assert_allclose(mp.centroid, [a / 2, b / 2, c / 2], atol=1e-11)
    np.testing.assert_allclose(mp.inertia, box_inertia(a, b, c, rho * a * b * c),
                               atol=1e-11 * rho * a * b * c * c * c)


def test_parallelepiped_volume_is_determinant():
    A = np.array([[1.0, 0.3, 0.1], [0.0, 2.0, 0.4], [0.2, 0.0, 1.5]])
    net = cube_net(2) @ A.T + [1.0, -2.0, 3.0]
    mp = BSplineVolume(net, (1, 1, 1)).mass_properties()
    assert mp.volume == pytest.approx(abs(np.linalg.det(A)), rel=QUAD)
    np.testing.assert_allclose(mp.centroid, A @ [0.5, 0.5, 0.5] + [1.0, -2.0, 3.0], atol=EXACT)


def test_solid_cylinder_matches_closed_form():
    R, H, rho = 1.5, 2.0, 3.0
    mp = NURBSVolume.revolve_rectangle(0.0, R, 0.0, H).mass_properties(density=rho)
    V = np.pi * R * R * H
    m = rho * V
    assert mp.volume == pytest.approx(V, rel=RATIONAL)
    np.testing.assert_allclose(mp.centroid, [0, 0, H / 2], atol=1e-12)
    expected = np.diag([m * (3 * R * R + H * H) / 12] * 2 + [m * R * R / 2])
    np.testing.assert_allclose(mp.inertia, expected, atol=RATIONAL * m * (R * R + H * H))
    np.testing.assert_allclose(np.sort(mp.principal_moments), np.sort(np.diag(expected)),
                               rtol=1e-10)


def test_tube_volume_and_quadrature_convergence():
    vol = NURBSVolume.revolve_rectangle(1.0, 2.0, 0.0, 1.0)
    exact = np.pi * (4.0 - 1.0)
    errors = [abs(vol.mass_properties(n_gauss=n).volume - exact) for n in (2, 4, 8)]
    assert errors[0] > errors[1] > errors[2]
    assert vol.mass_properties().volume == pytest.approx(exact, rel=RATIONAL)


def test_evaluation_jacobian_and_faces():
    r = rng(3)
    net = cube_net(3) + r.uniform(-0.05, 0.05, (3, 3, 3, 3))
    vol = BSplineVolume(net, (2, 2, 2))
    u, v, w = r.uniform(0.05, 0.95, (3, 100))
    J = vol.jacobian(u, v, w)
    assert J.shape == (100, 3, 3)
    h = 1e-6
    fd = (vol(u + h, v, w) - vol(u - h, v, w)) / (2 * h)
    np.testing.assert_allclose(J[:, :, 0], fd, atol=1e-8)
    fd = (vol(u, v, w + h) - vol(u, v, w - h)) / (2 * h)
    np.testing.assert_allclose(J[:, :, 2], fd, atol=1e-8)
    faces = vol.boundary_surfaces()
    assert sorted(faces) == ["u0", "u1", "v0", "v1", "w0", "w1"]
    np.testing.assert_allclose(faces["u0"](v, w), vol(0.0, v, w), atol=EXACT)
    np.testing.assert_allclose(faces["v1"](u, w), vol(u, 1.0, w), atol=EXACT)
    np.testing.assert_allclose(faces["w1"](u, v), vol(u, v, 1.0), atol=EXACT)


def test_rational_volume_jacobian_and_faces():
    vol = NURBSVolume.revolve_rectangle(0.5, 1.0, 0.0, 2.0)
    r = rng(4)
    u, v, w = r.uniform(0.05, 0.95, (3, 50))
    p = vol(u, v, w)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 0.5 + 0.5 * u, atol=1e-14 * 10)
    J = vol.jacobian(u, v, w)
    h = 1e-6
    fd = (vol(u, v + h, w) - vol(u, v - h, w)) / (2 * h)
    np.testing.assert_allclose(J[:, :, 1], fd, atol=1e-7)
    face = vol.boundary_surfaces()["u1"]
    assert isinstance(face, NURBSSurface)
    q = face(v, w)
    np.testing.assert_allclose(np.hypot(q[:, 0], q[:, 1]), 1.0, atol=1e-14 * 10)


def test_volume_errors():
    with pytest.raises(ValueError, match="shape \\(n_u, n_v, n_w, 3\\)"):
        BSplineVolume(np.zeros((2, 2, 3)), (1, 1, 1))
    with pytest.raises(ValueError, match="degree 2 needs 3"):
        BSplineVolume(cube_net(2), (2, 1, 1))
    with pytest.raises(ValueError, match="density must be > 0"):
        BezierVolume(cube_net(2)).mass_properties(density=0)
    with pytest.raises(ValueError, match="u must lie in"):
        BezierVolume(cube_net(2))(1.5, 0.5, 0.5)
    with pytest.raises(ValueError, match="weights must be > 0"):
        NURBSVolume(cube_net(2), np.zeros((2, 2, 2)), (1, 1, 1))
