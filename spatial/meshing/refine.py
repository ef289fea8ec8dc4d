"""Vertices moved onto the true surface along their lattice edge, and those that need not move."""

from __future__ import annotations

import numpy as np

from .arrays import EVAL_CHUNK, REFINE_ACCEPT, REFINE_STEPS, REFINE_TOL, ZERO_NUDGE, _chunks_on_threads
from .kernels import edge_points, illinois_step

__all__ = []


def _certified(f0, f1, h, lip):
    """Vertices whose linear interpolation is already within ``REFINE_ACCEPT * h`` of the level.

    On an edge of length ``h`` with end values ``f0 < 0 < f1`` (or the
    reverse), an ``L``-Lipschitz field has a root in ``[|f0| / (L h), 1 - |f1|
    / (L h)]``, an interval that holds the interpolated point too; so ``|f|``
    there is at most ``L h w`` with ``w = 1 - (|f0| + |f1|) / (L h)``.  An
    edge crossing a plane square on has ``w = 0``.  Ends pushed off the
    level (`ZERO_NUDGE`) are not trusted.
    """
    if not (np.isfinite(lip) and lip > 0):
        return np.zeros(f0.shape[0], dtype=bool)
    floor = np.float32(ZERO_NUDGE * h * (1 + 1e-3))
    a = np.abs(f0)
    trusted = a > floor
    both = np.abs(f1)
    trusted &= both > floor
    both += a
    del a
    # L h w = L h - (|f0| + |f1|) <= REFINE_ACCEPT h; single precision is ample for that
    trusted &= both >= np.float32(lip * h - REFINE_ACCEPT * h)
    return trusted


def _refine_on_edges(solid, origin, nodes, axis, h, t, f0, f1, rows=None, steps=REFINE_STEPS, tol=REFINE_TOL,
                     accept=REFINE_ACCEPT, chunk=EVAL_CHUNK, threads=1):
    """Illinois regula falsi for the root of f along each vertex's edge, in place.

    Vertex ``i`` lies at ``origin + (nodes[i] + t[i] * e[axis[i]]) * h``.  The bracket
    ``[a, b]`` (initially ``[0, 1]``, end values of opposite signs) is kept,
    so every vertex stays on its edge.  Only vertices whose value is still
    above ``tol * h`` are updated; those already within ``accept * h`` take
    that last update without being evaluated again.  Works on chunks of
    vertices (`rows`, default all) to bound the temporaries; `t` is updated
    in place; the chunks run on `threads` threads.  Returns the number of evaluations spent.
    """
    rows = np.arange(t.shape[0]) if rows is None else np.asarray(rows)
    origin = np.asarray(origin, dtype=np.float64)
    used = []

    def work(s0, s1):
        # the chunks' rows are disjoint: each writes its own entries of t
        sl = rows[s0:s1]
        t[sl], n = _refine_chunk(solid, nodes, axis, origin, sl, h, t[sl], f0[sl], f1[sl], steps, tol, accept)
        used.append(n)

    _chunks_on_threads(work, rows.shape[0], chunk, threads=threads)
    return sum(used)


def _refine_chunk(solid, nodes, axis, origin, rows, h, t, fa, fb, steps, tol, accept):
    n = t.shape[0]
    t = t.astype(np.float64)  # a copy
    a = np.zeros(n)
    b = np.ones(n)
    fa = fa.astype(np.float64)
    fb = fb.astype(np.float64)
    side = np.zeros(n, dtype=np.int8)
    active = np.arange(n, dtype=np.int64)
    q = np.empty((n, 3))
    spent = 0
    for step in range(steps):
        if active.size == 0:
            break
        edge_points(nodes, axis, origin, h, rows, active, t, q)
        ft = solid(q[:active.size])
        spent += active.size
        active = illinois_step(active, ft, t, a, b, fa, fb, side, step, tol * h, accept * h)
    return t, spent
