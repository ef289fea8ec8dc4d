"""Local caps of a graded size field: where the surface crosses itself, where elements miss the quality."""

import numpy as np
import pytest
import pyvista as pv

from implicit import box
from spatial.fea.graded import GROWTH, SizeField
from spatial.fea.graded_surface import crossing_triangles, poor_element_nodes, surface_info
from spatial.fea.surface import mesh_faces


def test_refined_adds_sources_graded_as_the_field():
    f = SizeField(5.0, [[0.0, 0.0, 0.0]], [1.0])
    g = f.refined([[10.0, 0.0, 0.0], [0.0, 0.0, 0.0]], [0.5, 2.0])
    x = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [6.0, 0.0, 0.0], [5.0, 3.0, 0.0], [40.0, 0.0, 0.0]])
    d0 = np.linalg.norm(x, axis=1)
    d1 = np.linalg.norm(x - [10.0, 0.0, 0.0], axis=1)
    np.testing.assert_allclose(g(x), np.minimum.reduce([np.full(len(x), 5.0), 1.0 + GROWTH * d0, 0.5 + GROWTH * d1]))
    assert g.smallest == 0.5 and f.smallest == 1.0          # the field refined is left as it was
    np.testing.assert_allclose(f(x), np.minimum(5.0, 1.0 + GROWTH * d0))
    # sizes at or over the field's size are no sources
    assert SizeField(5.0).refined([[0.0, 0.0, 0.0]], [5.0]).uniform
    with pytest.raises(ValueError, match="sizes: expected one size per point"):
        f.refined([[0.0, 0.0, 0.0]], [1.0, 2.0])


def test_crossing_triangles_are_those_that_pierce_or_face_into_the_solid():
    a = pv.Cube(x_length=2.0, y_length=2.0, z_length=2.0).triangulate()
    pa, fa = np.asarray(a.points), mesh_faces(a)
    assert crossing_triangles(box(2.0), pa, fa).size == 0
    # a second cube moved by (1, 1, 1): only triangles near the corner where they overlap cross
    pb = pa + 1.0
    p = np.concatenate([pa, pb])
    f = np.concatenate([fa, fa + len(pa)])
    hit = crossing_triangles(None, p, f)
    first = hit < len(fa)
    assert first.any() and (~first).any()
    # the first cube's crossing triangles lie on its faces x, y or z = 1, the second's on theirs at 0
    def on(tri, value):
        return np.isclose(p[f[tri]], value).all(axis=1).any(axis=1)

    assert on(hit[first], 1.0).all() and on(hit[~first], 0.0).all()
    # a triangle turned over on its face
    fb = fa.copy()
    fb[3] = fb[3, ::-1]
    assert crossing_triangles(box(2.0), pa, fb).tolist() == [3]
    assert crossing_triangles(None, pa, fb).size == 0


def test_poor_element_nodes_are_the_corners_of_the_elements_out_of_bounds():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0.05], [3, 3, 3]], dtype=float)
    tets = [[0, 1, 2, 3], [0, 1, 2, 4], [1, 2, 3, 5]]
    bad = poor_element_nodes(p, tets, 10.0, 165.0, 3.0)
    # the flat second element only (its angles at the edge 1-2: 180 and 0 degrees)
    assert sorted(map(tuple, bad.tolist())) == sorted(map(tuple, p[[0, 1, 2, 4]].tolist()))
    assert poor_element_nodes(p, tets[:1], 10.0, 165.0, 3.0).size == 0


def test_surface_info_reads_the_surface_field_data():
    s = pv.Sphere()
    assert surface_info(s) == {}
    s.field_data["start"] = np.array(["plain"])
    s.field_data["local_caps"] = np.array([2])
    assert surface_info(s) == {"surface_start": "plain", "local_caps": 2}
