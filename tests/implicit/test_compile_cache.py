"""numba's on-disk cache serves the evaluator's kernels: a second process compiles nothing.

Each run is a fresh interpreter with its own cache folder (NUMBA_CACHE_DIR), so the
test does not depend on what earlier tests or processes left in ``__pycache__``.
"""

import os

import pytest

pytest.importorskip("numba")

JOB = ("import numpy as np, implicit; from implicit.evaluate.kernels import prime_cache; prime_cache(); "
       "implicit.sphere(1.0)(np.random.default_rng(0).random((200_000, 3)))")


def _files(folder):
    return sorted(os.path.relpath(os.path.join(d, f), folder) for d, _, fs in os.walk(folder) for f in fs)


def test_second_process_loads_every_kernel_and_saves_nothing(fresh_cache_run, tmp_path):
    first = fresh_cache_run(JOB)
    assert "data saved" in first  # the first process compiled and stored the kernels
    after_first = _files(tmp_path)
    second = fresh_cache_run(JOB)
    saved = [line for line in second.splitlines() if "saved" in line]
    assert saved == [], "a second process compiled again:\n" + "\n".join(saved)
    assert "data loaded" in second
    fresh_cache_run(JOB)
    assert _files(tmp_path) == after_first  # no growth of cache files across runs
