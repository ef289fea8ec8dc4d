"""CSG trees <-> JSON: round trips, the encoder hook, located errors, hostile input."""

import json

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import implicit as I
from implicit import Solid
from implicit.families import instance
from implicit.serialize import MAX_DEPTH, from_dict, from_json, to_dict, to_json

PTS = np.random.default_rng(0).uniform(-2.5, 2.5, (3000, 3))

EVERY_KIND = [
    I.halfspace((1, 2, 3), point=(0.1, 0, 0)), I.sphere(1.2, (0.1, 0.2, 0.3)), I.box((1, 2, 3)),
    I.rounded_box((1, 1, 1), radius=0.1), I.cylinder(0.5, 2, axis=(1, 1, 0)), I.cone(1, 2, axis=(0, 1, 0)),
    I.frustum(1, 0.4, 1.5), I.torus(1, 0.3, axis=(1, 0, 1)), I.ellipsoid((1, 0.5, 0.7)),
    I.capsule((0, 0, 0), (1, 1, 0), 0.3), I.wedge((1, 2, 1)), I.pyramid([(0, 0), (1, 0), (0, 1)], 1.0),
    I.convex_polyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                        [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]),
    I.prism([(0, 0), (1, 0), (1, 1), (0.5, 0.2), (0, 1)], 1.0, axis=(1, 0, 0)),
    I.extrude((I.circle(1) - I.rectangle(0.5)).offset(0.1) | I.circle(0.2, (2, 0)), 1.0),
    I.revolve(I.polygon([(0, -0.5), (1, -0.5), (0.5, 0.5), (0, 0.5)]), 200, center=(0, 0, 1)),
    I.sphere(1) | I.box(1.5), I.sphere(1) & I.box(1.5), I.box(2) - I.sphere(1) - I.cylinder(0.2, 3),
    ~I.sphere(1), I.smooth_union(I.sphere(1), I.box(1), blend=0.2),
    I.smooth_intersection(I.sphere(1), I.box(1.5), blend=0.2), I.smooth_difference(I.box(2), I.sphere(1), blend=0.1),
    I.box(1).rotate(33, (1, 2, 3)).translate((1, 0, 0)), I.sphere(1).scale((1, 2, 3)),
    I.box(1).affine([[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), I.offset(I.box(1), 0.2), I.shell(I.sphere(1), 0.1),
    instance("hex_bolt", diameter=0.5, length=1, head_height=0.3, across_flats=0.8),
]


def test_every_registered_kind_is_covered():
    kinds = {node.kind for s in EVERY_KIND for node in s.walk()}
    missing = {k for k, cls in Solid.registry.items() if cls.__module__.startswith("implicit.")
               and cls.__module__.split(".")[1] in ("primitives", "csg", "transforms", "modifiers", "polyhedra",
                                                   "sweeps", "families")} - kinds
    assert not missing


@pytest.mark.parametrize("solid", EVERY_KIND, ids=lambda s: s.kind)
def test_round_trip_evaluates_identically(solid):
    text = to_json(solid)
    again = from_json(text)
    assert again.kind == solid.kind and again.count_nodes() == solid.count_nodes()
    np.testing.assert_allclose(again(PTS), solid(PTS), rtol=0, atol=1e-14)
    assert to_json(again) == text                   # a second trip is a fixed point
    assert json.loads(to_json(solid, indent=2)) == json.loads(text)


def _tree_strategy():
    leaves = st.sampled_from([I.sphere(0.8), I.box((1, 0.5, 0.7)), I.cylinder(0.3, 2), I.torus(0.7, 0.2),
                              I.wedge((1, 1, 1)), I.ellipsoid((1, 0.5, 0.5)),
                              I.extrude(I.rectangle((1, 0.4)), 0.8)])

    def grow(children):
        pair = st.tuples(children, children)
        return st.one_of(
            pair.map(lambda ab: ab[0] | ab[1]), pair.map(lambda ab: ab[0] & ab[1]), pair.map(lambda ab: ab[0] - ab[1]),
            children.map(lambda a: ~a),
            st.tuples(children, st.floats(-90, 90)).map(lambda t: t[0].rotate(t[1], (1, 1, 0))),
            st.tuples(children, st.floats(-1, 1)).map(lambda t: t[0].translate((t[1], 0, 0.5))),
            st.tuples(children, st.floats(0.5, 2)).map(lambda t: t[0].scale((t[1], 1, 1))),
            pair.map(lambda ab: I.smooth_union(ab[0], ab[1], blend=0.2)),
            children.map(lambda a: I.offset(a, 0.1)),
        )
    return st.recursive(leaves, grow, max_leaves=8)


@settings(derandomize=True, max_examples=40, deadline=None)
@given(tree=_tree_strategy())
def test_random_trees_round_trip(tree):
    again = from_json(to_json(tree))
    np.testing.assert_allclose(again(PTS[:500]), tree(PTS[:500]), rtol=0, atol=1e-14)
    assert again.tree() == tree.tree()


class Tagged(Solid):
    """A node with data that its params do not carry: uses the to_params hook."""

    kind = "test_tagged_ball"
    __slots__ = ("_data",)

    def __init__(self, data):
        data = np.asarray(data, dtype=float)
        super().__init__((), {"n": int(data.size)}, (np.full(3, -data[0]), np.full(3, data[0])), exact=True)
        object.__setattr__(self, "_data", data)

    def to_params(self):
        return {"data": self._data.tolist()}

    @classmethod
    def from_params(cls, children, params):
        return cls(params["data"])

    def _evaluate(self, p):
        return np.linalg.norm(p, axis=1) - self._data[0]


def test_encoder_hook_for_data_backed_nodes():
    node = Tagged([1.5, 2.0]) | I.box(1)
    data = to_dict(node)
    assert data["children"][0] == {"kind": "test_tagged_ball", "data": [1.5, 2.0]}
    np.testing.assert_array_equal(from_dict(data)(PTS), node(PTS))


@pytest.mark.parametrize("doc, error, match", [
    ({"kind": "union", "children": [{"kind": "sphere"}, {"kind": "sphere", "radius": -2}]},
     ValueError, r"^\$\.children\[1\]\.radius: expected a positive number, got -2$"),
    ({"kind": "blob"}, ValueError, r"^\$\.kind: unknown node kind 'blob'; known: affine, box, capsule"),
    ({"radius": 1}, TypeError, r"^\$\.kind: expected a node kind \(a string\), got null"),
    ({"kind": 3}, TypeError, r"^\$\.kind: expected a node kind \(a string\), got a number"),
    ([], TypeError, r"^\$: expected a node object, got an array"),
    ({"kind": "union", "children": {"kind": "sphere"}}, TypeError, r"^\$\.children: expected an array, got an object"),
    ({"kind": "union", "children": ["sphere"]}, TypeError, r"^\$\.children\[0\]: expected a node object, got a string"),
    ({"kind": "sphere", "radius": "big"}, TypeError, r"^\$\.radius: expected a positive number, got 'big'"),
    ({"kind": "sphere", "radius": [1, 2]}, TypeError, r"^\$\.radius: expected a positive number"),
    ({"kind": "sphere", "center": [0, 0]}, ValueError, r"^\$\.center: expected 3 numbers, got shape \(2,\)"),
    ({"kind": "sphere", "centre": [0, 0, 0]}, TypeError, r"^\$: sphere: got an unexpected keyword argument 'centre'"),
    ({"kind": "cylinder", "height": 1}, TypeError, r"^\$: cylinder: missing a required argument: 'radius'"),
    ({"kind": "union", "children": []}, ValueError, r"^\$: union: expected at least one solid"),
    ({"kind": "affine", "matrix": [[1, 0, 0], [0, 0, 0], [0, 0, 1]], "children": [{"kind": "sphere"}]},
     ValueError, r"^\$\.matrix: expected an invertible matrix"),
    ({"kind": "extrude", "height": 1, "profile": {"kind": "profile_union",
                                                  "children": [{"kind": "circle", "radius": -1}]}},
     ValueError, r"^\$\.profile\.children\[0\]\.radius: expected a positive number, got -1"),
    ({"kind": "convex_polyhedron", "normals": [[0, 0, 1]] * 4, "points": [[0, 0, 0]] * 4},
     ValueError, r"^\$: convex_polyhedron: the half-spaces do not bound a finite solid"),
])
def test_bad_documents_name_the_location(doc, error, match):
    with pytest.raises(error, match=match):
        from_json(doc)


def test_hostile_text():
    with pytest.raises(ValueError, match=r"JSON: NaN is not allowed"):
        from_json('{"kind": "sphere", "radius": NaN}')
    with pytest.raises(ValueError, match=r"JSON: -Infinity is not allowed"):
        from_json('{"kind": "sphere", "radius": -Infinity}')
    with pytest.raises(ValueError, match=r"\$\.radius: expected a positive number, got inf"):
        from_json('{"kind": "sphere", "radius": 1e999}')
    with pytest.raises(ValueError, match=r"JSON: Expecting .* at line 1 column"):
        from_json('{"kind": "sphere",')
    with pytest.raises(ValueError, match=r"JSON: nested too deeply"):
        from_json("[" * 200000 + "]" * 200000)
    with pytest.raises(ValueError, match=r"JSON: the text is longer than 100 characters"):
        from_json('{"kind": "sphere", "radius": 1}' + " " * 100, max_chars=100)
    with pytest.raises(ValueError, match=r"JSON: not UTF-8 text"):
        from_json(b'{"kind": "\xff"}')
    with pytest.raises(TypeError, match=r"^\$: expected a node object, got a number"):
        from_json(12)


def test_depth_and_size_limits():
    doc = {"kind": "sphere"}
    for _ in range(MAX_DEPTH + 5):
        doc = {"kind": "offset", "distance": 0.0, "children": [doc]}
    with pytest.raises(ValueError, match=rf"the tree is deeper than {MAX_DEPTH} levels"):
        from_dict(doc)
    wide = {"kind": "union", "children": [{"kind": "sphere"}] * 50}
    with pytest.raises(ValueError, match=r"the tree has more than 20 nodes"):
        from_dict(wide, max_nodes=20)
    ok = {"kind": "sphere"}
    for _ in range(200):
        ok = {"kind": "offset", "distance": 0.001, "children": [ok]}
    assert from_dict(ok)([[0.0, 0, 0]])[0] == pytest.approx(-1.2)


def test_to_json_refuses_non_solids_and_unregistered_nodes():
    with pytest.raises(TypeError, match="solid: expected a Solid, got dict"):
        to_json({"kind": "sphere"})

    class Anonymous(I.Solid):
        __slots__ = ()

        def _evaluate(self, p):
            return p[:, 0]

    with pytest.raises(TypeError, match=r"Anonymous: kind 'solid' is not registered for JSON"):
        to_json(Anonymous())
