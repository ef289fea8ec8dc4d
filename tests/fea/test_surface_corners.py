"""Every corner of the part is a node of the FEA surface (corners carried over from the feature mesh)."""

import os
import runpy

import numpy as np
import pytest
from scipy.spatial import cKDTree

from implicit import box
from spatial.fea.surface import surface_for_fea, surface_quality
from spatial.fea.surface_corners import exact_corners
from implicit.facets import FacetField
from spatial.meshing import mesh

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
# the L bracket of examples/bracket.py: legs 50 (along x) and 40 (along z), 4 thick, 30 wide
BRACKET_CORNERS = np.array([[x, y, z] for y in (0.0, 30.0) for x, z in
                            ((0, 0), (50, 0), (50, 4), (4, 4), (4, 40), (0, 40))], dtype=float)


@pytest.mark.parametrize("size", [1.5, 2.0])
def test_every_bracket_corner_is_a_node(size):
    solid = runpy.run_path(os.path.join(EXAMPLES, "bracket.py"))["solid"]
    s = surface_for_fea(solid, size=size)
    dist, _ = cKDTree(np.asarray(s.points)).query(BRACKET_CORNERS)
    assert dist.max() <= 1e-6 * size
    q = surface_quality(s, solid)
    assert q.closed and q.min_angle > 9.0


def test_exact_corners_of_a_feature_mesh():
    b = box((1.0, 2.0, 3.0))
    c = exact_corners(FacetField(b), mesh(b, resolution=12, features=True))
    # the box's corners, solved on its faces (not the feature vertices, kept inside their cells)
    want = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-1.0, 1.0) for z in (-1.5, 1.5)])
    assert c.shape == (8, 3)
    assert cKDTree(c).query(want)[0].max() < 1e-12
    plain = mesh(box(1.0), resolution=8, features=False)
    assert exact_corners(FacetField(box(1.0)), plain).shape == (0, 3)
