"""An extruded polygon's side split at its sharp corners: the same face to the user, an edge at every corner."""

import os
import runpy

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import extrude, polygon, rectangle
from implicit.facets import FacetField
from implicit.profile_facets import SHARP_TURN_DEGREES, polygon_runs, run_fields, run_groups
from spatial.fea.facets import FacetField as NamedFacets, solve_on_facets

GEAR = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "gear.py")


def _gear():
    return runpy.run_path(GEAR)


def _turns(v):
    e = np.roll(v, -1, axis=0) - v
    a = np.arctan2(e[:, 1], e[:, 0])
    return np.degrees((a - np.roll(a, 1) + np.pi) % (2 * np.pi) - np.pi)


def test_the_gear_side_is_cut_at_its_80_tooth_corners_into_four_facets_named_alike():
    model = _gear()
    gear = model["solid"]
    plain, split = NamedFacets(gear), NamedFacets(gear, split_sides=True)
    assert sorted(set(split.names)) == sorted(set(plain.names))            # the names the user sees
    assert split.names.count("extrude_0.side") == 4 and len(split.names) == len(plain.names) + 3
    v, starts = polygon_runs(model["gear_outline"]())
    assert starts.size == 80 and np.all(np.abs(_turns(v)[starts]) > SHARP_TURN_DEGREES)
    # the field, and the name of the deciding facet, are those of the unsplit tree everywhere
    p = np.random.default_rng(1).uniform(-24, 24, (4000, 3)) * [1, 1, 0.6] + [0, 0, 8]
    v0, d0, _ = plain(p)
    v1, d1, _ = split(p)
    np.testing.assert_array_equal(v0, v1)
    assert [plain.names[i] for i in d0] == [split.names[i] for i in d1]


def test_each_tooth_corner_is_the_common_zero_of_two_side_facets_and_a_cap():
    model = _gear()
    gear = model["solid"]
    ff = FacetField(gear, split_sides=True)
    v, starts = polygon_runs(model["gear_outline"]())
    corners = np.column_stack([v[starts], np.full(starts.size, 10.0)])      # on the top face z = 10
    _, _, fv = ff(corners)
    on = np.abs(fv) < 1e-9
    assert np.all(on.sum(axis=0) == 3)
    names = np.array(ff.names)
    for col in on.T:
        assert sorted(names[col]) == ["extrude_0.side", "extrude_0.side", "extrude_0.top"]
    # Gauss-Newton on those three facets, from 0.05 away, lands on the corner
    sets = np.array([np.flatnonzero(col) for col in on.T])
    start = corners + np.random.default_rng(2).normal(0, 0.05, corners.shape)
    np.testing.assert_allclose(solve_on_facets(ff, start, sets, iters=12), corners, atol=1e-6)


def test_closed_form_gradients_match_differences_of_the_facet_values():
    gear = _gear()["solid"]
    ff = FacetField(gear, split_sides=True)
    rng = np.random.default_rng(3)
    p = rng.uniform(-23, 23, (3000, 3)) * [1, 1, 0.4] + [0, 0, 5]
    _, dec, _ = ff(p)
    exact = ff.gradients_of(p, dec)
    numeric = ff.facet_gradients(p)[dec, np.arange(len(p))]
    close = np.linalg.norm(exact - numeric, axis=1) < 1e-5
    # only points within 1e-7 of a crease between two runs may differ
    assert close.mean() > 0.995
    np.testing.assert_allclose(np.linalg.norm(exact, axis=1), 1.0, atol=1e-9)


def test_a_rectangle_side_splits_into_the_four_faces_of_a_box():
    part = extrude(rectangle((4.0, 2.0)), 1.0)
    ff = FacetField(part, split_sides=True)
    assert ff.names == ["extrude_0.side"] * 4 + ["extrude_0.top", "extrude_0.bottom"]
    _, dec, fv = ff([[1.5, 0.3, 0.0], [0.5, 1.0, 0.2], [0.0, 0.0, 0.5]])
    assert dec.tolist() == [1, 2, 4]
    np.testing.assert_allclose(fv[:4, 0], [-1.3, -0.5, -0.7, -3.5])


def test_smooth_polygons_and_other_profiles_keep_one_side():
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    assert polygon_runs(np.column_stack([np.cos(t), np.sin(t)])) is None
    assert FacetField(extrude(polygon(np.column_stack([np.cos(t), np.sin(t)])), 1.0), split_sides=True).names == [
        "extrude_0.side", "extrude_0.top", "extrude_0.bottom"]


@pytest.mark.parametrize("count", [2, 3, 4, 5, 8, 9, 11, 80])
def test_neighbouring_runs_never_share_a_facet(count):
    g = run_groups(count)
    assert np.all(g != np.roll(g, 1)) and g.max() < 7
    if count >= 4:
        assert np.all(g != np.roll(g, 2))           # nor runs two apart: a tooth's two flanks


@settings(max_examples=25, deadline=None)
@given(n=st.integers(3, 9), seed=st.integers(0, 10_000))
def test_on_the_profile_the_nearest_run_is_zero_and_the_distance_is_the_profiles(n, seed):
    """A star-shaped polygon of random radii: the kernel's distance is the profile's own, and at
    points of its edges the facet of the nearest run is zero there."""
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    if np.diff(np.r_[ang, ang[0] + 2 * np.pi]).max() > 0.9 * np.pi:
        ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = rng.uniform(0.5, 2.0, n)
    prof = polygon(np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]))
    q = rng.uniform(-2.2, 2.2, (500, 2))
    runs = polygon_runs(prof._v)
    if runs is None:
        return
    v, starts = runs
    _, _, (_, d) = run_fields(v, starts, q, nearest=True)
    np.testing.assert_allclose(d, prof(q), atol=1e-12)
    t = rng.uniform(0, 1, (len(v), 1))
    on = v + t * (np.roll(v, -1, axis=0) - v)
    f, _, (near, _) = run_fields(v, starts, on, nearest=True)
    assert np.abs(f[near, np.arange(len(on))]).max() < 1e-12
