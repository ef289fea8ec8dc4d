"""The numba interpreter that runs tapes: kernels compiled once per process, and their calls.

numba is optional: without it `numba_available` is False and `implicit.evaluate.compile`
falls back to numpy.
"""

from __future__ import annotations

import threading
import time

import numpy as np

from . import prune
from ..csg import Difference, Union
from ..primitives import Box, Cone, Sphere, Torus
from .tape import (OPS, PRUNE_MODES, RULES, KernelSource, Tape, Unsupported,  # noqa: F401
                   _numpy_evaluate, register_rule)

__all__ = ["numba_available", "COMPILE_SECONDS", "prime_cache"]


# ---------------------------------------------------------------------------
# numba, optional
# ---------------------------------------------------------------------------

def _load_numba():
    """Return the numba module, or None when it cannot be imported."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return None
    return numba


def numba_available() -> bool:
    """True when numba can be imported (the compiled path is possible)."""
    return _load_numba() is not None


# ---------------------------------------------------------------------------
# the interpreter (numba, compiled once per machine: implicit.evaluate.jit)
# ---------------------------------------------------------------------------

_KERNELS: dict = {}
_KERNEL_LOCK = threading.Lock()
#: Seconds spent compiling each kernel ("serial", "parallel", "bin").
COMPILE_SECONDS: dict[str, float] = {}


def _kernel(name: str):
    """The compiled kernel `name` ("serial", "parallel", "bin", "bounds" or
    "unsort"), or None when numba is not importable."""
    kernel = _KERNELS.get(name)
    if kernel is not None:
        return kernel
    numba = _load_numba()
    if numba is None:
        return None
    with _KERNEL_LOCK:
        from . import jit  # numba's cache serves these module-level kernels in every later process

        if name not in _KERNELS:
            start = time.perf_counter()
            if name == "bin":
                kernel = jit.bin_points
                kernel(np.zeros((1, 3)), np.zeros(3), np.ones(3), np.ones(3, np.int64), np.zeros(1, np.int32),
                       np.zeros(1, np.int32), np.zeros((1, 3)))
            elif name == "unsort":
                kernel = jit.unsort
                kernel(np.zeros(1), np.zeros(1, np.int32), np.zeros(1))
            elif name == "bounds":
                kernel = jit.bounds_of
                kernel(np.zeros((1, 3)))
            else:
                kernel = jit.run_parallel if name == "parallel" else jit.run_serial
                tape = Tape(Difference(Sphere(1.0), Cone(1.0, 1.0), Union(Box(), Torus(1.0, 0.5))))
                _call(kernel, tape, np.zeros((4, 3)))
                _call(kernel, tape, np.zeros((4, 3)), record=True)
            COMPILE_SECONDS[name] = time.perf_counter() - start
            _KERNELS[name] = kernel
    return _KERNELS[name]


#: Points per block of the interpreter (registers stay in the L1/L2 cache).
BLOCK = 256


def _call(kernel, tape: Tape, flat, starts=None, flags=None, nthreads=1, *, record=False, out=None,
          inputs=None):
    """Run `tape` on the contiguous points `flat` (n, 3).

    Without `starts` the points are cut into equal bins with every flag set.
    Returns the values (n,), or with `record` the stored operand values
    ``(tape.nstore, n)`` of the recording tape.
    """
    n = flat.shape[0]
    if inputs is None:
        inputs = tape.inputs(flat)
    if starts is None:
        nb = max(1, min(nthreads * 64, -(-n // BLOCK)))
        starts = np.linspace(0, n, nb + 1).astype(np.int64)
        flags = np.ones((nb, max(1, len(tape.flags))), dtype=np.bool_)
    if out is None:
        out = np.empty(n)
    if record:
        rec = np.empty((tape.nstore, n))
        kernel(tape.record, tape.consts, tape.nreg, tape.result, flat, starts, flags, out, BLOCK, nthreads, rec, inputs)
        return rec
    kernel(tape.code, tape.consts, tape.nreg, tape.result, flat, starts, flags, out, BLOCK, nthreads, _NO_RECORD, inputs)
    return out


_NO_RECORD = np.empty((0, 0))


def _flags(tape: Tape, lo: np.ndarray, hi: np.ndarray, kernel) -> np.ndarray:
    """Pruning flags ``(m, len(tape.flags))`` of the boxes `lo`..`hi`, the
    operand values at their centres from one run of the recording tape."""
    return prune.operand_flags(tape, lo, hi, lambda centres: _call(kernel, tape, centres, record=True))


def prime_cache() -> dict:
    """Compile (or load) every kernel once, so that later processes find them in numba's cache.

    `make` set-up calls it after installing, so a fresh clone's first job does not
    compile.  Returns the seconds each kernel took (empty without numba).

    Examples
    --------
    >>> sorted(prime_cache()) if numba_available() else []    # doctest: +SKIP
    ['bin', 'bounds', 'parallel', 'serial', 'unsort']
    """
    if not numba_available():
        return {}
    for name in ("serial", "parallel", "bin", "bounds", "unsort"):
        _kernel(name)
    return dict(COMPILE_SECONDS)
