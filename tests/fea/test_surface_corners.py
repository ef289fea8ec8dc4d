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


# the bracket's 18 straight edges: the L profile's six sides at y = 0 and y = 30, and its six corners along y
_PROFILE = [(0, 0), (50, 0), (50, 4), (4, 4), (4, 40), (0, 40)]
BRACKET_EDGES = [((x0, y, z0), (x1, y, z1)) for y in (0.0, 30.0)
                 for (x0, z0), (x1, z1) in zip(_PROFILE, _PROFILE[1:] + _PROFILE[:1])] + \
                [((x, 0.0, z), (x, 30.0, z)) for x, z in _PROFILE]


def test_every_bracket_edge_is_a_chain_of_nodes():
    """The FEA surface starts from the feature mesh: along each true edge lie surface nodes, joined
    end to end by surface edges, from one corner to the other."""
    solid = runpy.run_path(os.path.join(EXAMPLES, "bracket.py"))["solid"]
    size = 2.0
    s = surface_for_fea(solid, size=size)
    pts = np.asarray(s.points)
    faces = np.asarray(s.faces).reshape(-1, 4)[:, 1:]
    edges = {tuple(e) for e in np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)}
    for a, b in BRACKET_EDGES:
        a, b = np.asarray(a, float), np.asarray(b, float)
        t = (pts - a) @ (b - a) / np.dot(b - a, b - a)
        off = np.linalg.norm(pts - (a + np.clip(t, 0, 1)[:, None] * (b - a)), axis=1)
        on = np.flatnonzero(off < 1e-6 * size)
        chain = on[np.argsort(t[on])]
        assert t[chain[0]] == pytest.approx(0.0, abs=1e-9) and t[chain[-1]] == pytest.approx(1.0, abs=1e-9), (a, b)
        links = [tuple(sorted(p)) in edges for p in zip(chain[:-1], chain[1:])]
        assert all(links), (a, b, links)
        assert np.diff(t[chain]).max() * np.linalg.norm(b - a) < 2.5 * size


def test_beam_as_thick_as_the_size_keeps_its_volume():
    """At a size equal to its thickness the free clusters span the beam's section (the surface from the
    feature mesh would enclose 82 percent of it); clusters kept to the faces keep the volume exactly at
    that size (nodes on the faces, edges and corners), and `tet_mesh` needs no finer size."""
    from spatial.fea.tetmesh import _surface_for

    beam = box((100.0, 10.0, 10.0), center=(50.0, 0.0, 0.0))
    coarse = surface_for_fea(beam, size=10.0)
    assert coarse.field_data["start"][0] == "features" and coarse.field_data["clusters"][0] == "faces"
    assert abs(abs(coarse.volume) - 1e4) / 1e4 < 1e-9
    s, used, _ = _surface_for(beam, 10.0, (1e4, 0.0), 0.005, 1)
    assert used == 10.0
    assert abs(s.volume - 10000.0) / 10000.0 < 1e-9


def test_gear_surface_free_of_self_intersections():
    """The gear's rim bends at every vertex of its flanks' polygon (one face): a surface whose edges
    were flipped onto chords across those bends pierced itself."""
    from spatial.fea.surface import self_intersections

    gear = runpy.run_path(os.path.join(EXAMPLES, "gear.py"))["solid"]
    s = surface_for_fea(gear, size=2.0, check_intersections=False)
    assert self_intersections(s) == 0
    # clustered from the feature mesh, flips only onto chords that follow the rim
    assert s.field_data["start"][0] == "features"

