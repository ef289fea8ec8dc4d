"""A size graded over the part: fine in narrow gaps, thin walls and on curved faces, the size asked elsewhere."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from implicit import box, cylinder, sphere
from spatial.fea.graded import BAND_RATIO, SizeField, curvatures, graded_size_field, weighted_clusters
from spatial.fea.resolve import resolving_field
from spatial.fea.surface import surface_for_fea
from spatial.fea.surface_quality import _is_closed_manifold, mesh_faces, self_intersections


def test_size_field_grows_linearly_from_its_sources_and_stops_at_the_size():
    f = SizeField(4.0, [[0, 0, 0], [10, 0, 0]], [1.0, 0.5], growth=0.25)
    x = np.array([[0, 0, 0], [2, 0, 0], [5, 0, 0], [10, 0, 0], [10, 4, 0], [30, 0, 0]], float)
    # min(4, 1 + 0.25 |x - p0|, 0.5 + 0.25 |x - p1|), each source in its own band
    np.testing.assert_allclose(f(x), [1.0, 1.5, 1.75, 0.5, 1.5, 4.0])
    assert f.smallest == 0.5 and not f.uniform and SizeField(4.0).uniform


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_size_field_errs_finer_by_at_most_the_band_ratio(seed):
    rng = np.random.default_rng(seed)
    p, h = rng.uniform(-5, 5, (40, 3)), rng.uniform(0.2, 3.0, 40)
    x = rng.uniform(-8, 8, (200, 3))
    exact = np.minimum(3.0, (h[None, :] + 0.3 * np.linalg.norm(x[:, None] - p[None], axis=2)).min(axis=1))
    got = SizeField(3.0, p, h, growth=0.3)(x)
    assert np.all(got <= exact + 1e-12) and np.all(got >= exact / BAND_RATIO - 1e-12)
    # graded: neighbouring points differ by at most the growth times their distance
    y = x + rng.normal(scale=0.1, size=x.shape)
    fy = SizeField(3.0, p, h, growth=0.3)(y)
    assert np.all(np.abs(got - fy) <= 0.3 * np.linalg.norm(x - y, axis=1) + (BAND_RATIO - 1) * 3.0)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_size_field_searches_each_band_only_as_far_as_it_can_lower_the_size(seed):
    """The least over the bands, finest first with each point's reach, is bit for bit every band's
    nearest source within (size - h) / growth over every point."""
    rng = np.random.default_rng(seed)
    p, h = rng.uniform(-5, 5, (60, 3)), rng.uniform(0.2, 3.0, 60)
    x = np.concatenate([rng.uniform(-8, 8, (300, 3)), [[30.0, 0.0, 0.0]]])
    f = SizeField(3.0, p, h, growth=0.3).refined(rng.uniform(-5, 5, (5, 3)), rng.uniform(0.1, 2.0, 5))
    every = np.full(len(x), f.size)
    for hb, tree in f._bands:
        d, _ = tree.query(x, k=1, distance_upper_bound=(f.size - hb) / f.growth)
        every = np.minimum(every, hb + f.growth * d)
    np.testing.assert_array_equal(f(x), every)
    assert every.min() < 1.5 and every[-1] == 3.0


def test_curvatures_of_cylinder_sphere_and_plane_faces():
    part = box(10.0) - cylinder(2.0, 20.0) | sphere(1.5, center=(0.0, 0.0, 6.5))
    k = curvatures(part, [[2.0, 0, 0], [0, -2.0, 1.0], [5.0, 1.0, 0], [0, 0, 8.0]], 1e-3)
    np.testing.assert_allclose(k, [0.5, 0.5, 0.0, 1 / 1.5], rtol=1e-4, atol=1e-9)


def test_graded_field_of_a_slot_is_fine_in_the_slot_only():
    slot = box((20.0, 8.0, 8.0)) - box((1.0, 10.0, 10.0))         # a cut 1 wide across a bar 8 thick
    f = graded_size_field(slot, 2.0, voxel=0.25)
    assert f.smallest == pytest.approx(0.8, abs=0.02)              # GAP_FRACTION of the width
    near, far = f([[0.5, 0.0, 4.0], [9.9, 0.0, 4.0]])
    assert near < 1.0 and far == 2.0
    # a wall under 2.5 sizes thick is refined too: WALL_FRACTION of its thickness
    bar = graded_size_field(box((20.0, 3.0, 8.0)), 2.0, voxel=0.25)
    assert bar([[0.0, 1.5, 0.0]])[0] == pytest.approx(0.4 * 3.0, rel=0.02)


def test_weighted_clusters_give_a_closed_graded_surface():
    slot = box((20.0, 8.0, 8.0)) - box((1.0, 10.0, 10.0))
    f = graded_size_field(slot, 2.0, voxel=0.25)
    s = surface_for_fea(slot, size=f.smallest, size_field=f)
    faces = mesh_faces(s)
    assert _is_closed_manifold(faces) and self_intersections(s) == 0
    p = np.asarray(s.points)
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    length = np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1)
    mid = 0.5 * (p[e[:, 0]] + p[e[:, 1]])
    slot_side = np.abs(mid[:, 0]) < 1.5
    far = np.abs(mid[:, 0]) > 8.0
    assert np.median(length[slot_side]) < 1.0 and np.median(length[far]) > 1.5


def test_the_pyacvd_weights_are_set_on_area_and_centroid():
    import pyvista as pv

    src = pv.Sphere(radius=1.0, theta_resolution=30, phi_resolution=30).triangulate().clean()
    f = SizeField(0.5, [[0.0, 0.0, 1.0]], [0.1], growth=0.3)
    clus, nclus = weighted_clusters(src, 0.5, f)
    w = (0.5 / f(np.asarray(clus.mesh.points))) ** 2
    # centroid of each point's weight = the point itself, whatever its weight
    np.testing.assert_allclose(clus.wcent / np.ravel(clus.area)[:, None], clus.mesh.points, atol=1e-6)
    assert np.ravel(clus.area).max() / np.ravel(clus.area).min() > 0.5 * w.max() / w.min()
    assert nclus > 1.1547 * 4 * np.pi / 0.25


def test_resolving_field_only_where_a_gap_needs_it_and_refuses_only_past_a_fifth():
    from implicit import extrude, polygon

    slot = extrude(polygon([[0, 0], [10, 0], [10, 10], [6, 10], [6, 2], [4, 2], [4, 10], [0, 10]]), 5.0)
    assert resolving_field(slot, 1.5) is None                      # 1.8 of the gap of 2 resolves it
    f = resolving_field(slot, 4.0)
    # the gap of 2 asks for 1.6, the wall of 2 under it for 0.8 (WALL_FRACTION 0.4)
    assert f.size == 4.0 and f.smallest == pytest.approx(0.8, abs=0.02)
    assert f([[4.0, 6.0, 2.5]])[0] == pytest.approx(1.65, abs=0.1)      # on the side of the gap
    with pytest.raises(ValueError, match=r"size: 9 cannot follow a gap 1.97 wide .* the largest size that resolves it is 7.9$"):
        resolving_field(slot, 9.0)
