"""The lost-feature and thin-wall warnings of the cluster mesher are the single-process ones.

The bricks find their candidates on the workers; the client measures them together (the same budget,
thinnest feature and count as one process).  A LocalCluster of two worker processes on loopback.
"""

import os
import sys
import warnings

import pytest

import implicit as I

distributed = pytest.importorskip("distributed")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))


@pytest.fixture(scope="module")
def client():
    from spatial.distributed import local_cluster

    with local_cluster(2) as cluster, distributed.Client(cluster) as c:
        yield c


def _said(solid, **kw):
    import spatial

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = spatial.mesh(solid, progress=False, features=False, **kw)
    return m, sorted(str(w.message) for w in caught if issubclass(w.category, RuntimeWarning))


@pytest.mark.parametrize("seed", [1274, 3132, 3370, 5071])
def test_regression_specks_are_announced_as_in_one_process(seed, client):
    from fuzzgen import random_case

    case = random_case(seed, resolutions=(16, 48), max_depth=5)
    kw = dict(voxel_size=case.voxel_size, bounds=case.bounds)
    one, ref = _said(case.solid, **kw)
    # lattices of 8-15 voxels: one brick (a lattice of 8 is classified whole, as in one process)
    out, got = _said(case.solid, client=client, brick=32, **kw)
    lost = [s for s in ref if "the feature may be lost" in s]
    assert len(lost) == 1, ref
    assert got == ref
    assert out.n_cells == one.n_cells


_SPECK = I.sphere(1, (-0.96, 0.01, 2.02)) & I.sphere(1, (0.96, 0.01, 2.02)) & I.sphere(1, (0.0, 0.97, 2.02))
_C = (0.013, 0.007, 0.011)


@pytest.mark.parametrize("name, solid, h", [
    ("speck beside a box", I.box(1.0) | _SPECK, 0.1),
    ("two gaps in a block", I.box(2.0) - (I.box(1.0, center=_C) - I.box((1.2, 1.2, 0.97), center=_C)), 0.05),
])
def test_features_found_across_many_bricks_are_the_single_process_ones(name, solid, h, client):
    from spatial.distributed.plan import plan_bricks

    assert plan_bricks(solid, voxel_size=h, brick=16, block=16).bricks.shape[0] >= 5
    _, ref = _said(solid, voxel_size=h)
    _, got = _said(solid, voxel_size=h, client=client, brick=16, block=16)
    # the speck: its lens-shaped wall, measured on the field; the gaps: the lost-feature warning
    assert len([s for s in ref if "may be lost" in s]) == 1, ref
    assert got == ref


def test_thin_wall_measured_on_the_field_is_announced_on_the_cluster(client):
    # a wall 0.05 thick left by a difference: the tree knows boxes of 10 only; the field's walls know it
    slab = I.box(10) - I.box(10, center=(0.05, 0, 0))
    _, ref = _said(slab, voxel_size=0.2)
    _, got = _said(slab, voxel_size=0.2, client=client, brick=32)
    thin = [s for s in got if "the wall may be lost" in s]
    assert len(thin) == 1 and "box_0.-x and box_1.-x" in thin[0] and "voxel_size=0.0125 keeps it" in thin[0]
    assert got == ref


def test_specks_beyond_the_budget_are_counted_on_the_cluster(client, tmp_path):
    from speckparts import many_specks

    from spatial.distributed.plan import plan_bricks

    part = many_specks(0.1)
    # the 100 candidates come from many bricks and are measured together: the same 48 and 52 as one process
    assert plan_bricks(part, voxel_size=0.1, brick=16, block=16).bricks.shape[0] > 8
    _, ref = _said(part, voxel_size=0.1)
    _, got = _said(part, voxel_size=0.1, client=client, brick=16, block=16)
    assert any("52 candidates for a feature the lattice may lose not examined" in s for s in ref), ref
    assert got == ref
    # written as parts, the same warnings
    index = str(tmp_path / "specks.pvtp")
    import spatial

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        parts = spatial.mesh(part, voxel_size=0.1, client=client, brick=16, block=16, parts=index, progress=False)
    assert sorted(str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)) == ref
    assert all("specks" not in b for b in parts.bricks)


def test_no_warning_on_the_benchmark_part(client):
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples"))
    from benchmark_part import model

    _, got = _said(model(), resolution=64, client=client, brick=32)
    assert got == []
