"""Certified sign of the Jacobian determinant of 10-node tetrahedra (Bezier bounds).

The Jacobian determinant of a quadratic tetrahedron is a cubic polynomial of
the natural coordinates.  Written in the Bernstein basis of degree 3 (20
coefficients) it lies between its smallest and largest coefficient, and
it equals its coefficient at each corner.  So: every coefficient > 0 proves
the element valid; a value < 0 at a lattice point proves it folded; in
between, the element is split into 8 sub-tetrahedra (the coefficients of
each piece are a fixed linear map of the parent's) and the test repeats on
the pieces.  This is the positivity test of gmsh's curved-mesh validity
check (A. Johnen, J.-F. Remacle, C. Geuzaine, "Geometrical validity of
curvilinear finite elements", J. Comput. Phys. 233, 2013,
doi:10.1016/j.jcp.2012.08.051), done for all elements at once.
"""

from __future__ import annotations

from math import factorial

import numpy as np

__all__ = ["jacobian_sign", "jacobian_bezier"]

_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
_DL = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
#: Multi-indices (i, j, k, l), i + j + k + l = 3, of the cubic Bernstein basis.
_ALPHA = np.array([(i, j, k, 3 - i - j - k) for i in range(4) for j in range(4 - i) for k in range(4 - i - j)])


def _bernstein(bary):
    """Cubic Bernstein polynomials at barycentric points ``(p, 4)`` -> ``(p, 20)``."""
    coef = np.array([factorial(3) / np.prod([factorial(a) for a in al]) for al in _ALPHA])
    return coef * np.prod(bary[:, None, :] ** _ALPHA[None, :, :], axis=2)


def _lattice(corners):
    """The 20 lattice points alpha/3 of a sub-tetrahedron given by its 4 barycentric corners."""
    return (_ALPHA / 3.0) @ corners


_REF = np.eye(4)
_LAGRANGE_POINTS = _lattice(_REF)  # barycentric (L0, L1, L2, L3)
_B = _bernstein(_LAGRANGE_POINTS)
_B_INV = np.linalg.inv(_B)


def _children():
    """Barycentric corners of the 8 sub-tetrahedra of the midpoint split of the reference tet."""
    v = list(_REF)
    m = {(a, b): 0.5 * (_REF[a] + _REF[b]) for a in range(4) for b in range(a + 1, 4)}
    kids = [[v[0], m[0, 1], m[0, 2], m[0, 3]], [m[0, 1], v[1], m[1, 2], m[1, 3]],
            [m[0, 2], m[1, 2], v[2], m[2, 3]], [m[0, 3], m[1, 3], m[2, 3], v[3]]]
    # The octahedron around the diagonal m02-m13.
    ring = [m[0, 1], m[1, 2], m[2, 3], m[0, 3]]
    for a in range(4):
        kids.append([m[0, 2], m[1, 3], ring[a], ring[(a + 1) % 4]])
    return np.array(kids)


#: Bezier coefficients of each child piece from those of the parent: (8, 20, 20).
_SPLIT = np.stack([_B_INV @ _bernstein(_lattice(k)) for k in _children()])


def _dn(bary):
    """Derivatives of the 10 quadratic shape functions at barycentric points: ``(p, 10, 3)``."""
    p = len(bary)
    dn = np.zeros((p, 10, 3))
    for k in range(4):
        dn[:, k] = (4 * bary[:, k:k + 1] - 1) * _DL[k]
    for e, (i, j) in enumerate(_EDGES):
        dn[:, 4 + e] = 4 * (bary[:, i:i + 1] * _DL[j] + bary[:, j:j + 1] * _DL[i])
    return dn


_DN_LATTICE = _dn(_LAGRANGE_POINTS)


def jacobian_bezier(points, tets10) -> np.ndarray:
    """Bezier coefficients ``(m, 20)`` of the Jacobian determinant of each 10-node element.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> e = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    >>> x = np.concatenate([p, 0.5 * (p[e[:, 0]] + p[e[:, 1]])])
    >>> np.allclose(jacobian_bezier(x, [np.arange(10)]), 1.0)
    True
    """
    x = np.asarray(points, dtype=np.float64)[np.asarray(tets10)]
    jac = np.einsum("mak,pal->mpkl", x, _DN_LATTICE)
    return np.linalg.det(jac) @ _B_INV.T


def jacobian_sign(points, tets10, *, depth: int = 5, rtol: float = 1e-12) -> np.ndarray:
    """Sign of the smallest Jacobian determinant of each 10-node element: ``(m,)`` int8.

    +1: proven positive everywhere in the element; -1: negative somewhere
    (a point with a negative value was found); 0: not settled after `depth`
    splits (the determinant touches zero within ``rtol`` of its size).

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> e = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    >>> x = np.concatenate([p, 0.5 * (p[e[:, 0]] + p[e[:, 1]])])
    >>> x[4] = [0.5, 0.6, 0.0]  # mid node of edge 01 pushed past the opposite edge: folds
    >>> int(jacobian_sign(x, [np.arange(10)])[0])
    -1
    """
    coef = jacobian_bezier(points, tets10)
    m = len(coef)
    sign = np.zeros(m, dtype=np.int8)
    scale = np.abs(coef).max(axis=1) * rtol
    owner = np.arange(m)
    c = coef
    for level in range(depth + 1):
        neg = ((c @ _B.T) < -scale[owner][:, None]).any(axis=1)
        pos = c.min(axis=1) > scale[owner]
        bad = np.unique(owner[neg])
        sign[bad] = -1
        # an element is open while it has a piece neither proven positive nor negative
        open_ = ~pos & ~neg & (sign[owner] == 0)
        if level == depth or not open_.any():
            done = np.setdiff1d(np.arange(m), np.unique(owner[open_]))
            settled = done[sign[done] == 0]
            sign[settled] = 1
            break
        c = np.einsum("cpq,nq->ncp", _SPLIT, c[open_]).reshape(-1, 20)
        owner = np.repeat(owner[open_], 8)
    return sign
