"""The compiled polygon distance is served by numba's on-disk cache: a second process compiles nothing.

The kernel measures outlines of many edges (a gear's), so every process meshing a gear
used to compile it again when it was a closure built on first use.
"""


import numpy as np
import pytest

pytest.importorskip("numba")

JOB = ("import numpy as np; from implicit.profiles import polygon_distance; "
       "t = np.linspace(0, 2 * np.pi, 64, endpoint=False); "
       "v = np.c_[np.cos(t), np.sin(t)] * (1 + 0.1 * np.cos(8 * t))[:, None]; "
       "print(float(polygon_distance(np.random.default_rng(0).random((500, 2)) * 3 - 1.5, v).sum()))")


def test_second_process_loads_the_polygon_kernel(fresh_cache_run):
    first = fresh_cache_run(JOB)
    assert "polygon_signed_distance" in first and "data saved" in first
    second = fresh_cache_run(JOB)
    saved = [line for line in second.splitlines() if "saved" in line]
    assert saved == [], "a second process compiled the polygon kernel again:\n" + "\n".join(saved)
    assert "data loaded" in second
    # the same figure from the cached kernel as from the freshly compiled one
    assert first.strip().splitlines()[-1] == second.strip().splitlines()[-1]


def test_compiled_polygon_distance_equals_the_vectorized_form():
    from implicit import profiles

    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    v = np.c_[np.cos(t), np.sin(t)] * (1 + 0.1 * np.cos(8 * t))[:, None]
    p = np.random.default_rng(1).random((400, 2)) * 3 - 1.5
    compiled = profiles.polygon_distance(p, v)
    few = profiles.polygon_distance(p[:40], v)          # under 64 points: the numpy form
    np.testing.assert_allclose(compiled[:40], few, rtol=0, atol=1e-12)
    assert np.all(compiled[np.hypot(p[:, 0], p[:, 1]) < 0.85] < 0)   # inside the outline
    assert np.all(compiled[np.hypot(p[:, 0], p[:, 1]) > 1.15] > 0)
