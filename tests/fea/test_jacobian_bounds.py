"""Sign of the Jacobian determinant of 10-node elements: Bezier bounds against gmsh's minSICN
and against dense sampling."""

import warnings

import meshio
import numpy as np
import pytest

from implicit.families import instance
from spatial.fea import tet_mesh
from spatial.fea.curved import add_midnodes
from spatial.fea.jacobian_bounds import jacobian_sign
from spatial.fea.quality import _tet10_jacobians, scaled_jacobian


def _lattice(n):
    """Barycentric lattice points of degree n (faces and edges included), natural coordinates."""
    i, j, k = np.meshgrid(*[np.arange(n + 1)] * 3, indexing="ij")
    keep = (i + j + k) <= n
    return np.stack([i[keep], j[keep], k[keep]], axis=1) / n


@pytest.fixture(scope="module")
def bent():
    """A plate's quadratic mesh with mid-edge nodes pushed at random: a mix of valid and folded elements."""
    part = instance("hole_plate", length=40, width=20, thickness=4, hole_diameter=6, rows=1, cols=2, margin=10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = tet_mesh(part, size=3.0, order=1, allow_poor=True)
    p, t, _ = add_midnodes(m.points, m.tets)
    p = p.copy()
    p[len(m.points):] += np.random.default_rng(1).normal(scale=0.45, size=(len(p) - len(m.points), 3))
    return p, t


def test_straight_and_folded_single_elements():
    c = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    e = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    x = np.concatenate([c, 0.5 * (c[e[:, 0]] + c[e[:, 1]])])
    assert jacobian_sign(x, [np.arange(10)])[0] == 1
    assert jacobian_sign(x, [[0, 2, 1, 3, 6, 5, 4, 7, 9, 8]])[0] == -1  # inside out
    # a mid-edge node moved towards the opposite edge: corners and centre stay positive, an edge folds
    y = x.copy()
    y[9] = [0.0, 0.5, 0.5] + 0.9 * np.array([0.0, -0.5, -0.5]) + [0.4, 0, 0]
    dense = _tet10_jacobians(y[None], _lattice(12)).min()
    assert np.sign(dense) == jacobian_sign(y, [np.arange(10)])[0]


def test_the_sign_agrees_with_dense_sampling_and_catches_what_corners_and_centre_miss(bent):
    p, t = bent
    s = jacobian_sign(p, t)
    dense = _tet10_jacobians(p[t], _lattice(9)).min(axis=1)
    # negative proven only at a found point; positive proven by the bounds: never wrong either way
    assert np.all(dense[s == 1] > 0)
    late = np.nonzero((s == -1) & (dense >= 0))[0]  # folded between the points of this lattice
    if late.size:
        assert np.all(_tet10_jacobians(p[t[late]], _lattice(48)).min(axis=1) < 0)
    assert np.all(s[dense < 0] == -1)
    assert (s == 0).sum() <= 2
    sampled = _tet10_jacobians(p[t]).min(axis=1)
    missed = (sampled > 0) & (s == -1)
    assert missed.sum() > 10  # folds between the corners and the centre are common here
    assert np.all(scaled_jacobian(p, t)[s <= 0] <= 0) and np.all(scaled_jacobian(p, t)[s == 1] > 0)


def test_every_element_gmsh_finds_folded_is_flagged(bent, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    p, t = bent
    path = tmp_path / "bent.msh"
    meshio.write(path, meshio.Mesh(p, [("tetra10", t)]), file_format="gmsh22")
    gmsh.initialize(["-nopopup"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        _, tags, _ = gmsh.model.mesh.getElements(3)
        sicn = np.array(gmsh.model.mesh.getElementQualities(tags[0], "minSICN"))
    finally:
        gmsh.finalize()
    s = jacobian_sign(p, t)
    assert (sicn < 0).sum() > 100
    assert np.all(s[sicn < 0] == -1)
    # gmsh's minSICN is an estimate: where it says positive and the bounds say folded,
    # a point of negative Jacobian determinant exists (found on a fine lattice)
    differ = np.nonzero((sicn > 0) & (s == -1))[0]
    if differ.size:
        # (a fold can be thinner than a degree-24 lattice: one element of this plate needs 48)
        fine = _tet10_jacobians(p[t[differ]], _lattice(48)).min(axis=1)
        assert np.all(fine < 0)
    assert np.mean(np.sign(sicn) == s) > 0.97


def test_a_curved_plate_mesh_is_valid_everywhere_and_gives_up_few_surface_moves():
    part = instance("hole_plate", length=40, width=20, thickness=4, hole_diameter=6, rows=1, cols=2, margin=10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = tet_mesh(part, size=3.0, order=2, allow_poor=True)
    assert np.all(jacobian_sign(m.points, m.tets) == 1)
    # every boundary mid node on the surface (13 of 792 stayed off when a fold gave up the move of one
    # boundary mid node, 48 when it gave up all of them; interior mid nodes now make room)
    assert m.info["off_surface_nodes"] == 0
