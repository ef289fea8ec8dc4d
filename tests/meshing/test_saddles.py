"""The tie finder of `saddles` marks the same corners as its plain reference, on tie-rich blocks."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from spatial.meshing.saddles import _kernel, break_ties


def _reference(v, out):
    """The finder as first written: every cube's eight corners read and counted."""
    nx, ny, nz = v.shape
    found = 0

    def face(p, q, r, s):
        a, b, c, d = v[p], v[q], v[r], v[s]
        if (a < 0) != (c < 0) or (b < 0) != (d < 0) or (a < 0) == (b < 0):
            return 0
        if np.float64(a) * np.float64(c) != np.float64(b) * np.float64(d):
            return 0
        if a < 0:
            out[p] = out[r] = True
        else:
            out[q] = out[s] = True
        return 1

    for i in range(nx - 1):
        for j in range(ny - 1):
            for k in range(nz - 1):
                corners = v[i:i + 2, j:j + 2, k:k + 2]
                neg = int(np.count_nonzero(corners < 0))
                same = bool(np.all(np.abs(corners) == abs(v[i, j, k])))
                if neg < 2 or neg > 6:
                    continue
                i1, j1, k1 = i + 1, j + 1, k + 1
                for z in (k, k1):
                    found += face((i, j, z), (i1, j, z), (i1, j1, z), (i, j1, z))
                for y in (j, j1):
                    found += face((i, y, k), (i1, y, k), (i1, y, k1), (i, y, k1))
                for x in (i, i1):
                    found += face((x, j, k), (x, j1, k), (x, j1, k1), (x, j, k1))
                if neg == 2 and same:
                    for di in range(2):
                        for dj in range(2):
                            for dk in range(2):
                                if v[i + di, j + dj, k + dk] < 0 and v[i1 - di, j1 - dj, k1 - dk] < 0:
                                    out[i + di, j + dj, k + dk] = True
                                    found += 1
    return found


def _same(v):
    a = np.zeros(v.shape, bool)
    b = np.zeros(v.shape, bool)
    fa = _reference(v, a)
    fb = _kernel()(v, b)
    assert fa == fb
    assert np.array_equal(a, b)
    return fa


def test_same_marks_on_tie_rich_blocks():
    rng = np.random.default_rng(0)
    found = 0
    for trial in range(60):
        shape = tuple(int(s) for s in rng.integers(2, 7, 3))
        v = rng.choice([-1.0, 1.0, -0.5, 0.5], size=shape).astype(np.float32)
        found += _same(v)
    assert found > 100   # the blocks did hold ties of both kinds


def test_checkerboard_is_all_ties():
    v = np.where(np.indices((4, 4, 4)).sum(axis=0) % 2, 1.0, -1.0).astype(np.float32)
    assert _same(v) > 0
    out = break_ties(v)
    assert out is not v and np.all(out[v < 0] < -1.0) and np.all(out[v > 0] == 1.0)


@settings(max_examples=40, deadline=None)
@given(arrays(np.float32, st.tuples(st.integers(2, 5), st.integers(2, 5), st.integers(2, 5)),
              elements=st.sampled_from([-2.0, -1.0, -0.5, 0.5, 1.0, 2.0])))
def test_same_marks_law(v):
    _same(v)
