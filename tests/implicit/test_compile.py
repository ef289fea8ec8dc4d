"""The compiled, pruned evaluation equals the plain numpy evaluation.

Random trees of every node kind with a fast-path rule are evaluated both ways
(with and without per-bin pruning); kinds without a rule and a missing numba
fall back to numpy with identical results.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import implicit.evaluate.compile as fast
import implicit.evaluate.prune as prune
from implicit import (box, cone, cylinder, difference, frustum, halfspace, intersection,
                      rounded_box, smooth_difference, smooth_intersection, smooth_union, sphere,
                      torus, union)
from implicit.evaluate.compile import RULES, compile_solid, register_rule
from implicit.families import instance
from implicit.primitives import capsule, ellipsoid
from implicit.solid import Solid

#: Compiled and numpy values agree to this (absolute and relative).
TOL = 1e-12

AXES = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), None]


def _axis(rng):
    axis = AXES[rng.integers(len(AXES))]
    return tuple(rng.normal(size=3)) if axis is None else axis


def _centre(rng):
    # Often on the origin or an axis, so that zero offsets are exercised.
    c = rng.uniform(-1.0, 1.0, 3)
    c[rng.random(3) < 0.3] = 0.0
    return tuple(c)


class _Blob(Solid):
    """A node kind without a fast-path rule (a sphere of radius 1)."""

    __slots__ = ()

    def __init__(self):
        super().__init__((), {}, (-np.ones(3), np.ones(3)), exact=True)

    def _evaluate(self, p):
        return np.sqrt(np.einsum("ij,ij->i", p, p)) - 1.0


def _leaf(rng) -> Solid:
    kind = rng.integers(12)
    if kind == 0:
        return halfspace(tuple(rng.normal(size=3)), _centre(rng))
    if kind == 1:
        return sphere(rng.uniform(0.2, 1.2), _centre(rng))
    if kind == 2:
        return box(tuple(rng.uniform(0.3, 2.0, 3)), _centre(rng))
    if kind == 3:
        size = rng.uniform(0.4, 2.0, 3)
        return rounded_box(tuple(size), rng.uniform(0.01, 0.45) * size.min(), _centre(rng))
    if kind == 4:
        return cylinder(rng.uniform(0.1, 1.0), rng.uniform(0.2, 2.0), _centre(rng), _axis(rng))
    if kind == 5:
        return cone(rng.uniform(0.1, 1.0), rng.uniform(0.2, 2.0), _centre(rng), _axis(rng))
    if kind == 6:
        return frustum(rng.uniform(0.1, 1.0), rng.uniform(0.05, 1.0), rng.uniform(0.2, 2.0), _centre(rng), _axis(rng))
    if kind == 7:
        big = rng.uniform(0.4, 1.2)
        return torus(big, rng.uniform(0.05, 0.9) * big, _centre(rng), _axis(rng))
    if kind == 8:
        return ellipsoid(tuple(rng.uniform(0.2, 1.5, 3)), _centre(rng))
    if kind == 9:
        a = _centre(rng)
        b = a if rng.random() < 0.2 else _centre(rng)  # a ball when a == b
        return capsule(a, b, rng.uniform(0.1, 0.8))
    if kind == 10:
        # A part family instance (a whole tree under one node), scaled to size.
        name = ("l_bracket", "hole_plate", "flanged_pipe")[rng.integers(3)]
        return instance(name).scale(0.02)
    # A kind without a rule: evaluated by numpy as an input of the tape.
    return _Blob().scale(rng.uniform(0.3, 1.0)).translate(_centre(rng))


def random_tree(rng, depth: int = 3) -> Solid:
    """A random tree of every node kind the fast path knows."""
    if depth == 0 or rng.random() < 0.25:
        return _leaf(rng)
    kind = rng.integers(14)
    kids = [random_tree(rng, depth - 1) for _ in range(rng.integers(2, 5))]
    blend = rng.uniform(0.05, 0.5)
    a = kids[0]
    if kind == 0:
        return union(*kids)
    if kind == 1:
        return intersection(*kids)
    if kind == 2:
        return difference(*kids)
    if kind == 3:
        return smooth_union(*kids, blend=blend)
    if kind == 4:
        return smooth_intersection(*kids, blend=blend)
    if kind == 5:
        return smooth_difference(*kids, blend=blend)
    if kind == 6:
        return ~a
    if kind == 7:
        return a.offset(rng.uniform(-0.2, 0.3))
    if kind == 8:
        return a.shell(rng.uniform(0.05, 0.4))
    if kind == 9:
        return a.translate(tuple(rng.uniform(-1, 1, 3)))
    if kind == 10:
        return a.rotate(rng.uniform(-180, 180), tuple(rng.normal(size=3)), about=_centre(rng))
    if kind == 11:
        return a.scale(rng.uniform(0.5, 2.0) if rng.random() < 0.5 else tuple(rng.uniform(0.5, 2.0, 3)))
    if kind == 12:
        return a.mirror(tuple(rng.normal(size=3)), _centre(rng))
    matrix = np.eye(3) + rng.uniform(-0.4, 0.4, (3, 3))
    return a.affine(matrix, tuple(rng.uniform(-1, 1, 3)))


def _points(rng, n=4000):
    """Uniform points, plus a cluster, so that bins differ in size."""
    pts = rng.uniform(-2.5, 2.5, (n, 3))
    pts[: n // 4] = rng.normal(0.0, 0.3, (n // 4, 3))
    return pts


@settings(derandomize=True, max_examples=70, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_random_trees_match_numpy_with_and_without_pruning(seed):
    rng = np.random.default_rng(seed)
    tree = random_tree(rng)
    pts = _points(rng)
    ref = fast._numpy_evaluate(tree, pts)
    compiled = compile_solid(tree)
    assert compiled.backend == "numba"
    old = prune.POINTS_PER_BIN
    prune.POINTS_PER_BIN = 8
    try:
        pruned = compiled(pts, prune=True)
    finally:
        prune.POINTS_PER_BIN = old
    np.testing.assert_allclose(compiled(pts, prune=False), ref, rtol=TOL, atol=TOL)
    np.testing.assert_allclose(pruned, ref, rtol=TOL, atol=TOL)


def test_random_trees_cover_every_rule():
    kinds = set()
    for seed in range(60):
        kinds.update(type(node) for node in random_tree(np.random.default_rng(seed)).walk())
    assert set(RULES) <= kinds


def _plate():
    plate = rounded_box((8.0, 5.0, 0.5), 0.1)
    bosses = [cylinder(0.4, 1.0, center=(x, 0.0, 0.4)) for x in (-2.0, 0.0, 2.0)]
    body = smooth_union(plate, *bosses, box((4.0, 0.3, 0.6)).rotate(30.0), blend=0.2)
    holes = [cylinder(0.15, 2.0, center=(x, y, 0.0)) for x in np.linspace(-3.5, 3.5, 8) for y in (-2.0, 2.0)]
    return difference(body, *holes)


def test_family_instances_join_the_fast_path():
    part = instance("hole_plate")
    assert fast.supports(part)
    lo, hi = part.bounds
    pts = lo - 1 + (hi - lo + 2) * np.random.default_rng(9).random((30000, 3))
    np.testing.assert_allclose(compile_solid(part)(pts), fast._numpy_evaluate(part, pts), rtol=TOL, atol=TOL)


def test_pruning_switches_off_most_operands_of_a_plate_and_keeps_values():
    part = _plate()
    lo, hi = part.bounds
    pts = lo + (hi - lo) * np.random.default_rng(3).random((20000, 3))
    compiled = compile_solid(part)
    with prune.Workspace(len(pts)) as (cell, order, sorted_pts, values):
        g, scale = prune.grid(lo, hi, len(pts))
        assert g.tolist() == [9, 6, 2]  # near-cubic bins of about 256 points
        starts, blo, bhi = fast._kernel("bin")(pts, lo, scale, g, cell, order, sorted_pts)
        # Every point lands in its bin's box, bins are contiguous runs.
        assert starts[0] == 0 and starts[-1] == len(pts)
        assert np.array_equal(np.sort(order), np.arange(len(pts)))
        assert np.array_equal(sorted_pts, pts[order])
        for b in range(len(starts) - 1):
            chunk = sorted_pts[starts[b]:starts[b + 1]]
            assert np.array_equal(chunk.min(axis=0), blo[b]) and np.array_equal(chunk.max(axis=0), bhi[b])
        active = fast._flags(compiled.tape, blo, bhi, fast._kernel("serial"))
    assert active.shape == (len(starts) - 1, len(compiled.tape.flags))
    assert active.mean() < 0.35
    np.testing.assert_allclose(compiled(pts, prune=True), fast._numpy_evaluate(part, pts), rtol=TOL, atol=TOL)


def test_far_operand_of_a_union_is_switched_off_near_the_other():
    part = union(sphere(1.0), sphere(1.0, (10.0, 0.0, 0.0)))
    tape = compile_solid(part).tape
    lo = np.array([[-0.5, -0.5, -0.5], [9.5, -0.5, -0.5], [4.0, -1.0, -1.0]])
    hi = lo + np.array([1.0, 1.0, 1.0])
    active = fast._flags(tape, lo, hi, fast._kernel("serial"))
    # Near the first sphere only it counts, and the other way round; between
    # them (values 3..5 from both) both stay.
    assert active.tolist() == [[True, False], [False, True], [True, True]]


def test_smooth_union_keeps_an_operand_within_the_blend():
    near = smooth_union(sphere(1.0), sphere(1.0, (2.1, 0.0, 0.0)), blend=0.5)
    far = smooth_union(sphere(1.0), sphere(1.0, (4.0, 0.0, 0.0)), blend=0.5)
    lo = np.array([[0.9, -0.05, -0.05]])
    hi = lo + 0.1
    kernel = fast._kernel("serial")
    # At x ~ 1 the second sphere's values are about 0.1 (within the blend)
    # or 2.0 (beyond it): kept, then dropped.
    assert fast._flags(compile_solid(near).tape, lo, hi, kernel).tolist() == [[True]]
    assert fast._flags(compile_solid(far).tape, lo, hi, kernel).tolist() == [[False]]


def test_tape_reuses_registers():
    part = union(*[sphere(0.3, (x, 0.0, 0.0)) for x in range(40)])
    tape = compile_solid(part).tape
    assert len(tape) > 150
    assert tape.nreg <= 8


def test_axis_aligned_cylinder_needs_no_products():
    tape = fast.Tape(cylinder(1.0, 2.0))
    names = {code: name for name, (code, _) in fast.OPS.items()}
    used = [names[int(op)] for op in tape.code[:, 0]]
    assert used == ["neg", "cylinder"]  # the frame of axis z holds -x as a row
    tilted = fast.Tape(cylinder(1.0, 2.0, center=(0.0, 0.0, 1.0), axis=(0.0, 1.0, 1.0)))
    used = [names[int(op)] for op in tilted.code[:, 0]]
    assert used == ["subk", "mulk", "madk", "neg", "mulk", "madk", "cylinder"]


def test_shapes_and_empty_input():
    part = sphere(1.0) - box(0.5)
    compiled = compile_solid(part)
    pts = np.random.default_rng(0).uniform(-1, 1, (4, 5, 3))
    out = compiled(pts)
    assert out.shape == (4, 5)
    np.testing.assert_allclose(out, part(pts), rtol=TOL, atol=TOL)
    assert compiled(np.zeros((0, 3))).shape == (0,)
    assert float(compiled([0.0, 0.0, 0.9])) == pytest.approx(-0.1, abs=1e-15)


def test_solid_call_takes_the_compiled_path_for_large_inputs():
    part = _plate()
    lo, hi = part.bounds
    pts = lo + (hi - lo) * np.random.default_rng(5).random((fast.AUTO_MIN_POINTS + 1, 3))
    assert fast._cached(part, False) is None
    values = part(pts)
    assert fast._cached(part, False) is not None
    np.testing.assert_allclose(values, fast._numpy_evaluate(part, pts), rtol=TOL, atol=TOL)
    assert isinstance(part.compiled(), fast.CompiledSolid)
    # A small call of a new tree stays with numpy (no compiled entry).
    other = sphere(2.0)
    other(pts[:100])
    assert fast._cached(other, False) is None


def test_small_calls_of_a_large_tree_take_the_compiled_path():
    """From `SMALL_CALL_MIN_NODES` nodes a call of a few points runs on the tape (numpy pays per node);
    a smaller tree's small call stays with numpy, bit for bit its own evaluation."""
    big = union(*[capsule((x, 0.0, 0.0), (x, 1.0, 0.0), 0.2) for x in range(40)]) & box(90.0)
    assert big.count_nodes() >= fast.SMALL_CALL_MIN_NODES
    pts = np.random.default_rng(7).uniform(-1.0, 40.0, (5, 3))
    assert fast._cached(big, False) is None
    values = big(pts)
    assert fast._cached(big, False) is not None          # compiled on the first small call
    np.testing.assert_allclose(values, fast._numpy_evaluate(big, pts), rtol=TOL, atol=TOL)
    assert big(pts[:1]).shape == (1,) and big(np.zeros((0, 3))).shape == (0,)
    small = union(*[sphere(0.5, center=(x, 0.0, 0.0)) for x in range(4)])
    assert small.count_nodes() < fast.SMALL_CALL_MIN_NODES
    got = small(pts)
    assert fast._cached(small, False) is None
    assert np.array_equal(got, small._evaluate(np.ascontiguousarray(pts)))


def test_parallel_kernel_matches():
    part = _plate()
    pts = np.random.default_rng(7).uniform(-5, 5, (60000, 3))
    compiled = compile_solid(part, parallel=True)
    assert compiled.parallel
    ref = fast._numpy_evaluate(part, pts)
    np.testing.assert_allclose(compiled(pts, prune=True), ref, rtol=TOL, atol=TOL)
    np.testing.assert_allclose(compiled(pts, prune=False), ref, rtol=TOL, atol=TOL)


def test_unknown_kind_is_evaluated_by_numpy_where_the_tape_reads_it(monkeypatch):
    blob = _Blob()
    part = union(blob.rotate(30.0, (1, 1, 0)).translate((2.5, 0.0, 0.0)), box(1.0), sphere(0.5, (-2.0, 0.0, 0.0)))
    compiled = compile_solid(part)
    assert compiled.backend == "numba" and [n for n, _ in compiled.tape.opaque] == [blob]
    assert not fast.supports(part) and fast.supports(box(1.0))
    pts = np.random.default_rng(2).uniform(-1.0, 1.0, (60000, 3)) * (4.0, 0.8, 0.8)
    ref = fast._numpy_evaluate(part, pts)
    calls = []
    monkeypatch.setattr(_Blob, "_evaluate", lambda self, p: calls.append(len(p)) or _sphere_values(p))
    np.testing.assert_allclose(compiled(pts, prune=False), ref, rtol=TOL, atol=TOL)
    assert sum(calls) == len(pts)
    calls.clear()
    np.testing.assert_allclose(compiled(pts, prune=True), ref, rtol=TOL, atol=TOL)
    # Pruned: the bin centres, then only the points of bins where the blob
    # can change the union.
    assert 0 < sum(calls) < 0.5 * len(pts)


def _sphere_values(p):
    return np.sqrt(np.einsum("ij,ij->i", p, p)) - 1.0


class _Swap(Solid):
    """The child with x and y exchanged (a test node whose rule declares no
    numpy map for its coordinates)."""

    __slots__ = ()

    def __init__(self, child):
        super().__init__((child,), {}, child.bounds, exact=child.exact)

    def _evaluate(self, p):
        return self._children[0]._evaluate(np.ascontiguousarray(p[:, [1, 0, 2]]))


def test_unknown_kind_below_undeclared_coordinates_falls_back_to_numpy(monkeypatch):
    monkeypatch.setitem(fast.RULES, _Swap, lambda node, gen, c: gen.node(node.children[0], (c[1], c[0], c[2])))
    part = union(_Swap(_Blob().translate((0.5, 0.0, 0.0))), box(1.0))
    compiled = fast.CompiledSolid(part)
    assert compiled.backend == "numpy"
    pts = np.random.default_rng(2).uniform(-2, 2, (fast.AUTO_MIN_POINTS + 7, 3))
    assert np.array_equal(compiled(pts), fast._numpy_evaluate(part, pts))
    # With a rule-less kind but known coordinates, the same tree compiles.
    assert fast.CompiledSolid(_Swap(box(1.0))).backend == "numba"


def test_a_new_kind_joins_the_fast_path_by_a_rule(monkeypatch):
    def blob_rule(node, gen, coords):
        return gen.op("subk", gen.op("hyp3", *coords), gen.const(1.0))
    monkeypatch.setitem(fast.RULES, _Blob, blob_rule)
    part = difference(_Blob().scale(2.0), box(1.0))
    compiled = fast.CompiledSolid(part)
    assert compiled.backend == "numba"
    pts = np.random.default_rng(4).uniform(-3, 3, (30000, 3))
    np.testing.assert_allclose(compiled(pts, prune=True), fast._numpy_evaluate(part, pts), rtol=TOL, atol=TOL)


def test_missing_numba_falls_back_silently(monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba -> ImportError
    assert not fast.numba_available()
    part = _plate().translate((0.1, 0.0, 0.0))
    compiled = compile_solid(part)
    assert compiled.backend == "numpy" and compiled.tape is None
    pts = np.random.default_rng(6).uniform(-4, 4, (fast.AUTO_MIN_POINTS + 3, 3))
    ref = fast._numpy_evaluate(part, pts)
    assert np.array_equal(compiled(pts), ref)
    assert np.array_equal(part(pts), ref)


def test_register_rule_validates_its_arguments():
    with pytest.raises(TypeError, match="cls: expected a Solid subclass"):
        register_rule(int)
    with pytest.raises(ValueError, match="prune: expected one of"):
        register_rule(_Blob, prune="median")
    with pytest.raises(TypeError, match="solid: expected a Solid, got str"):
        compile_solid("sphere")
    with pytest.raises(ValueError, match="points: expected an array of shape"):
        compile_solid(sphere(1.0))(np.zeros((3, 2)))


def test_points_on_a_plane_are_binned_in_two_dimensions():
    g, scale = prune.grid(np.zeros(3), np.array([2.0, 1.0, 0.0]), 256 * 50)
    assert g.tolist() == [10, 5, 1] and scale[2] == 0.0
    assert prune.grid(np.zeros(3), np.array([np.inf, 1.0, 1.0]), 1000) is None
    part = _plate()
    xy = np.random.default_rng(8).uniform(-4.5, 4.5, (30000, 2))
    pts = np.column_stack([xy, np.full(len(xy), 0.25)])
    np.testing.assert_allclose(compile_solid(part)(pts, prune=True), fast._numpy_evaluate(part, pts),
                               rtol=TOL, atol=TOL)


def test_calls_from_several_threads_at_once():
    from concurrent.futures import ThreadPoolExecutor
    part = _plate()
    compiled = compile_solid(part)
    rng = np.random.default_rng(10)
    batches = [rng.uniform(-5, 5, (20000 + 1000 * i, 3)) for i in range(6)]
    with ThreadPoolExecutor(3) as pool:
        results = list(pool.map(lambda p: compiled(p, prune=True), batches))
    for pts, values in zip(batches, results):
        np.testing.assert_allclose(values, fast._numpy_evaluate(part, pts), rtol=TOL, atol=TOL)


def test_group_bounds_are_the_frames_norms_and_operands_lipschitz_constants():
    # A union below a scale by 2: operand bounds grow with the frame's norm (1/2 in the operands'
    # coordinates); a union of two spheres has Lipschitz constant 1 per operand.
    inner = union(sphere(1.0), sphere(1.0, center=(3.0, 0.0, 0.0)))
    tape = fast.Tape(inner.scale(2.0) - box(0.5))
    assert len(tape.group_bounds) == len(tape.groups)
    for (node, frame, slots, _), bounds in zip(tape.groups, tape.group_bounds):
        if frame is None or len(slots) != len(node.children):
            assert bounds is None
            continue
        norm, lips = bounds
        assert norm == float(np.linalg.norm(frame[0], 2))
        assert lips.shape == (len(node.children), 1)
        assert lips[:, 0].tolist() == [c.lipschitz for c in node.children]
    norms = sorted(b[0] for b in tape.group_bounds if b is not None)
    assert norms[0] == pytest.approx(0.5) and norms[-1] == pytest.approx(1.0)
