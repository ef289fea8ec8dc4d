"""The deciding operand of a sharp Boolean of two: what ``argmin`` / ``argmax`` of their stack picks."""

import numpy as np
import pytest

from implicit.facets import _decide


def _stacked(kind, results):
    values = np.stack([r[0] for r in results])
    decs = np.stack([r[1] for r in results])
    if kind == "difference":
        values[1:] *= -1.0
    idx = values.argmin(axis=0) if kind == "union" else values.argmax(axis=0)
    cols = np.arange(values.shape[1])
    return values[idx, cols], decs[idx, cols]


@pytest.mark.parametrize("kind", ["union", "intersection", "difference"])
def test_two_operands_decide_as_the_stack_does_ties_zeros_and_nans_included(kind):
    rng = np.random.default_rng(5)
    a = rng.integers(-3, 4, 2000).astype(np.float64)
    b = rng.integers(-3, 4, 2000).astype(np.float64)
    a[rng.random(2000) < 0.1] = np.nan
    b[rng.random(2000) < 0.1] = np.nan
    a[::7], b[::7] = 0.0, -0.0                       # ties of signed zeros: the first operand wins
    da, db = rng.integers(0, 9, 2000), rng.integers(10, 19, 2000)
    value, dec = _decide(kind, [(a, da), (b, db)])
    want_value, want_dec = _stacked(kind, [(a, da), (b, db)])
    assert np.array_equal(dec, want_dec)
    assert np.array_equal(value.view(np.int64), want_value.view(np.int64))     # the same bits
    assert (dec >= 10).any() and (dec < 10).any()
    three = [(a, da), (b, db), (-a, db + 20)]
    assert all(np.array_equal(x, y, equal_nan=True) for x, y in zip(_decide(kind, three), _stacked(kind, three)))
