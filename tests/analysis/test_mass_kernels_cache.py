"""The compiled sums of the mass properties come from numba's on-disk cache: a second process compiles
nothing (as closures they were compiled again in every process, about 1.5 s of CPU each time)."""


import pytest

pytest.importorskip("numba")

JOB = ("import numpy as np; from spatial.analysis.mass_solid import _kernels; level, shell = _kernels(); "
       "p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float); "
       "t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]); "
       "v, mids, w = level(p, t, np.zeros(3)); s = shell(mids, w, np.zeros(3)); "
       "print(repr(float(v[0])), repr(float(s[0])))")


def test_second_process_loads_the_mass_kernels(fresh_cache_run):
    first = fresh_cache_run(JOB)
    assert "mass_kernels" in first and "data saved" in first
    second = fresh_cache_run(JOB)
    saved = [line for line in second.splitlines() if "saved" in line and "mass_kernels" in line]
    assert saved == [], "a second process compiled the mass kernels again:\n" + "\n".join(saved)
    assert "data loaded" in second
    last = second.strip().splitlines()[-1].split()
    # the unit corner tetrahedron's volume (1/6), the same from the cached kernels
    assert abs(float(last[0]) - 1.0 / 6.0) < 1e-15 and first.strip().splitlines()[-1] == second.strip().splitlines()[-1]
