"""Features the lattice may lose whatever their faces: specks, slivers and gaps, found at the shell's extrema."""

import os
import sys
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import implicit as I
from spatial import mesh
from spatial.cells.lattice import make_lattice
from spatial.cells.specks import lost_feature
from spatial.meshing.boundary import boundary_cells_2h

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from speckparts import many_specks  # noqa: E402


def _messages(solid, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = mesh(solid, progress=False, **kw)
    return m, [str(w.message) for w in caught]


def _feature(solid, h):
    lat = make_lattice(solid, voxel_size=h)
    found = boundary_cells_2h(lat, False)
    return lost_feature(lat.solid, lat.origin, lat.voxel_size, found["cells"], found["centres"],
                        uniform=found["uniform"], uniform_parents=found["uniform_parents"])


# two plates 0.015 thick cut out of a box and the rest taken from a block: two gaps 0.015 thick
# inside the material, between faces of different boxes -- the tree knows boxes of 0.97 and more,
# the wall measurement walls of material, not gaps
_C = (0.013, 0.007, 0.011)
GAPS = I.box(2.0) - (I.box(1.0, center=_C) - I.box((1.2, 1.2, 0.97), center=_C))


def test_gaps_inside_the_material_are_named_with_the_voxel_that_keeps_them():
    h = 0.05
    m, said = _messages(GAPS, voxel_size=h)
    lost = [s for s in said if "the feature may be lost" in s]
    assert len(lost) == 1 and len(said) == 1, said
    assert "a thin gap" in lost[0] and "box_1" in lost[0] and "box_2" in lost[0]
    f = _feature(GAPS, h)
    assert f.kind == "gap"
    assert abs(f.thickness - 0.015) <= f.resolution
    # the point named lies in a gap (outside the solid, inside the outer box)
    assert float(GAPS(np.asarray([f.at]))[0]) > 0 and np.all(np.abs(f.at) < 1.0)
    assert f"voxel_size={f.thickness / 4:.4g} keeps it" in lost[0]
    # the mesh stays valid
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    from fuzzcheck import mesh_failures

    assert mesh_failures(m, h) == []


def test_no_feature_on_the_benchmark_part():
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples"))
    from benchmark_part import model

    for n in (48, 64, 100):
        assert _feature(model(), 1.5 / n) is None


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(["sphere", "box", "cylinder", "torus"]),
       shift=st.tuples(*[st.floats(-0.5, 0.5)] * 3), voxels=st.integers(8, 24))
def test_parts_the_lattice_resolves_have_no_feature(kind, shift, voxels):
    # a primitive four voxels or more through, anywhere on the lattice: no feature is lost
    h = 1.0 / voxels
    make = {"sphere": lambda: I.sphere(1.0), "box": lambda: I.box((2.0, 1.5, 1.0)),
            "cylinder": lambda: I.cylinder(0.5, 2.0), "torus": lambda: I.torus(0.8, 0.25)}[kind]
    solid = I.translate(make(), tuple(v * h for v in shift))
    if kind == "torus" and h > 0.5 * 0.25 / 2:
        return
    assert _feature(solid, h) is None


def test_a_speck_beside_a_body_is_found_where_it_is():
    # the intersection of three unit spheres leaves a speck about 0.06 thick and 0.3 across beside a
    # box: at a voxel of 0.1 the lattice holds a tenth of it at most
    speck = (I.sphere(1, (-0.96, 0.01, 2.02)) & I.sphere(1, (0.96, 0.01, 2.02))
             & I.sphere(1, (0.0, 0.97, 2.02)))
    f = _feature(I.box(1.0) | speck, 0.1)
    assert f is not None and f.kind == "material"
    assert f.thickness + f.resolution < 0.2
    assert np.linalg.norm(np.asarray(f.at) - (0.0, 0.05, 2.02)) < 0.3
    assert "sphere" in f.between


@pytest.mark.parametrize("seed", [1274, 3132])
def test_detection_costs_few_evaluations(seed):
    # the candidates come from the classification's values; only the neighbours of unknown sign and
    # the fine blocks of the candidates are sampled
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    from fuzzgen import random_case

    c = random_case(seed, resolutions=(16, 48), max_depth=5)
    lat = make_lattice(c.solid, voxel_size=c.voxel_size, bounds=c.bounds)
    found = boundary_cells_2h(lat, False)
    calls = []

    class Counting:
        lipschitz = lat.solid.lipschitz

        def __call__(self, p):
            calls.append(len(p))
            return lat.solid(p)

    f = lost_feature(Counting(), lat.origin, lat.voxel_size, found["cells"], found["centres"],
                     uniform=found["uniform"], uniform_parents=found["uniform_parents"])
    assert f is not None
    assert sum(calls) <= 4 * 17 ** 3


def test_specks_beyond_the_budget_are_counted_and_said():
    # 100 specks beside a box of 730 BOUNDARY cells: the budget (48) measures the shallowest 48, all lost,
    # and counts the other 52; a budget of 100 measures them all
    from spatial.cells import specks

    h = 0.1
    part = many_specks(h)
    lat = make_lattice(part, voxel_size=h)
    found = boundary_cells_2h(lat, False)
    m = found["cells"].shape[0]
    assert specks.candidate_budget(m) == specks.MIN_CANDIDATES == 48
    pts, side, depth = specks.speck_candidates(lat.solid, lat.origin, h, found["cells"], found["centres"],
                                               uniform=found["uniform"], uniform_parents=found["uniform_parents"])
    assert pts.shape[0] == 100 and np.all(side == 1)
    f = specks.examine(lat.solid, pts, side, depth, h, cells=m)
    assert (f.kind, f.count, f.unexamined) == ("material", 48, 52)
    assert f.examine_voxel == pytest.approx(h * np.sqrt(m / (100 * specks.CELLS_PER_CANDIDATE)))
    every = specks.examine(lat.solid, pts, side, depth, h, cells=m, budget=100)
    assert (every.count, every.unexamined) == (100, 0)
    # gathered in another order (brick by brick), the same answer
    perm = np.random.default_rng(0).permutation(100)
    assert specks.examine(lat.solid, pts[perm], side[perm], depth[perm], h, cells=m) == f
    # the mesh says so (the tree knows the spheres' walls, so the overflow is said on its own line)
    _, said = _messages(part, voxel_size=h)
    told = [s for s in said if "not examined" in s]
    assert len(told) == 1 and "52 candidates for a feature the lattice may lose not examined" in told[0], said
    assert f"voxel_size={f.examine_voxel:.4g} examines them" in told[0]


def test_a_budget_that_follows_the_surface_examines_them_all(monkeypatch):
    from spatial.cells import specks

    h = 0.1
    part = many_specks(h, n=60)
    lat = make_lattice(part, voxel_size=h)
    found = boundary_cells_2h(lat, False)
    monkeypatch.setattr(specks, "CELLS_PER_CANDIDATE", 4)
    assert specks.candidate_budget(found["cells"].shape[0]) > 60
    f = lost_feature(lat.solid, lat.origin, h, found["cells"], found["centres"], uniform=found["uniform"],
                     uniform_parents=found["uniform_parents"])
    assert (f.kind, f.count, f.unexamined) == ("material", 60, 0)
    # nothing lost among the examined but some left out: a feature of kind 'unexamined'
    pts = np.array([[3.0, 3.0, 3.0], [3.0, 3.0, 3.5]])
    u = specks.examine(I.box(1.0), pts, np.ones(2, np.int8), np.zeros(2), h, cells=10, budget=1)
    assert (u.kind, u.unexamined) == ("unexamined", 1)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        specks.warn_feature(u, h)
    assert "1 candidates for a feature the lattice may lose not examined" in str(said[0].message)


@pytest.mark.parametrize("which", ["gaps", "speck", "many", 1274, 3132])
def test_slabs_give_the_one_grid_candidates(which, monkeypatch):
    # a shell whose box holds more than DENSE_CELLS cells is searched slab by slab along x: the same
    # candidates in the same order, and the same feature, as one grid over the box
    from spatial.cells import specks, specks_kernels

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    from fuzzgen import random_case

    bounds = None
    if which == "gaps":
        solid, h = GAPS, 0.05
    elif which == "speck":
        solid, h = I.box(1.0) | (I.sphere(1, (-0.96, 0.01, 2.02)) & I.sphere(1, (0.96, 0.01, 2.02))
                                 & I.sphere(1, (0.0, 0.97, 2.02))), 0.1
    elif which == "many":
        solid, h = many_specks(0.1, n=20), 0.1
    else:
        c = random_case(which, resolutions=(16, 48), max_depth=5)
        solid, h, bounds = c.solid, c.voxel_size, c.bounds
    lat = make_lattice(solid, voxel_size=h, bounds=bounds)
    found = boundary_cells_2h(lat, False)
    args = (lat.solid, lat.origin, lat.voxel_size, found["cells"], found["centres"], found["uniform"],
            found["uniform_parents"])
    calls = []
    real = specks_kernels.extrema
    monkeypatch.setattr(specks_kernels, "extrema", lambda *a: calls.append(a[4].size) or real(*a))
    one = specks._candidates(*args)
    whole = len(calls)          # one grid: one search, and one more after sampling unknown neighbours
    feat = lost_feature(*args[:5], uniform=args[5], uniform_parents=args[6])
    assert one[0].size > 0 and whole <= 2
    dims = found["cells"].max(axis=0) - found["cells"].min(axis=0) + 3
    for planes in (1, 2, 5):
        # a grid of `planes` core planes and one on each side (the smallest, 1: a slab per plane)
        monkeypatch.setattr(specks, "DENSE_CELLS", int((planes + 2) * dims[1] * dims[2]))
        del calls[:]
        slabs = specks._candidates(*args)
        assert len(calls) > whole
        np.testing.assert_array_equal(slabs[0], one[0])
        np.testing.assert_array_equal(slabs[1], one[1])
        assert lost_feature(*args[:5], uniform=args[5], uniform_parents=args[6]) == feat


def test_a_plateau_of_candidates_is_one_and_only_unmeasured_plateaus_are_counted():
    # 100 candidates side by side (cells 2h apart) of one value: one plateau, measured first, nothing
    # left out; the same candidates at 100 values are 100 plateaus, 52 of them beyond the budget
    from spatial.cells import specks

    h = 0.1
    g = np.stack(np.meshgrid(np.arange(10), np.arange(10), indexing="ij"), -1).reshape(-1, 2) * 2 * h
    pts = np.column_stack([g, np.full(100, 3.0)])
    side = -np.ones(100, np.int8)
    assert specks._plateaus(pts, side, np.zeros(100), h).max() == 0
    assert specks.examine(I.box(1.0), pts, side, np.zeros(100), h, cells=100) is None
    depth = np.linspace(0, 0.01, 100)
    assert np.unique(specks._plateaus(pts, side, depth, h)).size == 100
    u = specks.examine(I.box(1.0), pts, side, depth, h, cells=100)
    assert (u.kind, u.unexamined) == ("unexamined", 52)
    # two plateaus: the second one's first member comes before the first one's second
    lab = np.array([0, 0, 0, 1, 1])
    np.testing.assert_array_equal(specks._rank_within(lab), [0, 1, 2, 0, 1])
    np.testing.assert_array_equal(specks._rank_within(np.array([1, 0, 1, 0])), [0, 0, 1, 1])
