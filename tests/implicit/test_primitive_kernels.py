"""The compiled capsule: numpy's distances and gradients up to rounding, and numpy's own without numba."""

import numpy as np
import pytest

import implicit.primitives as prim
from implicit import capsule
from implicit.facet_gradients import leaf_facets_with_gradients

pytest.importorskip("numba")


def _numpy_capsule(c, p):
    w = p - c._a
    if c._ab2 > 0.0:
        t = np.clip((w @ c._ab) / c._ab2, 0.0, 1.0)
        w = w - t[:, None] * c._ab
    r = np.sqrt(np.einsum("ij,ij->i", w, w))
    return r - c._r, np.divide(w, r[:, None], out=np.zeros_like(w), where=r[:, None] > 0)


@pytest.mark.parametrize("ends", [((0.0, 0.0, 0.0), (1.0, 2.0, -0.5)), ((1.0, 1.0, 1.0), (1.0, 1.0, 1.0))])
def test_compiled_capsule_is_numpys_up_to_rounding(ends):
    c = capsule(ends[0], ends[1], 0.3)
    p = np.random.default_rng(0).uniform(-2.0, 3.0, (5000, 3))
    p[0] = ends[0]                                      # on the segment: distance -r, gradient zero
    want_v, want_g = _numpy_capsule(c, p)
    assert prim.capsule_kernels() is not None
    v = c._evaluate(p)
    np.testing.assert_allclose(v, want_v, rtol=1e-13, atol=1e-13)
    assert v[0] == -0.3
    names, fv, fg = leaf_facets_with_gradients(c, p, 1e-7)
    assert names == [""] and np.array_equal(fv[0], v)    # the same loop: the same bits
    np.testing.assert_allclose(fg[0], want_g, atol=1e-12)
    assert np.array_equal(fg[0, 0], [0.0, 0.0, 0.0])
    np.testing.assert_allclose(np.linalg.norm(fg[0, 1:], axis=1), 1.0, atol=1e-12)
    # a strided or non-float input is made contiguous float64 first
    np.testing.assert_allclose(c._evaluate(np.asfortranarray(p)), v, rtol=0, atol=0)


def test_without_numba_capsules_are_evaluated_by_numpy(monkeypatch):
    c = capsule((0.0, 0.0, 0.0), (0.0, 0.0, 2.0), 0.5)
    p = np.random.default_rng(1).uniform(-1.0, 3.0, (300, 3))
    monkeypatch.setattr(prim, "_CAPSULE_KERNELS", [None])
    want_v, want_g = _numpy_capsule(c, p)
    assert np.array_equal(c._evaluate(p), want_v)
    _, fv, fg = leaf_facets_with_gradients(c, p, 1e-7)
    assert np.array_equal(fv[0], want_v) and np.array_equal(fg[0], want_g)
