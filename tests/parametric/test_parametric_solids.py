"""Solids from parametric curves, surfaces and volumes, against closed forms."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import (
    curve_profile, cylinder, extrude_curve, revolve_curve, sphere, surface_solid, sweep, thicken,
    torus, volume_solid,
)
from implicit.parametric_solids import (
    CurveProfile, SurfaceProjector, rotation_minimizing_frames, winding_number,
)
from implicit.serialize import from_json, to_json
from implicit.sweeps import circle, rectangle
from parametric.conics import arc, circle as nurbs_circle, ellipse
from parametric.curves import Bezier, BSpline
from parametric.tensor import BezierSurface, sphere as nurbs_sphere, torus as nurbs_torus
from parametric.volumes import NURBSVolume

#: Distances that should agree with a closed form up to rounding and Newton.
EXACT_TOL = 1e-9
#: Slack of the conservativeness check against a sampled surface.
SAMPLED_TOL = 1e-9

RNG = np.random.default_rng(20261122)
POINTS = RNG.uniform(-3.0, 3.0, (3000, 3))


def _rect_sdf(q, centre, half):
    d = np.abs(q - centre) - half
    return np.linalg.norm(np.maximum(d, 0.0), axis=-1) + np.minimum(d.max(axis=-1), 0.0)


def _tube_sdf(p, r0, r1, z0, z1):
    rz = np.stack([np.hypot(p[:, 0], p[:, 1]), p[:, 2]], axis=1)
    return _rect_sdf(rz, np.array([(r0 + r1) / 2, (z0 + z1) / 2]), np.array([(r1 - r0) / 2, (z1 - z0) / 2]))


def _rectangle_curve(r0, r1, z0, z1):
    return BSpline([[r0, z0], [r1, z0], [r1, z1], [r0, z1], [r0, z0]], 1)


# ---------------------------------------------------------------------------- curve profiles

def test_curve_profile_of_an_ellipse_matches_its_axes():
    prof = curve_profile(ellipse(2.0, 1.0, center=(0.0, 0.0)))
    got = prof(np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 2.5], [-2.0, 0.0]]))
    np.testing.assert_allclose(got, [-1.0, 1.0, 1.5, 0.0], atol=EXACT_TOL)


def test_curve_profile_sign_does_not_depend_on_orientation():
    ccw = _rectangle_curve(0.0, 2.0, 0.0, 1.0)
    cw = BSpline(np.asarray(ccw.control_points)[::-1], 1)
    q = RNG.uniform(-1.0, 3.0, (500, 2))
    np.testing.assert_allclose(curve_profile(ccw)(q), curve_profile(cw)(q), atol=EXACT_TOL)
    exact = _rect_sdf(q, np.array([1.0, 0.5]), np.array([1.0, 0.5]))
    np.testing.assert_allclose(curve_profile(cw)(q), exact, atol=EXACT_TOL)


def test_curve_profile_rejects_open_and_spatial_curves():
    with pytest.raises(ValueError, match="closed curve"):
        CurveProfile(Bezier([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]))
    with pytest.raises(ValueError, match="planar"):
        CurveProfile(nurbs_circle(1.0))
    with pytest.raises(TypeError, match="curve"):
        CurveProfile("circle")
    with pytest.raises(ValueError, match="samples"):
        CurveProfile(nurbs_circle(1.0, center=(0, 0)), samples=3)


# ---------------------------------------------------------------------------- revolve / extrude

def test_revolved_rectangle_curve_is_a_tube():
    tube = revolve_curve(_rectangle_curve(0.5, 1.5, -1.0, 1.0))
    np.testing.assert_allclose(tube(POINTS), _tube_sdf(POINTS, 0.5, 1.5, -1.0, 1.0), atol=EXACT_TOL)
    assert tube.exact


def test_revolved_rectangle_touching_the_axis_is_a_cylinder():
    solid = revolve_curve(_rectangle_curve(0.0, 1.0, -1.0, 1.0), axis=(1.0, 0.0, 0.0))
    f, exact = solid(POINTS), cylinder(1.0, 2.0, axis=(1, 0, 0))(POINTS)
    np.testing.assert_allclose(f[exact > 0], exact[exact > 0], atol=EXACT_TOL)
    # inside, the profile's edge on the axis counts as boundary: a bound, right sign
    assert np.all((f[exact < 0] < 0) & (f[exact < 0] >= exact[exact < 0] - EXACT_TOL))


def test_revolved_nurbs_circle_is_a_torus():
    ring = revolve_curve(nurbs_circle(0.5, center=(2.0, 0.0)))
    np.testing.assert_allclose(ring(POINTS), torus(2.0, 0.5)(POINTS), atol=EXACT_TOL)


def test_extruded_nurbs_circle_is_an_exact_cylinder():
    rod = extrude_curve(nurbs_circle(1.0, center=(0.0, 0.0)), 2.0, center=(0.1, 0.2, 0.3))
    np.testing.assert_allclose(rod(POINTS), cylinder(1.0, 2.0, center=(0.1, 0.2, 0.3))(POINTS), atol=EXACT_TOL)


def test_partial_revolution_is_a_bound_and_exact_outside():
    half = revolve_curve(_rectangle_curve(0.5, 1.5, -1.0, 1.0), angle_degrees=180.0)
    f = half(POINTS)
    full = _tube_sdf(POINTS, 0.5, 1.5, -1.0, 1.0)
    upper = POINTS[:, 1] > 0.05   # in the swept half, the field equals the full tube's
    np.testing.assert_allclose(f[upper & (full > 0)], full[upper & (full > 0)], atol=EXACT_TOL)
    assert np.all(f >= full - EXACT_TOL)
    with pytest.raises(TypeError, match="angle_degrees"):
        revolve_curve(nurbs_circle(0.5, center=(2.0, 0.0)), angle_degrees="90")


# ---------------------------------------------------------------------------- sweeps

def test_sweep_of_a_circle_along_a_line_is_a_cylinder():
    rod = sweep(circle(0.7), Bezier([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]))
    np.testing.assert_allclose(rod(POINTS), cylinder(0.7, 2.0)(POINTS), atol=EXACT_TOL)


def test_sweep_along_a_nurbs_circle_is_a_torus():
    ring = sweep(nurbs_circle(0.5, center=(0.0, 0.0)), nurbs_circle(2.0))
    np.testing.assert_allclose(ring(POINTS), torus(2.0, 0.5)(POINTS), atol=EXACT_TOL)


def test_sweep_of_a_rectangle_along_a_line_is_a_box():
    bar = sweep(rectangle((1.0, 0.6)), Bezier([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]))
    lo, hi = bar.bounds
    assert np.all(lo <= [-0.5, -0.3, -1.0]) and np.all(hi >= [0.5, 0.3, 1.0])
    got = bar(POINTS)
    # the frame starts at an arbitrary normal: compare with both orientations
    a = _rect_sdf(POINTS, np.zeros(3), np.array([0.5, 0.3, 1.0]))
    b = _rect_sdf(POINTS, np.zeros(3), np.array([0.3, 0.5, 1.0]))
    assert min(np.abs(got - a).max(), np.abs(got - b).max()) < EXACT_TOL


def _swept_surface_samples(profile_radius, path, n_path=400, n_ring=200):
    u = np.linspace(*path.domain, n_path)
    X, T = path(u), path.tangent(u)
    R = rotation_minimizing_frames(X, T)
    B = np.cross(T, R)
    th = np.linspace(0, 2 * np.pi, n_ring, endpoint=False)
    ring = (np.cos(th)[None, :, None] * R[:, None] + np.sin(th)[None, :, None] * B[:, None])
    side = (X[:, None] + profile_radius * ring).reshape(-1, 3)
    rr = np.linspace(0, profile_radius, 40)[:, None, None]
    caps = [(X[k] + rr * ring[k][None]).reshape(-1, 3) for k in (0, -1)]
    return np.concatenate([side] + caps)


def test_sweep_along_a_curved_path_is_conservative_where_documented():
    path = arc(2.0, 0.0, np.pi / 2, center=(0.0, 0.0, 0.0))     # curvature radius 2
    pipe = sweep(circle(0.4), path)                               # profile 0.4 < 2
    samples = _swept_surface_samples(0.4, path)
    from scipy.spatial import cKDTree

    q = RNG.uniform(-1.0, 3.0, (2000, 3))
    upper, _ = cKDTree(samples).query(q)                          # >= true distance
    f = pipe(q)
    assert np.all(np.abs(f) <= upper + SAMPLED_TOL)
    # and tight: within the sampling spacing of the surface
    assert np.max(upper - np.abs(f)) < 0.02
    # inside the tube's cross-sections the value is the pipe's exact distance
    on_path = path(np.linspace(0.3, 0.7, 50))
    np.testing.assert_allclose(pipe(on_path), -0.4, atol=EXACT_TOL)


def test_rotation_minimizing_frames_do_not_twist_along_a_helix():
    t = np.linspace(0.0, 4 * np.pi, 2000)
    X = np.stack([np.cos(t), np.sin(t), 0.3 * t], 1)
    T = np.stack([-np.sin(t), np.cos(t), np.full_like(t, 0.3)], 1)
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    R = rotation_minimizing_frames(X, T)
    np.testing.assert_allclose(np.einsum("ij,ij->i", R, T), 0.0, atol=1e-12)
    # rotation-minimizing: dr/ds has no component along b = t x r
    B = np.cross(T, R)
    dR = np.diff(R, axis=0)
    twist = np.abs(np.einsum("ij,ij->i", dR, B[:-1] + B[1:]) / 2)
    assert twist.max() < 1e-6
    # the Frenet frame of the helix twists: its torsion term is far from zero
    N = -np.stack([np.cos(t), np.sin(t), 0 * t], 1)
    assert np.abs(np.einsum("ij,ij->i", np.diff(N, axis=0), np.cross(T, N)[:-1])).max() > 1e-4


def test_sweep_rejects_a_planar_path():
    with pytest.raises(ValueError, match="3D curve"):
        sweep(circle(0.5), nurbs_circle(2.0, center=(0.0, 0.0)))
    with pytest.raises(TypeError, match="profile"):
        sweep(3.0, nurbs_circle(2.0))


# ---------------------------------------------------------------------------- surfaces

def test_thickened_plane_patch_is_a_slab():
    plate = BezierSurface([[[-2, -2, 0], [-2, 2, 0]], [[2, -2, 0], [2, 2, 0]]])
    slab = thicken(plate, 0.4)
    q = RNG.uniform(-1.5, 1.5, (2000, 3))
    np.testing.assert_allclose(slab(q), np.abs(q[:, 2]) - 0.2, atol=EXACT_TOL)
    # beyond the patch's edge: distance to the edge
    np.testing.assert_allclose(slab(np.array([[3.0, 0.0, 1.0]])), [np.hypot(1.0, 1.0) - 0.2], atol=EXACT_TOL)
    with pytest.raises(ValueError, match="thickness"):
        thicken(plate, -1.0)
    with pytest.raises(TypeError, match="surface"):
        thicken("plate", 0.1)


def test_nurbs_sphere_surface_gives_the_sphere_solid():
    ball = surface_solid(nurbs_sphere(2.0, center=(0.5, 0.0, 0.0)))
    np.testing.assert_allclose(ball(POINTS), sphere(2.0).translate((0.5, 0, 0))(POINTS), atol=EXACT_TOL)
    # points on the axis through the poles
    axis = np.array([[0.5, 0.0, z] for z in (-3.0, -1.0, 0.0, 1.0, 3.0)])
    np.testing.assert_allclose(ball(axis), [1.0, -1.0, -2.0, -1.0, 1.0], atol=EXACT_TOL)


def test_nurbs_torus_surface_gives_the_torus_solid():
    ring = surface_solid(nurbs_torus(2.0, 0.5))
    np.testing.assert_allclose(ring(POINTS), torus(2.0, 0.5)(POINTS), atol=EXACT_TOL)


def _box_faces(inward=False):
    c = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float) * 2 - 1
    quads = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 4, 5), (2, 3, 6, 7), (0, 2, 4, 6), (1, 3, 5, 7)]
    faces = []
    for q in quads:
        net = c[list(q)].reshape(2, 2, 3)
        normal = np.cross(net[1, 0] - net[0, 0], net[0, 1] - net[0, 0])
        if (np.dot(normal, net.mean(axis=(0, 1))) < 0) != inward:
            net = net[::-1]
        faces.append(BezierSurface(net))
    return faces


@pytest.mark.parametrize("inward", [False, True])
def test_box_of_six_patches_signs_edges_and_corners(inward):
    solid = surface_solid(_box_faces(inward))
    exact = _rect_sdf(POINTS, np.zeros(3), np.ones(3))
    np.testing.assert_allclose(solid(POINTS), exact, atol=EXACT_TOL)


def test_winding_number_of_a_tessellated_sphere():
    pts, tri = nurbs_sphere(1.0).tessellate(40, 40)
    w = winding_number(np.array([[0.0, 0.0, 0.0], [0.3, 0.2, -0.5], [2.0, 0.0, 0.0]]), pts[tri])
    np.testing.assert_allclose(w, [1.0, 1.0, 0.0], atol=1e-6)


def test_surface_projector_wraps_the_seam_and_reaches_the_poles():
    proj = SurfaceProjector(nurbs_sphere(1.0))
    assert proj.closed_u and not proj.closed_v
    q = np.array([[2.0, -1e-3, 0.1], [1e-3, 1e-3, 2.0], [0.0, 0.0, -0.5]])
    _, x, d = proj.project(q)
    np.testing.assert_allclose(d, np.abs(np.linalg.norm(q, axis=1) - 1.0), atol=EXACT_TOL)


def test_surface_solid_rejects_an_open_patch():
    with pytest.raises(ValueError, match="encloses no volume"):
        surface_solid(BezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]]))
    with pytest.raises(TypeError, match="closed_surface"):
        surface_solid([])


# ---------------------------------------------------------------------------- volumes

def test_volume_solid_of_a_revolved_rectangle_is_the_tube():
    tube = volume_solid(NURBSVolume.revolve_rectangle(0.5, 1.0, -1.0, 1.0))
    q = POINTS[:800]
    np.testing.assert_allclose(tube(q), _tube_sdf(q, 0.5, 1.0, -1.0, 1.0), atol=EXACT_TOL)
    uvw, inside = tube.invert(np.array([[0.75, 0.0, 0.0], [0.0, 0.75, 0.5], [0.0, 0.0, 0.0]]))
    assert inside.tolist() == [True, True, False]
    np.testing.assert_allclose(uvw[1], [0.5, 0.25, 0.75], atol=1e-9)


def test_volume_solid_drops_collapsed_and_seam_faces():
    rod = volume_solid(NURBSVolume.revolve_rectangle(0.0, 1.0, 0.0, 2.0))
    assert len(rod._projs) == 3           # outer side and two end discs
    q = POINTS[:600]
    np.testing.assert_allclose(rod(q), cylinder(1.0, 2.0, center=(0, 0, 1))(q), atol=EXACT_TOL)
    with pytest.raises(TypeError, match="volume"):
        volume_solid(nurbs_sphere(1.0))


# ---------------------------------------------------------------------------- laws

SOLIDS = {
    "revolve": lambda: revolve_curve(_rectangle_curve(0.5, 1.5, -1.0, 1.0)),
    "extrude": lambda: extrude_curve(ellipse(1.5, 1.0, center=(0.0, 0.0)), 2.0),
    "sweep": lambda: sweep(circle(0.4), arc(2.0, 0.0, np.pi / 2, center=(0.0, 0.0, 0.0))),
    "thicken": lambda: thicken(BezierSurface([[[-1, -1, 0], [-1, 1, 0.5]], [[1, -1, 0.5], [1, 1, 0]]]), 0.3),
    "surface": lambda: surface_solid(nurbs_torus(1.5, 0.5)),
    "volume": lambda: volume_solid(NURBSVolume.revolve_rectangle(0.5, 1.0, -1.0, 1.0)),
}
BUILT = {k: f() for k, f in SOLIDS.items()}


@pytest.mark.parametrize("name", sorted(SOLIDS))
def test_json_round_trip_evaluates_identically(name):
    solid = BUILT[name]
    again = from_json(to_json(solid))
    assert again.kind == solid.kind
    q = POINTS[:300]
    np.testing.assert_array_equal(again(q), solid(q))


@pytest.mark.parametrize("name", sorted(SOLIDS))
def test_bounds_hold_the_interior(name):
    solid = BUILT[name]
    lo, hi = solid.bounds
    assert np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))
    q = RNG.uniform(lo - 1.0, hi + 1.0, (4000, 3))
    inside = q[solid(q) < 0]
    assert inside.shape[0] > 10
    assert np.all(inside >= lo) and np.all(inside <= hi)


@settings(derandomize=True, max_examples=25, deadline=None)
@given(name=st.sampled_from(sorted(SOLIDS)),
       corner=st.tuples(*[st.floats(-2.5, 2.5)] * 3),
       size=st.floats(0.01, 1.5), seed=st.integers(0, 2 ** 16))
def test_value_bounds_are_conservative_on_random_boxes(name, corner, size, seed):
    solid = BUILT[name]
    lo = np.array(corner)
    hi = lo + size
    vmin, vmax = solid.value_bounds(lo[None], hi[None])
    q = np.random.default_rng(seed).uniform(lo, hi, (200, 3))
    f = solid(q)
    assert np.all(f >= vmin[0] - 1e-12) and np.all(f <= vmax[0] + 1e-12)


@settings(derandomize=True, max_examples=20, deadline=None)
@given(p=st.tuples(*[st.floats(-3.0, 3.0)] * 3))
def test_fields_never_exceed_the_true_distance(p):
    q = np.array([p])
    truths = {
        "revolve": _tube_sdf(q, 0.5, 1.5, -1.0, 1.0),
        "surface": torus(1.5, 0.5)(q),
        "volume": _tube_sdf(q, 0.5, 1.0, -1.0, 1.0),
    }
    for name, true in truths.items():
        got = BUILT[name](q)
        assert abs(got[0]) <= abs(true[0]) + EXACT_TOL
        assert np.sign(got[0]) == np.sign(true[0]) or abs(true[0]) < 1e-9


# ---------------------------------------------------------------------------- meshed volumes

def test_meshed_volumes_of_revolve_and_extrude_match_closed_forms():
    spatial = pytest.importorskip("spatial")
    mass_properties = pytest.importorskip("spatial.analysis.mass").mass_properties
    tube = revolve_curve(_rectangle_curve(0.5, 1.5, -1.0, 1.0))
    rod = extrude_curve(ellipse(1.5, 1.0, center=(0.0, 0.0)), 2.0)
    surface = spatial.mesh(tube, resolution=48)
    assert surface.n_cells > 0
    v_tube = np.pi * (1.5 ** 2 - 0.5 ** 2) * 2.0
    v_rod = np.pi * 1.5 * 1.0 * 2.0
    assert mass_properties(surface).volume == pytest.approx(v_tube, rel=5e-3)
    assert mass_properties(tube, resolution=48).volume == pytest.approx(v_tube, rel=1e-3)
    assert mass_properties(rod, resolution=48).volume == pytest.approx(v_rod, rel=1e-3)


def test_closed_path_frames_close_without_a_jump():
    # a closed, non-planar periodic path: the transported frame must be corrected to close
    t = 2 * np.pi * np.arange(12) / 12
    ctrl = np.stack([2 * np.cos(t), 2 * np.sin(t), 0.6 * np.sin(2 * t)], 1)
    path = BSpline.periodic(ctrl, 3)
    ring = sweep(rectangle((0.4, 0.2)), path)
    r0, b0, t0 = ring.frames(np.array([0.0]))
    r1, b1, t1 = ring.frames(np.array([1.0]))
    np.testing.assert_allclose(np.concatenate([r0, b0, t0]), np.concatenate([r1, b1, t1]), atol=1e-9)
    # the field is continuous across the seam
    c = path(0.0)
    q = c + np.array([[0.05, 0.0, 0.02]])
    assert ring.exact is False
    np.testing.assert_allclose(ring(q + [[0.0, 1e-7, 0.0]]), ring(q - [[0.0, 1e-7, 0.0]]), atol=1e-6)


def test_rectangle_swept_along_a_gentle_spatial_curve_is_conservative():
    from scipy.spatial import cKDTree

    path = Bezier([[0.0, 0.0, 0.0], [1.0, 0.5, 1.0], [2.0, -0.5, 2.0], [3.0, 0.0, 3.0]])
    bar = sweep(rectangle((0.3, 0.2)), path)
    u = np.linspace(0.0, 1.0, 600)
    r, b, _ = bar.frames(u)
    s = np.linspace(-1.0, 1.0, 41)
    ones = np.ones_like(s)
    rim = np.concatenate([np.stack([0.15 * s, 0.1 * ones], 1), np.stack([0.15 * s, -0.1 * ones], 1),
                          np.stack([0.15 * ones, 0.1 * s], 1), np.stack([-0.15 * ones, 0.1 * s], 1)])
    side = path(u)[:, None] + rim[None, :, :1] * r[:, None] + rim[None, :, 1:] * b[:, None]
    X, Y = np.meshgrid(0.15 * s, 0.1 * s, indexing="ij")
    caps = [path(k)[None] + X.reshape(-1, 1) * r[i] + Y.reshape(-1, 1) * b[i] for i, k in ((0, 0.0), (-1, 1.0))]
    tree = cKDTree(np.concatenate([side.reshape(-1, 3)] + caps))
    lo, hi = bar.bounds
    q = RNG.uniform(lo, hi, (3000, 3))
    upper, _ = tree.query(q)
    f = bar(q)
    assert np.all(np.abs(f) <= upper + SAMPLED_TOL)
    assert np.max((upper - np.abs(f))[f > 0]) < 0.05


def test_trilinear_bezier_volume_is_the_exact_box():
    from parametric.volumes import BezierVolume

    g = np.stack(np.meshgrid(*[np.array([0.0, 1.0])] * 3, indexing="ij"), -1)
    brick = volume_solid(BezierVolume(g * [2.0, 1.0, 0.5] + [-1.0, 0.0, 0.0]))
    q = RNG.uniform(-2.0, 2.0, (1500, 3))
    exact = _rect_sdf(q, np.array([0.0, 0.5, 0.25]), np.array([1.0, 0.5, 0.25]))
    np.testing.assert_allclose(brick(q), exact, atol=EXACT_TOL)
