"""The half-space method: an intersection of half-spaces knows its finite bounds."""

import numpy as np
import pytest

import implicit as I

CORNERS = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)


def tetrahedron(corners=CORNERS):
    planes = []
    for k in range(4):
        f = [corners[i] for i in range(4) if i != k]
        n = np.cross(f[1] - f[0], f[2] - f[0])
        if np.dot(n, corners[k] - f[0]) > 0:
            n = -n
        planes.append(I.halfspace(n, f[0]))
    return planes[0] & planes[1] & planes[2] & planes[3]


def test_tetrahedron_of_tilted_halfspaces_has_its_box():
    t = tetrahedron()
    lo, hi = t.bounds
    np.testing.assert_allclose(lo, -1, atol=1e-8)
    np.testing.assert_allclose(hi, 1, atol=1e-8)
    assert np.all(lo <= -1) and np.all(hi >= 1)         # conservative
    assert t.is_bounded
    shifted = tetrahedron(CORNERS * 0.5 + [3, 0, -2])
    np.testing.assert_allclose(shifted.bounds[0], [2.5, -0.5, -2.5], atol=1e-8)


def test_tetrahedron_meshes_and_measures_its_closed_form_volume():
    from spatial.analysis.mass import mass_properties
    from spatial.meshing.boundary import mesh

    t = tetrahedron()
    exact = abs(np.linalg.det(CORNERS[1:] - CORNERS[0])) / 6      # 8/3
    surface = mesh(t, resolution=24, progress=False)
    assert surface.n_cells > 0 and surface.volume == pytest.approx(exact, rel=0.02)
    p = mass_properties(t, resolution=32)
    assert abs(p.volume - exact) <= p.error.volume and abs(p.volume - exact) < 1e-3 * exact


def test_halfspace_cuts_a_box_and_unbounded_stays_unbounded():
    cut = I.box(2.0) & I.halfspace((1, 1, 0), (0, 0, 0))      # x + y <= 0 inside [-1, 1]^3
    lo, hi = cut.bounds
    np.testing.assert_allclose(lo, [-1, -1, -1], atol=1e-8)
    np.testing.assert_allclose(hi, [1, 1, 1], atol=1e-8)
    wedge = I.box(2.0) & I.halfspace((1, 0, 1), (0.5, 0, 0.5))  # x + z <= 1 leaves x, z up to 1
    assert wedge.bounds[1][0] == pytest.approx(1.0)
    two = I.halfspace((1, 1, 0)) & I.halfspace((-1, 1, 0))       # a dihedral wedge: unbounded
    assert not two.is_bounded
    apart = I.halfspace((1, 1, 1), (-1, -1, -1)) & I.halfspace((-1, -1, -1), (1, 1, 1))
    assert apart.is_empty_bounds
