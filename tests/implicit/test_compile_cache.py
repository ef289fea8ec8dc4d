"""numba's on-disk cache serves the evaluator's kernels: a second process compiles nothing.

Each run is a fresh interpreter with its own cache folder (NUMBA_CACHE_DIR), so the
test does not depend on what earlier tests or processes left in ``__pycache__``.
"""

import os
import subprocess
import sys

import pytest

pytest.importorskip("numba")

JOB = ("import numpy as np, implicit; from implicit.evaluate.kernels import prime_cache; prime_cache(); "
       "implicit.sphere(1.0)(np.random.default_rng(0).random((200_000, 3)))")


def _run(cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), NUMBA_DEBUG_CACHE="1")
    proc = subprocess.run([sys.executable, "-c", JOB], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc.stdout + proc.stderr


def _files(folder):
    return sorted(os.path.relpath(os.path.join(d, f), folder) for d, _, fs in os.walk(folder) for f in fs)


def test_second_process_loads_every_kernel_and_saves_nothing(tmp_path):
    first = _run(tmp_path)
    assert "data saved" in first  # the first process compiled and stored the kernels
    after_first = _files(tmp_path)
    second = _run(tmp_path)
    saved = [line for line in second.splitlines() if "saved" in line]
    assert saved == [], "a second process compiled again:\n" + "\n".join(saved)
    assert "data loaded" in second
    _run(tmp_path)
    assert _files(tmp_path) == after_first  # no growth of cache files across runs
