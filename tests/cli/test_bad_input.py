"""Bad input gets a clear error naming the argument, before any work."""

import numpy as np
import pytest

import implicit as I
from implicit.serialize import from_json

NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize("make, error, match", [
    (lambda: I.sphere(-1), ValueError, r"^radius: expected a positive number, got -1$"),
    (lambda: I.sphere(0), ValueError, r"^radius: expected a positive number, got 0$"),
    (lambda: I.sphere(NAN), ValueError, r"^radius: expected a positive number, got nan$"),
    (lambda: I.sphere(INF), ValueError, r"^radius: expected a positive number, got inf$"),
    (lambda: I.sphere("1"), TypeError, r"^radius: expected a positive number, got '1'$"),
    (lambda: I.sphere(True), TypeError, r"^radius: expected a positive number, got True$"),
    (lambda: I.sphere(1, center=(0, NAN, 0)), ValueError, r"^center: expected finite numbers"),
    (lambda: I.sphere(1, center=(0, 0)), ValueError, r"^center: expected 3 numbers, got shape \(2,\)$"),
    (lambda: I.box((1, 0, 1)), ValueError, r"^size: expected positive edge lengths, got \[1\.0, 0\.0, 1\.0\]$"),
    (lambda: I.box(-2), ValueError, r"^size: expected a positive number, got -2$"),
    (lambda: I.rounded_box(1, radius=0.8), ValueError, r"^radius: expected at most half the smallest edge"),
    (lambda: I.cylinder(1, 0), ValueError, r"^height: expected a positive number, got 0$"),
    (lambda: I.cylinder(1, 1, axis=(0, 0, 0)), ValueError, r"^axis: expected a nonzero vector"),
    (lambda: I.cone(1, INF), ValueError, r"^height: expected a positive number, got inf$"),
    (lambda: I.frustum(1, 0, 1), ValueError, r"^top_radius: expected a positive number, got 0$"),
    (lambda: I.torus(1, 2), ValueError, r"^minor_radius: expected less than major_radius"),
    (lambda: I.ellipsoid((1, -1, 1)), ValueError, r"^radii: expected positive semi-axes"),
    (lambda: I.capsule((0, 0, 0), (1, 1, 1), 0), ValueError, r"^radius: expected a positive number, got 0$"),
    (lambda: I.capsule((0, 0, INF), (1, 1, 1), 1), ValueError, r"^a: expected finite numbers"),
    (lambda: I.wedge((1, 1, 0)), ValueError, r"^size: expected positive edge lengths"),
    (lambda: I.pyramid([(0, 0), (2, 0), (1, 0.2), (1, 2), (0, 2)], 1), ValueError, r"^base: expected a convex polygon$"),
    (lambda: I.pyramid([(0, 0), (1, 0), (0, 1)], -1), ValueError, r"^height: expected a positive number"),
    (lambda: I.prism([(0, 0), (1, 0)], 1), ValueError, r"vertices: expected an \(m, 2\) array with m >= 3"),
    (lambda: I.prism("abc", 1), TypeError, r"vertices: expected an \(m, 2\) array of numbers"),
    (lambda: I.convex_polyhedron([[0, 0, 1]] * 3, [[0, 0, 0]] * 3), ValueError, r"^normals: expected an \(m, 3\) array with m >= 4"),
    (lambda: I.convex_polyhedron([[0, 0, 1]] * 4, [[0, 0, 0]] * 3), ValueError, r"^points: expected the shape of normals"),
    (lambda: I.convex_polyhedron([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 0, 0]] * 4), ValueError,
     r"^normals: normal 0 is zero$"),
    (lambda: I.convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                                 [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]),
     ValueError, r"convex_polyhedron: the half-spaces have an empty intersection"),
    (lambda: I.convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                                 [[0, 0, 0], [0, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]),
     ValueError, r"convex_polyhedron: the half-spaces have an empty interior"),
    (lambda: I.convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]],
                                 [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]]),
     ValueError, r"do not bound a finite solid \(unbounded along -z\)"),
    (lambda: I.convex_polyhedron(np.ones((10001, 3)), np.zeros((10001, 3))), ValueError,
     r"^normals: expected at most 10000 planes, got 10001$"),
    (lambda: I.halfspace((0, 0, 0)), ValueError, r"^normal: expected a nonzero vector"),
    (lambda: I.sphere(1).translate((NAN, 0, 0)), ValueError, r"^offset: expected finite numbers"),
    (lambda: I.sphere(1).rotate(INF), ValueError, r"^angle_degrees: expected a finite number, got inf$"),
    (lambda: I.sphere(1).scale(0), ValueError, r"^factor: expected a positive number, got 0$"),
    (lambda: I.sphere(1).scale((1, -1, 1)), ValueError, r"^factor: expected positive scale factors"),
    (lambda: I.sphere(1).affine(np.zeros((3, 3))), ValueError, r"^matrix: expected an invertible matrix"),
    (lambda: I.sphere(1).affine(np.eye(2)), ValueError, r"^matrix: expected shape \(3, 3\), got \(2, 2\)$"),
    (lambda: I.sphere(1).offset(NAN), ValueError, r"^distance: expected a finite number, got nan$"),
    (lambda: I.sphere(1).shell(-0.1), ValueError, r"^thickness: expected a positive number, got -0\.1$"),
    (lambda: I.smooth_union(I.sphere(1), I.box(1), blend=0), ValueError, r"^blend: expected a positive number, got 0$"),
    (lambda: I.union(), ValueError, r"^union: expected at least one solid$"),
    (lambda: I.intersection(), ValueError, r"^intersection: expected at least one solid$"),
])
def test_constructors_reject_bad_values(make, error, match):
    with pytest.raises(error, match=match):
        make()


@pytest.mark.parametrize("points, error, match", [
    ([1.0, 2.0], ValueError, r"^points: expected an array of shape \(\.\.\., 3\), got shape \(2,\)$"),
    (np.zeros((4, 2)), ValueError, r"^points: expected an array of shape \(\.\.\., 3\), got shape \(4, 2\)$"),
    (5.0, ValueError, r"^points: expected an array of shape \(\.\.\., 3\), got shape \(\)$"),
    ([[0, NAN, 0]], ValueError, r"^points: expected numbers, got NaN$"),
    ([["a", "b", "c"]], TypeError, r"^points: expected an array of shape \(\.\.\., 3\) of numbers"),
    ([[0, 0], [0, 0, 0]], TypeError, r"^points: expected an array of shape \(\.\.\., 3\) of numbers"),
])
def test_evaluation_rejects_bad_points(points, error, match):
    with pytest.raises(error, match=match):
        I.sphere(1.0)(points)


def test_evaluation_keeps_shapes_and_handles_infinity():
    s = I.sphere(1.0)
    assert s(np.zeros((2, 4, 3))).shape == (2, 4)
    assert s(np.zeros((0, 3))).shape == (0,)
    assert s([[INF, 0, 0]])[0] == INF
    assert (I.box(1) - I.sphere(0.2))([[0, -INF, 0]])[0] == INF


def test_value_bounds_reject_bad_boxes():
    with pytest.raises(ValueError, match=r"lo and hi: expected the same shape, got \(2, 3\) and \(1, 3\)"):
        I.sphere(1).value_bounds(np.zeros((2, 3)), np.ones((1, 3)))
    with pytest.raises(ValueError, match=r"every lower corner must be <= its upper corner"):
        I.sphere(1).value_bounds(np.ones((1, 3)), np.zeros((1, 3)))


def test_solids_refuse_truth_and_equality():
    with pytest.raises(TypeError, match="truth value of a Solid is ambiguous"):
        bool(I.sphere(1))
    with pytest.raises(TypeError, match="Solids are not compared with =="):
        I.sphere(1) == I.sphere(1)
    with pytest.raises(AttributeError, match="immutable"):
        I.sphere(1)._params = {}
    with pytest.raises(TypeError, match="truth value of a Profile is ambiguous"):
        bool(I.circle(1))


@pytest.mark.parametrize("text, error, match", [
    ('{"kind": "sphere", "radius": NaN}', ValueError, r"JSON: NaN is not allowed"),
    ('{"kind": "box", "size": [1, 1, Infinity]}', ValueError, r"JSON: Infinity is not allowed"),
    ('{"kind": "box", "size": [1, 1, 1e400]}', ValueError, r"^\$\.size: expected finite numbers"),
    ('{"kind": "box", "size": {"x": 1}}', TypeError, r"^\$\.size: expected 3 numbers"),
    ('{"kind": "box", "size": null}', TypeError, r"^\$\.size: expected 3 numbers, got None"),
    ('{"kind": "halfspace", "normal": [0, 0, 0]}', ValueError, r"^\$\.normal: expected a nonzero vector"),
    ('{"kind": "union", "children": [{"kind": "__import__"}]}', ValueError,
     r"^\$\.children\[0\]\.kind: unknown node kind '__import__'"),
    ('{"kind": "family", "family": "os.system", "params": {}}', ValueError, r"^\$: unknown family 'os\.system'"),
    ('{"kind": "family", "family": "hole_plate", "params": [1]}', TypeError,
     r"^\$: hole_plate: expected parameters as a mapping, got list"),
    ('{"kind": "family", "family": "hole_plate", "extra": 1}', ValueError, r"^\$: unexpected keys \['extra'\] in a family node"),
    ('{"kind": "revolve", "profile": {"kind": "circle", "radius": 1}, "angle": 0}', ValueError,
     r"^\$\.angle: expected degrees in \(0, 360\], got 0"),
    ('{"kind": "revolve", "profile": {"kind": "circle", "radius": 1, "center": [0.5, 0]}}', ValueError,
     r"^\$\.profile: expected a profile in the half-plane r >= 0 or symmetric about r = 0"),
    ('{"kind": "extrude", "height": 1, "profile": 5}', TypeError, r"^\$\.profile: expected a Profile, got int"),
    ('{"kind": "sphere", "radius": 1, "children": [{"kind": "sphere"}]}', ValueError,
     r"^\$\.children: a sphere node is a leaf and takes no children"),
])
def test_malformed_json_is_reported_with_its_location(text, error, match):
    with pytest.raises(error, match=match):
        from_json(text)


def test_huge_json_is_refused_before_parsing():
    huge = '{"kind": "union", "children": [' + ",".join(['{"kind": "sphere"}'] * 10) + "]}"
    with pytest.raises(ValueError, match=r"JSON: the text is longer than 64 characters"):
        from_json(huge, max_chars=64)
    many = '{"kind": "union", "children": [' + ",".join(['{"kind": "sphere"}'] * 2000) + "]}"
    with pytest.raises(ValueError, match=r"the tree has more than 1000 nodes"):
        from_json(many, max_nodes=1000)
