"""Ties of marching cubes' ambiguous faces and cubes, broken towards joining the material.

Two solids touching along an edge or at a point (two boxes edge to edge,
two cubes corner to corner, two tangent spheres) make a regularized union
that is not a manifold there.  A manifold mesh must either fuse the bodies
(a neck about a voxel wide) or keep them apart; the policy here is to **fuse
them, wherever the contact falls on the lattice**.  Marching cubes already
fuses them almost everywhere: a lattice line through the contact has nodes
inside both bodies, and an ambiguous face or cube whose inside corners are
deeper than its outside ones are far joins them (Lewiner's asymptotic
decider).  What is left is the exact tie -- the contact half a voxel from
the nodes, where the inside and outside corners of an ambiguous face (or
the two inside corners of a cube, opposite each other) are equally far
from the surface -- which scikit-image settles by keeping them apart.

`break_ties` finds those ties in a block of samples and deepens the inside
corners by a relative ``TIE_PUSH`` (a few units in the last place of a
float32), so that the decider joins them; every other sample is left as it
was (the meshes of solids without such ties keep their bits).
"""

from __future__ import annotations

import numpy as np

__all__ = ["break_ties", "break_ties_marked", "TIE_PUSH"]

#: Relative deepening of an inside corner of a tie (float32 keeps it: 2**-20 is about 8 ulp).
TIE_PUSH = 2.0 ** -20


def _face(v, out, p, q, r, s):
    """One face with corners p, q, r, s in order (index triples): marks its inside corners at a tie."""
    a, b, c, d = v[p[0], p[1], p[2]], v[q[0], q[1], q[2]], v[r[0], r[1], r[2]], v[s[0], s[1], s[2]]
    # diagonal pattern: a, c on one side, b, d on the other
    if (a < 0) != (c < 0) or (b < 0) != (d < 0) or (a < 0) == (b < 0):
        return 0
    if np.float64(a) * np.float64(c) != np.float64(b) * np.float64(d):
        return 0
    if a < 0:
        out[p[0], p[1], p[2]] = True
        out[r[0], r[1], r[2]] = True
    else:
        out[q[0], q[1], q[2]] = True
        out[s[0], s[1], s[2]] = True
    return 1


def _square_inside(v, i, out):
    """``out[j, k]``: how many of the nodes ``(i, j..j+1, k..k+1)`` of plane `i` are inside (< 0)."""
    ny, nz = out.shape
    for j in range(ny):
        for k in range(nz):
            out[j, k] = ((v[i, j, k] < 0) + (v[i, j + 1, k] < 0) + (v[i, j, k + 1] < 0)
                         + (v[i, j + 1, k + 1] < 0))


def _find(v, out):
    """Marks in `out` the inside corners of ambiguous faces and body-diagonal cubes at a tie."""
    nx, ny, nz = v.shape
    found = 0
    # a cube's inside corners counted from its two yz squares' counts, each square counted once
    # (most cubes have 0 or 8 and are skipped after two additions)
    lower = np.empty((ny - 1, nz - 1), np.int8)
    upper = np.empty((ny - 1, nz - 1), np.int8)
    _square_inside(v, 0, lower)
    for i in range(nx - 1):
        _square_inside(v, i + 1, upper)
        for j in range(ny - 1):
            for k in range(nz - 1):
                neg = lower[j, k] + upper[j, k]
                if neg < 2 or neg > 6:        # no ambiguous face in a cube with 0, 1, 7 or 8 inside
                    continue
                i1, j1, k1 = i + 1, j + 1, k + 1
                for z in (k, k1):
                    found += _face(v, out, (i, j, z), (i1, j, z), (i1, j1, z), (i, j1, z))
                for y in (j, j1):
                    found += _face(v, out, (i, y, k), (i1, y, k), (i1, y, k1), (i, y, k1))
                for x in (i, i1):
                    found += _face(v, out, (x, j, k), (x, j1, k), (x, j1, k1), (x, j, k1))
                if neg != 2:
                    continue
                # two opposite corners inside, six outside, all equally far: the tie of the interior test
                mag = abs(v[i, j, k])
                same = True
                for di in range(2):
                    for dj in range(2):
                        for dk in range(2):
                            if abs(v[i + di, j + dj, k + dk]) != mag:
                                same = False
                if same:
                    for di in range(2):
                        for dj in range(2):
                            for dk in range(2):
                                if v[i + di, j + dj, k + dk] < 0 and v[i1 - di, j1 - dj, k1 - dk] < 0:
                                    out[i + di, j + dj, k + dk] = True
                                    found += 1
        lower, upper = upper, lower
    return found


_KERNEL: list = []


def _kernel():
    if not _KERNEL:
        try:
            import numba
        except ImportError:  # pragma: no cover - numba is a dependency
            _KERNEL.append(_find)
        else:
            global _face, _square_inside
            _face = numba.njit(cache=True, nogil=True, inline="always")(_face)
            _square_inside = numba.njit(cache=True, nogil=True)(_square_inside)
            _KERNEL.append(numba.njit(cache=True, nogil=True)(_find))
    return _KERNEL[0]


def break_ties(values):
    """`values` with the inside corners of marching cubes' exact ties deepened (see the module notes).

    Parameters
    ----------
    values : (a, b, c) float32
        A block of samples, negative inside.

    Returns
    -------
    ndarray
        `values` itself when it holds no tie, else a copy with the tie corners deepened.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.full((2, 2, 2), 0.5, np.float32); v[0, 0, :] = v[1, 1, :] = -0.5
    >>> out = break_ties(v)
    >>> bool(out[0, 0, 0] < -0.5), out is v
    (True, False)
    """
    if values.ndim != 3 or min(values.shape) < 2:
        return values
    return break_ties_marked(values, np.zeros(values.shape, dtype=np.bool_))


def break_ties_marked(values, marks):
    """`break_ties` with a scratch array of marks lent by the caller (no array made per block).

    Parameters
    ----------
    values : (a, b, c) float32
        A block of samples, negative inside, at least 2 along every axis.
    marks : (a, b, c) bool
        All False on entry; all False again on return.

    Returns
    -------
    ndarray
        `values` itself when it holds no tie, else a copy with the tie corners deepened.
    """
    if _kernel()(values, marks) == 0:
        return values   # nothing marked: the marks are still clear
    out = values.copy()
    out[marks] *= values.dtype.type(1.0 + TIE_PUSH)
    marks[...] = False
    return out
