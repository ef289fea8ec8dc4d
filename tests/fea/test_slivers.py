"""The sliver pass after TetGen: edge removal (3-2, 4-4, 2-2 on planar boundary), edge splits, and
the whole repair on meshes built with slivers (Delaunay meshes of a jittered lattice)."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import Delaunay

from spatial.fea.model import SIDE_NODES
from spatial.fea.quality import dihedral_angles, gamma, tet_volumes
from spatial.fea.sliver_flips import longest_interior_edges, remove_edges, remove_slivers, split_edges
from spatial.fea.slivers import boundary_faces, element_score


def _lattice(seed, n=5, jitter=1e-3):
    """Delaunay mesh of an n^3 lattice in the unit cube, each coordinate strictly inside (0, 1) jittered:
    the eight corners of each lattice cube are nearly cospherical, so the mesh is full of slivers."""
    rng = np.random.default_rng(seed)
    g = np.linspace(0.0, 1.0, n)
    p = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    free = (p > 0) & (p < 1)
    p = p + np.where(free, rng.normal(scale=jitter, size=p.shape), 0.0)
    t = Delaunay(p).simplices.astype(np.int64)
    neg = tet_volumes(p, t) < 0
    t[neg] = t[neg][:, [0, 2, 1, 3]]
    return p, t, free.all(axis=1)


def _faces(tets):
    """Every side as a sorted triple, with how many elements hold it."""
    f = np.sort(tets[:, SIDE_NODES].reshape(-1, 3), axis=1)
    return np.unique(f, axis=0, return_counts=True)


def _assert_conforming(points, tets, volume):
    assert (tet_volumes(points, tets) > 0).all()
    assert tet_volumes(points, tets).sum() == pytest.approx(volume, rel=1e-12)
    _, counts = _faces(tets)
    assert counts.max() <= 2  # no side in three elements: no overlap, no hanging node
    bf = np.sort(boundary_faces(tets)[0], axis=1)
    # The boundary closed: every boundary edge in exactly two boundary sides.
    e = np.sort(np.concatenate([bf[:, [0, 1]], bf[:, [1, 2]], bf[:, [0, 2]]]), axis=1)
    _, ecount = np.unique(e, axis=0, return_counts=True)
    assert (ecount == 2).all()


def test_three_needles_around_an_edge_become_two_elements():
    # Three elements around the edge (0, 0, +-1), far vertices on a small triangle: 3-2 flip.
    p = np.array([[0, 0, -1], [0, 0, 1], [0.5, 0, 0], [-0.25, 0.433, 0], [-0.25, -0.433, 0]], dtype=float)
    t = np.array([[0, 1, 2, 3], [0, 1, 3, 4], [0, 1, 4, 2]])
    t[tet_volumes(p, t) < 0] = t[tet_volumes(p, t) < 0][:, [0, 2, 1, 3]]
    new, removed = remove_edges(p, t, 10.0, 170.0, boundary=False)
    assert removed == 1 and len(new) == 2
    assert sorted(map(sorted, new.tolist())) == [[0, 2, 3, 4], [1, 2, 3, 4]]
    _assert_conforming(p, new, tet_volumes(p, t).sum())
    assert element_score(p, new, 10.0, 170.0).min() > 30.0
    assert element_score(p, t, 10.0, 170.0).max() < 10.0


def test_four_elements_around_an_edge_flip_to_four():
    # The octahedron split along its long axis: four needles; 4-4 flip onto a diagonal of the square.
    p = np.array([[0, 0, -2.5], [0, 0, 2.5], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], dtype=float)
    t = np.array([[0, 1, 2, 3], [0, 1, 3, 4], [0, 1, 4, 5], [0, 1, 5, 2]])
    t[tet_volumes(p, t) < 0] = t[tet_volumes(p, t) < 0][:, [0, 2, 1, 3]]
    before = element_score(p, t, 15.0, 165.0).min()
    new, removed = remove_edges(p, t, 15.0, 165.0, boundary=False)
    assert removed == 1 and len(new) == 4
    assert not (np.sort(new, axis=1)[:, :2] == [0, 1]).all(axis=1).any()  # the edge 0-1 is gone
    _assert_conforming(p, new, 2.0 * 2.5 / 3.0 * 2.0)  # two pyramids of base 2, height 2.5
    assert before < 15.0 and element_score(p, new, 15.0, 165.0).min() > 40.0


def test_planar_boundary_flip_keeps_the_surface_shape():
    # Two flat elements on the plane z = 0 sharing the long diagonal (0, 1) of a thin rhombus: the 2-2
    # flip onto the short diagonal (2, 3) keeps the plane, the nodes and the volume.
    p = np.array([[0, 0, 0], [2, 0, 0], [1, -0.2, 0], [1, 0.2, 0], [1, 0, 0.5]], dtype=float)
    t = np.array([[0, 1, 2, 4], [0, 1, 4, 3]])
    t[tet_volumes(p, t) < 0] = t[tet_volumes(p, t) < 0][:, [0, 2, 1, 3]]
    vol = tet_volumes(p, t).sum()
    kept, n_kept = remove_edges(p, t, 10.0, 165.0, boundary=False)
    assert n_kept == 0 and (kept == t).all()
    new, removed = remove_edges(p, t, 10.0, 165.0)
    assert removed == 1
    assert sorted(map(sorted, new.tolist())) == [[0, 2, 3, 4], [1, 2, 3, 4]]
    _assert_conforming(p, new, vol)
    bottom = {tuple(f) for f in np.sort(boundary_faces(new)[0], axis=1) if (p[f, 2] == 0).all()}
    assert bottom == {(0, 2, 3), (1, 2, 3)}
    assert element_score(p, t, 10.0, 165.0).max() < 4.0 and element_score(p, new, 10.0, 165.0).min() > 20.0
    # Out of the plane (the apex of one side lifted) the boundary edge stays.
    q = p.copy()
    q[2, 2] = 0.05
    assert remove_edges(q, t, 10.0, 165.0)[1] == 0


@settings(max_examples=5, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), boundary=st.booleans())
def test_edge_removal_laws(seed, boundary):
    """Edge removal keeps the volume, the positive orientation and the conformity, never lowers the
    worst score, and without boundary flips keeps the boundary sides as they are."""
    p, t, _ = _lattice(seed, n=4)
    new, removed = remove_edges(p, t, 10.0, 165.0, 3.0, boundary=boundary)
    assert removed > 0
    _assert_conforming(p, new, 1.0)
    assert element_score(p, new, 10.0, 165.0, 3.0).min() >= element_score(p, t, 10.0, 165.0, 3.0).min()
    if not boundary:
        b0 = {tuple(f) for f in np.sort(boundary_faces(t)[0], axis=1)}
        b1 = {tuple(f) for f in np.sort(boundary_faces(new)[0], axis=1)}
        assert b0 == b1
    # Boundary sides stay on the cube's faces (planar flips only).
    bp = p[boundary_faces(new)[0]]
    on_face = ((np.abs(bp) < 1e-12) | (np.abs(bp - 1) < 1e-12)).all(axis=1)
    assert on_face.any(axis=1).all()


@settings(max_examples=5, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_edge_splits_keep_the_mesh_conforming(seed):
    p, t, _ = _lattice(seed, n=4)
    bad = element_score(p, t, 10.0, 165.0) < 10.0
    edges = longest_interior_edges(p, t, bad)
    assert len(edges) > 0
    q, new = split_edges(p, t, edges)
    added = len(q) - len(p)
    assert 0 < added <= len(edges)
    _assert_conforming(q, new, 1.0)
    # Every new point is the middle of an edge asked for, and each split cut its elements in two.
    mids = 0.5 * (p[edges[:, 0]] + p[edges[:, 1]])
    d = np.linalg.norm(q[len(p):, None, :] - mids[None, :, :], axis=2).min(axis=1)
    assert d.max() < 1e-15
    ring = np.bincount(new.reshape(-1), minlength=len(q))[len(p):]
    assert len(new) - len(t) == ring.sum() // 2


@pytest.mark.parametrize("seed", [0, 1])
def test_sliver_pass_clears_a_lattice_full_of_slivers(seed):
    """A Delaunay mesh of a jittered lattice: some 60 elements under 10 degrees; smoothing and 2-3 flips
    alone leave 5 to 25 of them (measured over six seeds), the whole pass none, with gamma >= 0.25."""
    p, t, inside = _lattice(seed)
    assert (dihedral_angles(p, t).min(axis=1) < 10.0).sum() > 40
    q, new, counts = remove_slivers(p, t, inside, 10.0, 165.0, radius_edge=3.0)
    assert counts["flips"] > 0
    _assert_conforming(q, new, 1.0)
    assert dihedral_angles(q, new).min() >= 10.0
    assert gamma(q, new).min() >= 0.25
    # Boundary nodes did not move (not movable, no solid to slide on).
    np.testing.assert_array_equal(q[:len(p)][~inside], p[~inside])


def test_beam_with_every_node_on_its_boundary_meshes_clean():
    """The beam 100 x 10 x 10 on a surface of size 6.4 meshed at size 10: TetGen adds no interior node, so
    smoothing can only slide boundary nodes; elements under 10 degrees (9.82 with smoothing and 2-3 flips
    alone) go by 2-2 flips of diagonals on the beam's flat faces.  The surface clustered from the plain
    mesh has such elements; the one from the feature mesh (the default) meshes clean by sliding alone."""
    from implicit import box
    from spatial.fea import tet_mesh
    from spatial.fea.surface import surface_for_fea

    beam = box((100.0, 10.0, 10.0), center=(50.0, 0.0, 0.0))
    surf = surface_for_fea(beam, size=6.4, start="plain")
    m = tet_mesh(beam, size=10.0, surface=surf, reference_volume=1e4)
    assert m.info["tetgen_points"] == m.info["surface_points"]  # no interior node
    assert m.info["flips"] > 0
    assert m.quality.min_dihedral >= 10.0
    assert m.volume == pytest.approx(1e4, rel=1e-12)
    # The boundary is still the beam's: every boundary node on its surface.
    assert np.abs(beam(m.points[np.unique(m.boundary)])).max() < 1e-9


def test_smoothing_returns_the_scores_of_its_result():
    from spatial.fea.slivers import improve

    g = np.linspace(0.0, 1.0, 5)
    p = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    free = ((p > 0) & (p < 1)).all(axis=1)
    p[free] += np.random.default_rng(1).normal(scale=0.06, size=p[free].shape)
    t = Delaunay(p).simplices.astype(np.int64)
    t[tet_volumes(p, t) < 0] = t[tet_volumes(p, t) < 0][:, [0, 2, 1, 3]]
    before = element_score(p, t, 10.0, 165.0, 3.0)
    q, sc = improve(p, t, free, 10.0, 165.0, radius_edge=3.0, with_scores=True)
    np.testing.assert_array_equal(sc, element_score(q, t, 10.0, 165.0, 3.0))
    assert (sc < 10.0).sum() < (before < 10.0).sum() and not np.array_equal(q, p)
    # given the scores it starts from, the same result
    q2 = improve(p, t, free, 10.0, 165.0, radius_edge=3.0, scores=before)
    np.testing.assert_array_equal(q2, q)
