"""2D profiles, extrusion and revolution."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree

from implicit import box, cylinder, sphere, torus
from implicit.sweeps import (
    Profile, circle, extrude, polygon, polygon_distance, rectangle, revolve, rotation_to_axis,
)

EXACT = 1e-12


def _dense_edges(vertices, per_edge=4000):
    v = np.asarray(vertices, float)
    w = np.roll(v, -1, axis=0)
    t = np.linspace(0, 1, per_edge, endpoint=False)[:, None, None]
    return (v + t * (w - v)).reshape(-1, 2)


def _inside_by_winding(points, vertices):
    """Point-in-polygon by the winding number (independent of the crossing rule)."""
    v = np.asarray(vertices, float)
    d = v[None, :, :] - points[:, None, :]
    ang = np.arctan2(d[..., 1], d[..., 0])
    step = np.diff(np.concatenate([ang, ang[:, :1]], axis=1), axis=1)
    step = (step + np.pi) % (2 * np.pi) - np.pi
    return np.abs(step.sum(axis=1)) > np.pi


STAR = [(np.cos(a) * r, np.sin(a) * r) for a, r in zip(np.linspace(0, 2 * np.pi, 10, endpoint=False),
                                                          [1.0, 0.4] * 5)]
COMB = [(0, 0), (3, 0), (3, 2), (2.5, 2), (2.5, 0.5), (2, 0.5), (2, 2), (1, 2), (1, 0.5), (0.5, 0.5), (0.5, 2), (0, 2)]


@pytest.mark.parametrize("verts", [STAR, COMB, COMB[::-1]], ids=["star", "comb", "comb_cw"])
def test_polygon_distance_matches_dense_edges_and_winding(verts):
    pts = np.random.default_rng(0).uniform(-1.5, 3.5, (3000, 2))
    d = polygon(verts)(pts)
    dense, _ = cKDTree(_dense_edges(verts)).query(pts)
    assert np.all(np.abs(d) <= dense + 1e-12)
    assert np.all(dense - np.abs(d) < 2e-3)
    np.testing.assert_array_equal(d < 0, _inside_by_winding(pts, verts))


def test_polygon_distance_closed_forms():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    np.testing.assert_allclose(polygon_distance(np.array([[0.5, 0.5], [2, 2], [0.5, -3], [1, 0.5]]), sq),
                               [-0.5, np.sqrt(2), 3, 0], atol=EXACT)


def test_rectangle_and_circle_profiles():
    r = rectangle((2, 1), center=(1, 0))
    np.testing.assert_allclose(r([[1, 0], [3, 0], [3, 1.5], [1.5, 0.25]]), [-0.5, 1, np.sqrt(2), -0.25], atol=EXACT)
    c = circle(2.0, center=(1, 1))
    np.testing.assert_allclose(c([[1, 1], [4, 5]]), [-2, 3], atol=EXACT)
    np.testing.assert_allclose(rectangle(2.0)([[0, 3]]), [2], atol=EXACT)


def test_profile_booleans_and_offset():
    ring = circle(1.0) - circle(0.5)
    np.testing.assert_allclose(ring([[0, 0], [0.75, 0], [2, 0]]), [0.5, -0.25, 1], atol=EXACT)
    both = circle(1.0) | circle(1.0, center=(3, 0))
    np.testing.assert_allclose(both([[3, 0], [1.5, 0]]), [-1, 0.5], atol=EXACT)
    lens = circle(1.0) & circle(1.0, center=(1, 0))
    assert lens([[0.5, 0]])[0] < 0 and lens([[-0.5, 0]])[0] > 0
    grown = rectangle(2.0).offset(0.5)
    np.testing.assert_allclose(grown([[2, 2]]), [np.sqrt(2) - 0.5], atol=EXACT)
    assert not both.exact and rectangle(1.0).exact
    lo, hi = both.bounds
    np.testing.assert_array_equal(lo, [-1, -1])
    np.testing.assert_array_equal(hi, [4, 1])


def test_profile_dict_round_trip_and_errors():
    prof = (circle(1.0) - rectangle((0.5, 0.2))).offset(0.1) | polygon([(2, 0), (3, 0), (2, 1)])
    again = Profile.from_dict(prof.to_dict())
    pts = np.random.default_rng(1).uniform(-2, 4, (500, 2))
    np.testing.assert_array_equal(again(pts), prof(pts))
    with pytest.raises(ValueError, match=r"profile\.children\[1\]\.radius: expected a positive number, got -1"):
        Profile.from_dict({"kind": "profile_union", "children": [{"kind": "circle"}, {"kind": "circle", "radius": -1}]})
    with pytest.raises(ValueError, match=r"profile\.kind: unknown profile kind 'oval'; known: circle"):
        Profile.from_dict({"kind": "oval"})


def test_rotation_to_axis_takes_z_to_the_axis():
    for axis in [(0, 0, 1), (0, 0, -1), (1, 0, 0), (1, 2, 3), (0, -1, 0)]:
        r = rotation_to_axis(axis)
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
        np.testing.assert_allclose(np.linalg.det(r), 1.0)
        np.testing.assert_allclose(r[:, 2], np.array(axis) / np.linalg.norm(axis), atol=1e-12)
    np.testing.assert_array_equal(rotation_to_axis((0, 0, 1)), np.eye(3))


# ---------------------------------------------------------------------------
# extrude
# ---------------------------------------------------------------------------

def test_extruded_circle_is_a_cylinder_and_rectangle_a_box():
    pts = np.random.default_rng(2).uniform(-3, 3, (4000, 3))
    np.testing.assert_allclose(extrude(circle(1.0), 2.0, axis=(1, 1, 0))(pts), cylinder(1.0, 2.0, axis=(1, 1, 0))(pts),
                               atol=1e-12)
    np.testing.assert_allclose(extrude(rectangle((2, 1)), 3.0, center=(0, 0, 1))(pts),
                               box((2, 1, 3), center=(0, 0, 1))(pts), atol=1e-12)
    assert extrude(circle(1.0), 2.0).exact


def test_extrude_closed_forms_near_the_rim():
    e = extrude(polygon([(0, 0), (1, 0), (0, 1)]), 2.0)
    # Outside the hypotenuse and above the top: sqrt(d2^2 + dz^2).
    p = np.array([[0.5 + 0.3 / np.sqrt(2), 0.5 + 0.3 / np.sqrt(2), 1.4]])
    np.testing.assert_allclose(e(p), [np.hypot(0.3, 0.4)], atol=EXACT)
    np.testing.assert_allclose(e([[0.1, 0.1, 0.95]]), [-0.05], atol=EXACT)


def test_extrude_bounds():
    e = extrude(rectangle((2, 1)), 4.0, center=(1, 2, 3), axis=(1, 0, 0))
    lo, hi = e.bounds
    np.testing.assert_allclose(lo, [-1, 1.5, 2], atol=1e-12)
    np.testing.assert_allclose(hi, [3, 2.5, 4], atol=1e-12)


# ---------------------------------------------------------------------------
# revolve
# ---------------------------------------------------------------------------

def test_revolved_circle_is_a_torus_and_rectangle_a_cylinder():
    pts = np.random.default_rng(3).uniform(-2, 2, (4000, 3))
    np.testing.assert_allclose(revolve(circle(0.25, center=(1, 0)), axis=(0, 1, 1))(pts),
                               torus(1.0, 0.25, axis=(0, 1, 1))(pts), atol=1e-12)
    np.testing.assert_allclose(revolve(rectangle((1, 2), center=(0.5, 0)))(pts), cylinder(1.0, 2.0)(pts), atol=1e-12)
    np.testing.assert_allclose(revolve(circle(1.0))(pts), sphere(1.0)(pts), atol=1e-12)


def test_profiles_with_an_edge_on_the_axis_have_no_axis_boundary():
    pts = np.random.default_rng(6).uniform(-2, 2, (4000, 3))
    from implicit import cone
    tri = revolve(polygon([(0, 0), (1, 0), (0, 1)]))
    assert tri.exact
    np.testing.assert_allclose(tri(pts), cone(1.0, 1.0)(pts), atol=1e-12)
    # A boolean touching the axis: the centre is deep inside, not on a boundary.
    grooved = revolve(rectangle((1, 2), center=(0.5, 0)) - circle(0.2, center=(1, 0)))
    np.testing.assert_allclose(grooved([[0, 0, 0], [0, 0, 0.9]]), [-0.8, -0.1], atol=1e-12)
    ball = revolve(circle(1.0))                     # symmetric about the axis
    np.testing.assert_allclose(ball(pts), sphere(1.0)(pts), atol=1e-12)
    # No exact meridian (an offset touching the axis): still a valid bound, marked so.
    rounded = revolve(rectangle((1, 1), center=(0.5, 0)).offset(0.0) | circle(0.2, center=(1.2, 0)))
    assert rounded.exact is False


def test_half_revolution_of_a_tube():
    half = revolve(circle(0.25, center=(1, 0)), 180)
    full = torus(1.0, 0.25)
    # In the kept half (y >= 0) and outside it: distance to the end discs.
    np.testing.assert_allclose(half([[0, 1, 0], [1, 0, 0], [-1, 0, 0]]), [-0.25, 0, 0], atol=EXACT)
    np.testing.assert_allclose(half([[1, -0.5, 0]]), [0.5], atol=EXACT)          # straight below the end disc
    np.testing.assert_allclose(half([[0, -1, 0]]), [np.hypot(0.75, 1)], atol=EXACT)  # disc rim at (+-0.75, 0, 0)
    pts = np.random.default_rng(4).uniform(-2, 2, (4000, 3))
    keep = pts[:, 1] >= 0
    np.testing.assert_allclose(half(pts)[keep & (full(pts) >= 0)], full(pts)[keep & (full(pts) >= 0)], atol=1e-12)


def test_partial_revolve_is_exact_outside_and_a_bound_inside():
    part = revolve(rectangle((0.5, 0.6), center=(0.75, 0)), 90)
    assert not part.exact
    # Cloud on the boundary from its analytic pieces: lateral surfaces, caps and end faces.
    rng = np.random.default_rng(5)
    n = 200000
    phi = rng.uniform(0, np.pi / 2, n)
    r = rng.uniform(0.5, 1.0, n)
    z = rng.uniform(-0.3, 0.3, n)
    side = rng.integers(0, 4, n)
    r = np.where(side == 0, 0.5, np.where(side == 1, 1.0, r))
    z = np.where(side == 2, 0.3, np.where(side == 3, -0.3, z))
    lateral = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    u = rng.uniform(0.5, 1.0, n)
    w = rng.uniform(-0.3, 0.3, n)
    ends = np.vstack([np.column_stack([u, 0 * u, w]), np.column_stack([0 * u, u, w])])
    cloud = np.vstack([lateral, ends])
    pts = rng.uniform(-1.3, 1.3, (4000, 3))
    dist, _ = cKDTree(cloud).query(pts)
    f = part(pts)
    assert np.all(np.abs(f) <= dist + 1e-9)
    outside = f > 0
    assert np.all(dist[outside] - f[outside] < 0.02)


@settings(derandomize=True, max_examples=20, deadline=None)
@given(angle=st.floats(10, 350), seed=st.integers(0, 2 ** 31))
def test_partial_revolve_sign_matches_the_angular_sector(angle, seed):
    part = revolve(circle(0.3, center=(1, 0)), angle)
    pts = np.random.default_rng(seed).uniform(-1.5, 1.5, (2000, 3))
    phi = np.degrees(np.mod(np.arctan2(pts[:, 1], pts[:, 0]), 2 * np.pi))
    inside_full = torus(1.0, 0.3)(pts) < 0
    want = inside_full & (phi < angle)
    got = part(pts) < 0
    assert np.all(got == want)


def test_revolve_bounds_and_errors():
    lo, hi = revolve(rectangle((1, 2), center=(1, 0)), center=(0, 0, 1)).bounds
    np.testing.assert_allclose(lo, [-1.5, -1.5, 0], atol=1e-12)
    np.testing.assert_allclose(hi, [1.5, 1.5, 2], atol=1e-12)
    with pytest.raises(ValueError, match=r"profile: expected a profile in the half-plane r >= 0"):
        revolve(circle(1.0, center=(0.5, 0)))
    with pytest.raises(ValueError, match=r"angle: expected degrees in \(0, 360\], got 400"):
        revolve(circle(0.2, center=(1, 0)), 400)
    with pytest.raises(TypeError, match="angle_degrees: expected a number"):
        revolve(circle(0.2, center=(1, 0)), "90")


def test_bad_profiles():
    with pytest.raises(ValueError, match="expected a simple polygon, but its edges cross"):
        polygon([(0, 0), (2, 0), (2, 2), (1, -1), (0, 2)])
    with pytest.raises(ValueError, match="zero area"):
        polygon([(0, 0), (1, 1), (2, 2)])
    with pytest.raises(ValueError, match=r"expected an \(m, 2\) array with m >= 3"):
        polygon([(0, 0), (1, 1)])
    with pytest.raises(ValueError, match="expected finite numbers"):
        polygon([(0, 0), (1, np.nan), (0, 1)])
    with pytest.raises(ValueError, match="vertex 1 repeats"):
        polygon([(0, 0), (1, 0), (1, 0), (0, 1)])
    with pytest.raises(ValueError, match="radius: expected a positive number, got 0"):
        circle(0)
    with pytest.raises(TypeError, match="operand 1 must be a Profile"):
        circle(1.0) | sphere(1.0)
    with pytest.raises(TypeError, match="profile: expected a Profile, got Sphere"):
        extrude(sphere(1.0), 1.0)
    with pytest.raises(ValueError, match="height: expected a positive number, got -1"):
        extrude(circle(1.0), -1)
    with pytest.raises(ValueError, match=r"points: expected an array of shape \(\.\.\., 2\)"):
        circle(1.0)([[0, 0, 0]])


def test_large_polygons_are_checked_quickly_and_capped():
    from implicit.sweeps import MAX_POLYGON_VERTICES
    a = np.linspace(0, 2 * np.pi, MAX_POLYGON_VERTICES, endpoint=False)
    ring = polygon(np.column_stack([np.cos(a), np.sin(a)]))          # sort-and-sweep: well under a second
    assert ring([[0.0, 0.0]])[0] == pytest.approx(-1.0, abs=1e-7)
    crossed = np.column_stack([np.cos(a), np.sin(a)])
    crossed[[10, 5000]] = crossed[[5000, 10]]                          # two far vertices swapped
    with pytest.raises(ValueError, match="edges cross"):
        polygon(crossed)
    b = np.linspace(0, 2 * np.pi, MAX_POLYGON_VERTICES + 1, endpoint=False)
    with pytest.raises(ValueError, match=rf"expected at most {MAX_POLYGON_VERTICES} vertices, got {MAX_POLYGON_VERTICES + 1}"):
        polygon(np.column_stack([np.cos(b), np.sin(b)]))
