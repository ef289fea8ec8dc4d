"""A mid-sized call takes the compiled path in a fresh process (loading the interpreter from numba's cache)."""

from __future__ import annotations

import subprocess
import sys

CHILD = r"""
import numpy as np
from implicit import box, cylinder
from implicit.evaluate import kernels
from implicit.evaluate.compile import AUTO_MIN_POINTS
kernels.prime_cache()  # the cache as `make` set-up leaves it (loads, or compiles once)
kernels._KERNELS.clear()  # as a fresh process finds it
part = box((4.0, 3.0, 0.5)) - cylinder(0.3, 2.0)
pts = np.random.default_rng(0).uniform(-2, 2, (5000, 3))
assert pts.shape[0] < AUTO_MIN_POINTS
values = part(pts)
assert "serial" in kernels._KERNELS, "the compiled path was not taken"
assert np.allclose(values, part._evaluate(pts), atol=1e-12)
print("ok")
"""


def test_mid_sized_call_is_compiled_when_cache_is_ready():
    res = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.strip().endswith("ok")
