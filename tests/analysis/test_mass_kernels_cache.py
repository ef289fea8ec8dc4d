"""The compiled sums of the mass properties come from numba's on-disk cache: a second process compiles
nothing (as closures they were compiled again in every process, about 1.5 s of CPU each time)."""

import os
import subprocess
import sys

import pytest

pytest.importorskip("numba")

JOB = ("import numpy as np; from spatial.analysis.mass_solid import _kernels; level, shell = _kernels(); "
       "p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float); "
       "t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]); "
       "v, mids, w = level(p, t, np.zeros(3)); s = shell(mids, w, np.zeros(3)); "
       "print(repr(float(v[0])), repr(float(s[0])))")


def _run(cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), NUMBA_DEBUG_CACHE="1")
    proc = subprocess.run([sys.executable, "-c", JOB], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc.stdout + proc.stderr


def test_second_process_loads_the_mass_kernels(tmp_path):
    first = _run(tmp_path)
    assert "mass_kernels" in first and "data saved" in first
    second = _run(tmp_path)
    saved = [line for line in second.splitlines() if "saved" in line and "mass_kernels" in line]
    assert saved == [], "a second process compiled the mass kernels again:\n" + "\n".join(saved)
    assert "data loaded" in second
    last = second.strip().splitlines()[-1].split()
    # the unit corner tetrahedron's volume (1/6), the same from the cached kernels
    assert abs(float(last[0]) - 1.0 / 6.0) < 1e-15 and first.strip().splitlines()[-1] == second.strip().splitlines()[-1]
