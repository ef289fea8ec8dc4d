"""Transforms: translate, rotate, scale, mirror and general affine maps.

Every transform is one `Affine` node holding the map ``p -> A p + t``; the
field of the result is ``f(A^-1 (p - t)) * sigma_min(A)``.  Multiplying by the
smallest singular value keeps the result a conservative bound with the
child's Lipschitz constant: it is exact for rigid motions and uniform scales
(``sigma_min`` is then the scale), and a bound for non-uniform scale and
shear.  Chains of transforms fold into one node.
"""

from __future__ import annotations

import numpy as np

from .solid import Solid, as_finite, as_positive, as_vector, box_corners, register_operator

__all__ = ["Affine", "translate", "rotate", "scale", "mirror", "affine", "rotation_matrix"]


def rotation_matrix(angle_degrees: float, axis=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Rotation matrix (3, 3) for `angle_degrees` about `axis` (right-handed)."""
    angle = np.radians(as_finite(angle_degrees, "angle_degrees"))
    k = as_vector(axis, "axis", nonzero=True)
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * (kx @ kx)


class Affine(Solid):
    """The child mapped by ``p -> matrix @ p + offset``.

    Parameters
    ----------
    solid : Solid
    matrix : (3, 3) array_like
        Invertible linear part.
    offset : (3,) array_like
        Translation.
    """

    kind = "affine"
    __slots__ = ("_inv", "_offset", "_matrix", "_factor", "_cond")

    def __init__(self, solid: Solid, matrix, offset=(0.0, 0.0, 0.0)):
        if not isinstance(solid, Solid):
            raise TypeError(f"affine: solid must be a Solid, got {type(solid).__name__}")
        a = np.asarray(matrix, dtype=np.float64)
        if a.shape != (3, 3):
            raise ValueError(f"matrix: expected shape (3, 3), got {a.shape}")
        if not np.isfinite(a).all():
            raise ValueError("matrix: expected finite numbers")
        t = as_vector(offset, "offset")
        sv = np.linalg.svd(a, compute_uv=False)
        if sv[-1] <= 1e-12 * max(sv[0], 1e-300):
            raise ValueError(f"matrix: expected an invertible matrix, singular values {sv.tolist()}")
        lo, hi = solid.bounds
        if solid.is_empty_bounds:
            bounds = (lo, hi)
        else:
            # Interval arithmetic on p -> a p + t; zero coefficients contribute
            # nothing, so a translated or permuted half-space keeps its finite side.
            with np.errstate(invalid="ignore"):
                c_lo = np.where(a == 0.0, 0.0, a * lo)
                c_hi = np.where(a == 0.0, 0.0, a * hi)
            bounds = (np.minimum(c_lo, c_hi).sum(axis=1) + t, np.maximum(c_lo, c_hi).sum(axis=1) + t)
        rigid_or_uniform = np.isclose(sv[0], sv[-1], rtol=1e-12)
        super().__init__((solid,), {"matrix": a.tolist(), "offset": t.tolist()}, bounds,
                         exact=solid.exact and bool(rigid_or_uniform), lipschitz=solid.lipschitz)
        object.__setattr__(self, "_matrix", a)
        object.__setattr__(self, "_inv", np.linalg.inv(a))
        object.__setattr__(self, "_offset", t)
        object.__setattr__(self, "_factor", float(sv[-1]))
        object.__setattr__(self, "_cond", float(sv[0] / sv[-1]))

    @property
    def bound_slack_factor(self) -> float:
        """Condition number of the matrix (see `implicit.csg.bound_slack`)."""
        return self._cond

    @property
    def matrix(self) -> np.ndarray:
        return self._matrix.copy()

    @property
    def offset_vector(self) -> np.ndarray:
        return self._offset.copy()

    def _evaluate(self, p):
        q = (p - self._offset) @ self._inv.T
        out = self._children[0]._evaluate(q)
        if self._factor != 1.0:
            out = out * self._factor
        return out


def _compose(solid: Solid, a: np.ndarray, t: np.ndarray) -> Solid:
    """Apply ``p -> a p + t`` after `solid`'s own transform, folding chains."""
    if type(solid) is Affine:
        a2 = a @ solid._matrix
        t2 = a @ solid._offset + t
        child = solid.children[0]
    else:
        a2, t2, child = a, t, solid
    if np.allclose(a2, np.eye(3), rtol=0, atol=1e-15) and not np.any(t2):
        return child
    return Affine(child, a2, t2)


def _need_solid(solid, name):
    if not isinstance(solid, Solid):
        raise TypeError(f"{name}: solid must be a Solid, got {type(solid).__name__}")


@register_operator("translate")
def translate(solid: Solid, offset) -> Solid:
    """`solid` moved by `offset` (3,).

    Examples
    --------
    >>> from implicit import sphere
    >>> s = sphere(1).translate((2, 0, 0))
    >>> float(s([[2.0, 0, 0]])[0])
    -1.0
    """
    _need_solid(solid, "translate")
    return _compose(solid, np.eye(3), as_vector(offset, "offset"))


@register_operator("rotate")
def rotate(solid: Solid, angle_degrees: float, axis=(0.0, 0.0, 1.0), about=(0.0, 0.0, 0.0)) -> Solid:
    """`solid` rotated by `angle_degrees` about `axis` through point `about`."""
    _need_solid(solid, "rotate")
    r = rotation_matrix(angle_degrees, axis)
    c = as_vector(about, "about")
    return _compose(solid, r, c - r @ c)


@register_operator("scale")
def scale(solid: Solid, factor) -> Solid:
    """`solid` scaled about the origin: uniform for a number, per axis for 3 numbers."""
    _need_solid(solid, "scale")
    if np.ndim(factor) == 0:
        f = np.full(3, as_positive(factor, "factor"))
    else:
        f = as_vector(factor, "factor")
        if np.any(f <= 0):
            raise ValueError(f"factor: expected positive scale factors, got {f.tolist()}")
    return _compose(solid, np.diag(f), np.zeros(3))


@register_operator("mirror")
def mirror(solid: Solid, normal, point=(0.0, 0.0, 0.0)) -> Solid:
    """`solid` reflected in the plane through `point` with normal `normal`."""
    _need_solid(solid, "mirror")
    n = as_vector(normal, "normal", nonzero=True)
    n = n / np.linalg.norm(n)
    h = np.eye(3) - 2.0 * np.outer(n, n)
    c = as_vector(point, "point")
    return _compose(solid, h, c - h @ c)


@register_operator("affine")
def affine(solid: Solid, matrix, offset=(0.0, 0.0, 0.0)) -> Solid:
    """`solid` mapped by ``p -> matrix @ p + offset`` (invertible `matrix`)."""
    _need_solid(solid, "affine")
    a = np.asarray(matrix, dtype=np.float64)
    if a.shape != (3, 3):
        raise ValueError(f"matrix: expected shape (3, 3), got {a.shape}")
    return _compose(solid, a, as_vector(offset, "offset"))
