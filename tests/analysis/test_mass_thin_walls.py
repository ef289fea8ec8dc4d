"""Mass-property levels fine enough for a wall the tree does not know (a difference of two boxes)."""

import warnings

import numpy as np
import pytest

import implicit as I
from spatial.analysis import mass_properties
from spatial.cells.thickness import min_feature_size


def test_min_feature_size_reads_the_wall_a_difference_leaves():
    # the tree knows two boxes of 10; the field a wall 0.05 thick
    s = I.box(10) - I.box(10, center=(0.05, 0, 0))
    assert min_feature_size(s) == pytest.approx(0.05, rel=1e-3)
    assert min_feature_size(I.box((100.0, 100.0, 1.0)) | I.sphere(3.0)) == 1.0


def test_levels_for_the_wall_of_box_10_minus_box_10():
    # the levels are planned from the wall: the coarsest holds it (1.2 cells through), so no level
    # loses it; the moments are not computed here (a stub records the levels' voxels)
    from spatial.analysis.mass_core import WALL_CELLS

    s = I.box(10) - I.box(10, center=(0.05, 0, 0))
    hs = []

    def moments(solid, h, c0):
        hs.append(h)
        v = 0.5                          # any level: the same moments (no refinement asked)
        return np.array([v] + [0.0] * 13)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mass_properties(s, moments=moments, resolution=32)
    assert max(hs) <= 0.05 / WALL_CELLS * (1 + 1e-9)


def test_thin_wall_of_a_difference_meets_the_tolerance():
    # the slab [-0.5, -0.45] x [-0.5, 0.5]^2 of box(1) - box(1, center=(0.05, 0, 0)): the tree's
    # levels (32 cells across, 1.6 through the wall at the finest) lost it; the field's wall
    # raises them
    s = I.box(1) - I.box(1, center=(0.05, 0, 0))
    tol = 1e-3
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        mp = mass_properties(s, tolerance=tol)
    assert not [w for w in said if "may be lost" in str(w.message)]
    v = 0.05
    assert abs(mp.volume - v) <= tol * v
    assert mp.error.volume <= tol * v
    assert mp.centroid == pytest.approx([-0.475, 0.0, 0.0], abs=1e-4)
    assert np.diag(mp.inertia) == pytest.approx([v * 2 / 12, v * (1 + 0.05 ** 2) / 12, v * (1 + 0.05 ** 2) / 12],
                                                rel=5 * tol)
    assert "thinnest wall 0.05" in mp.method
