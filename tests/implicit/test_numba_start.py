"""Cached kernels load without numba's target refresh (`implicit.evaluate.numba_start`).

A throw-away module of cached kernels (one allocating an array, one parallel) is compiled
in a first fresh interpreter, then loaded in a second: the second gives the same values,
never imports numba's linalg registry (the refresh's mark), and still compiles a new
kernel that needs it.
"""

import json
import os
import subprocess
import sys
import textwrap

import pytest

pytest.importorskip("numba")

KERNELS = textwrap.dedent('''
    import numba
    import numpy as np

    @numba.njit(cache=True)
    def cumulative(x):
        out = np.empty(x.size)        # an allocation: needs numba's runtime
        total = 0.0
        for i in range(x.size):
            total += x[i] * x[i]
            out[i] = total
        return out

    @numba.njit(cache=True, parallel=True)
    def doubled(x):
        out = np.empty_like(x)
        for i in numba.prange(x.size):
            out[i] = 2.0 * x[i]
        return out
''')

JOB = textwrap.dedent('''
    import json, sys
    import implicit  # installs the start-up
    import numpy as np
    import numba
    import kernels
    x = np.arange(1.0, 6.0)
    a = kernels.cumulative(x).tolist()
    b = kernels.doubled(x).tolist()
    refreshed = "numba.np.linalg" in sys.modules
    @numba.njit
    def norm(v):
        return np.linalg.norm(v)       # typing this needs the registries the load skipped
    print(json.dumps(dict(a=a, b=b, refreshed=refreshed, norm=norm(x))))
''')


def _run(tmp_path, **env):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(tmp_path), **env)
    proc = subprocess.run([sys.executable, "-c", JOB], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_cached_kernels_load_without_the_refresh_and_compile_after(tmp_path):
    (tmp_path / "kernels.py").write_text(KERNELS)
    first = _run(tmp_path)
    assert first["refreshed"]  # compiling refreshes, as numba does
    second = _run(tmp_path)
    assert second["a"] == [1.0, 5.0, 14.0, 30.0, 55.0]
    assert second["b"] == [2.0, 4.0, 6.0, 8.0, 10.0]
    assert not second["refreshed"]
    assert second["norm"] == pytest.approx(55.0 ** 0.5, rel=1e-15)
    # numba's own start-up on request: the same values, with the refresh
    full = _run(tmp_path, IMPLICAD_NUMBA_FULL_START="1")
    assert full["refreshed"] and full["a"] == second["a"] and full["b"] == second["b"]


def test_install_is_idempotent_and_marks_the_loader():
    import numba.core.caching as caching

    from implicit.evaluate import numba_start

    numba_start.install()
    numba_start.install()
    if os.environ.get(numba_start.FULL_START) != "1":
        assert numba_start.installed()
        assert caching.Cache.load_overload.__wrapped__ is not None
        assert not hasattr(caching.Cache.load_overload.__wrapped__, "__wrapped__")  # wrapped once
