"""Compiled loops of `implicit.facets.FacetField`'s deciding facet of one leaf: a sharp box, a
cylinder (from its local coordinates) and a sphere.

Each loop does, point by point, what numpy's passes over the whole array do,
with numpy's semantics where they matter for the bits: ``np.maximum(a, b)``
and ``np.minimum(a, b)`` give `b` when the two are equal (so ``-0.0`` or
``+0.0`` as numpy gives it) and NaN from either; the sum of three products
of ``np.einsum("ij,ij->i", ...)`` adds the first and the last, then the
middle; the first largest facet wins, as ``argmax`` of their stack.  So the
values and the deciding facets are numpy's bit for bit (the tests compare
them on ties, signed zeros and NaNs).  Module-level ``njit(cache=True)``
functions, loaded from numba's on-disk cache; imported on first use only
(numba is not imported with `implicit`).
"""

from __future__ import annotations

import math

import numba

__all__ = ["box_decide", "cylinder_decide", "cylinder_decide_aligned", "sphere_values"]


@numba.njit(cache=True, nogil=True, inline="always")
def _maximum(a, b):  # pragma: no cover - compiled
    """``np.maximum(a, b)`` of two floats."""
    if a != a:
        return a
    if b != b:
        return b
    return a if a > b else b


@numba.njit(cache=True, nogil=True, inline="always")
def _minimum(a, b):  # pragma: no cover - compiled
    """``np.minimum(a, b)`` of two floats."""
    if a != a:
        return a
    if b != b:
        return b
    return a if a < b else b


@numba.njit(cache=True, nogil=True, inline="always")
def _norm3(x, y, z):  # pragma: no cover - compiled
    """``np.sqrt(np.einsum("ij,ij->i", v, v))`` of the row (x, y, z): numpy sums x and z first."""
    return math.sqrt((x * x + z * z) + y * y)


@numba.njit(cache=True, nogil=True)
def box_decide(p, c, h, rr, value, dec):  # pragma: no cover - compiled
    """A sharp box's field (centre `c`, half sizes `h`, rounding `rr`) and deciding facet (0..5:
    +x +y +z -x -y -z, the first largest) at every point, into `value` and `dec`."""
    for i in range(p.shape[0]):
        q0, q1, q2 = p[i, 0] - c[0], p[i, 1] - c[1], p[i, 2] - c[2]
        u0, u1, u2 = q0 - h[0], q1 - h[1], q2 - h[2]
        d0, d1, d2 = -q0 - h[0], -q1 - h[1], -q2 - h[2]
        best, k = u0, 0
        if u1 > best:
            k = 1
        best = _maximum(best, u1)
        if u2 > best:
            k = 2
        best = _maximum(best, u2)
        if d0 > best:
            k = 3
        best = _maximum(best, d0)
        if d1 > best:
            k = 4
        best = _maximum(best, d1)
        if d2 > best:
            k = 5
        dec[i] = k
        a0, a1, a2 = _maximum(u0, d0), _maximum(u1, d1), _maximum(u2, d2)
        outside = _norm3(_maximum(a0, 0.0), _maximum(a1, 0.0), _maximum(a2, 0.0))
        inside = _minimum(_maximum(_maximum(a0, a1), a2), 0.0)
        value[i] = outside + inside - rr


@numba.njit(cache=True, nogil=True, inline="always")
def _cylinder_at(q0, q1, q2, r, hh, value, dec, i):  # pragma: no cover - compiled
    """`cylinder_decide` of one point, in the cylinder's frame."""
    dr = math.hypot(q0, q1) - r
    top, bottom = q2 - hh, -q2 - hh
    best, k = dr, 0
    if top > best:
        k = 1
    best = _maximum(best, top)
    if bottom > best:
        k = 2
    dec[i] = k
    dz = _maximum(top, bottom)
    outside = math.hypot(_maximum(dr, 0.0), _maximum(dz, 0.0))
    value[i] = outside + _minimum(_maximum(dr, dz), 0.0)


@numba.njit(cache=True, nogil=True)
def cylinder_decide_aligned(p, c, frame, r, hh, value, dec):  # pragma: no cover - compiled
    """`cylinder_decide` of a cylinder whose frame's entries are 0, 1 or -1 (its axis along x, y or z),
    from the points `p`: each local coordinate is one of ``p - c``'s, as numpy's product gives it (up to
    the sign of a zero, which no value or facet below depends on: |x| and x - hh read it not)."""
    for i in range(p.shape[0]):
        d0, d1, d2 = p[i, 0] - c[0], p[i, 1] - c[1], p[i, 2] - c[2]
        q0 = d0 * frame[0, 0] + d1 * frame[0, 1] + d2 * frame[0, 2]
        q1 = d0 * frame[1, 0] + d1 * frame[1, 1] + d2 * frame[1, 2]
        q2 = d0 * frame[2, 0] + d1 * frame[2, 1] + d2 * frame[2, 2]
        _cylinder_at(q0, q1, q2, r, hh, value, dec, i)


@numba.njit(cache=True, nogil=True)
def cylinder_decide(q, r, hh, value, dec):  # pragma: no cover - compiled
    """A cylinder's field (radius `r`, half height `hh`) and deciding facet (0 wall, 1 top, 2 bottom)
    at the points `q` in its local frame (axis z), into `value` and `dec`."""
    for i in range(q.shape[0]):
        _cylinder_at(q[i, 0], q[i, 1], q[i, 2], r, hh, value, dec, i)


@numba.njit(cache=True, nogil=True)
def sphere_values(p, c, r, value):  # pragma: no cover - compiled
    """A sphere's field (centre `c`, radius `r`) at every point, into `value`."""
    for i in range(p.shape[0]):
        value[i] = _norm3(p[i, 0] - c[0], p[i, 1] - c[1], p[i, 2] - c[2]) - r
