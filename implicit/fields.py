"""Solids backed by data: a regular grid of sampled signed distances.

`GridSolid` interpolates samples trilinearly inside the grid's box and, outside
it, extrapolates conservatively from the value at the nearest point of the
box and the distance to the box.  Its Lipschitz constant comes from the data (the
largest finite difference between neighbouring samples, times sqrt(3) for the
trilinear interpolant, combined with the slope 1 of the extrapolation), so the
default `Solid.value_bounds` stays conservative and octrees classify it
rigorously.

Scanned or exported parts (meshes turned into level sets) and sampled
occupancy grids enter CSG trees through this node.
"""

from __future__ import annotations

import base64

import numpy as np

from .solid import Solid, as_positive, as_vector

__all__ = ["GridSolid", "grid_solid"]


class GridSolid(Solid):
    """A solid whose field is trilinear interpolation of sampled distances.

    Parameters
    ----------
    distance : (nx, ny, nz) array_like of float
        Signed distances (negative inside) sampled at
        ``origin + (i, j, k) * voxel_size``; at least 2 samples per axis.
    origin : (3,) array_like
        Position of sample ``(0, 0, 0)``.
    voxel_size : float
        Spacing of the samples.

    Notes
    -----
    Inside the box of the samples the field is the trilinear interpolant.
    Outside it, with ``c`` the nearest point of the box and ``d = |p - c|``:
    ``f(p) = sqrt(f(c)**2 + d**2)`` where ``f(c) > 0`` (a lower bound of the
    distance, as every boundary point lies in the box) and ``f(c) + d`` where
    the solid touches the box.  The field is a conservative bound (``exact``
    is False).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1.5, 1.5, 31)
    >>> X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    >>> ball = GridSolid(np.sqrt(X**2 + Y**2 + Z**2) - 1.0, origin=(-1.5, -1.5, -1.5), voxel_size=0.1)
    >>> round(float(ball([[0.5, 0.0, 0.0]])[0]), 6)
    -0.5
    """

    kind = "grid"
    __slots__ = ("_data", "_origin", "_h", "_top")

    def __init__(self, distance, origin=(0.0, 0.0, 0.0), voxel_size=1.0):
        try:
            data = np.asarray(distance, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"distance: expected a 3-d array of numbers, got {type(distance).__name__}") from exc
        if data.ndim != 3 or min(data.shape) < 2:
            raise ValueError(f"distance: expected a 3-d array with at least 2 samples per axis, got shape {data.shape}")
        if not np.isfinite(data).all():
            raise ValueError("distance: expected finite numbers (no NaN or inf)")
        o = as_vector(origin, "origin")
        h = as_positive(voxel_size, "voxel_size")
        data = np.ascontiguousarray(data)
        data.flags.writeable = False
        shape = np.array(data.shape)
        top = o + (shape - 1) * h
        # Lipschitz constant of the trilinear interpolant: sqrt(3) x the largest slope between neighbours.
        slope = max(float(np.abs(np.diff(data, axis=a)).max()) for a in range(3)) / h
        lip = float(np.hypot(np.sqrt(3.0) * slope, 1.0))
        inside = data < 0
        if inside.any():
            idx = np.argwhere(inside)
            lo = np.maximum(o + (idx.min(axis=0) - 1) * h, o)
            hi = np.minimum(o + (idx.max(axis=0) + 1) * h, top)
        else:
            lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        super().__init__((), {"shape": list(data.shape), "origin": o.tolist(), "voxel_size": h},
                         (lo, hi), exact=False, lipschitz=lip)
        object.__setattr__(self, "_data", data)
        object.__setattr__(self, "_origin", o)
        object.__setattr__(self, "_h", h)
        object.__setattr__(self, "_top", top)

    # -- data -----------------------------------------------------------------
    @property
    def distance(self) -> np.ndarray:
        """The samples, read-only, shape ``(nx, ny, nz)``."""
        return self._data

    @property
    def origin(self) -> np.ndarray:
        return self._origin.copy()

    @property
    def voxel_size(self) -> float:
        return self._h

    def to_params(self) -> dict:
        """JSON-safe parameters: the samples as base64 little-endian float32."""
        raw = np.ascontiguousarray(self._data, dtype="<f4").tobytes()
        return {"shape": list(self._data.shape), "origin": self._origin.tolist(), "voxel_size": self._h,
                "data": base64.b64encode(raw).decode("ascii")}

    @classmethod
    def from_params(cls, children, params):
        if "data" not in params:
            raise ValueError("grid: params need 'data' (base64 float32 samples) to rebuild the solid")
        shape = tuple(int(v) for v in params["shape"])
        data = np.frombuffer(base64.b64decode(params["data"]), dtype="<f4").reshape(shape)
        return cls(data, origin=params["origin"], voxel_size=params["voxel_size"])

    # -- evaluation -------------------------------------------------------------
    def _evaluate(self, p):
        h = self._h
        c = np.minimum(np.maximum(p, self._origin), self._top)
        outside = np.sqrt(np.einsum("ij,ij->i", p - c, p - c))
        u = (c - self._origin) / h
        n = np.array(self._data.shape) - 2
        i = np.minimum(np.floor(u).astype(np.int64), n)
        f = u - i
        d = self._data
        i0, j0, k0 = i[:, 0], i[:, 1], i[:, 2]
        fx, fy, fz = f[:, 0], f[:, 1], f[:, 2]
        c00 = d[i0, j0, k0] * (1 - fx) + d[i0 + 1, j0, k0] * fx
        c01 = d[i0, j0, k0 + 1] * (1 - fx) + d[i0 + 1, j0, k0 + 1] * fx
        c10 = d[i0, j0 + 1, k0] * (1 - fx) + d[i0 + 1, j0 + 1, k0] * fx
        c11 = d[i0, j0 + 1, k0 + 1] * (1 - fx) + d[i0 + 1, j0 + 1, k0 + 1] * fx
        c0 = c00 * (1 - fy) + c10 * fy
        c1 = c01 * (1 - fy) + c11 * fy
        inner = c0 * (1 - fz) + c1 * fz
        # Outside the box (every boundary lies inside it): for a positive value at the
        # nearest box point c, |p - s|^2 >= |c - s|^2 + |p - c|^2 for every s in the box.
        return np.where(inner > 0, np.sqrt(inner * inner + outside * outside), inner + outside)


def grid_solid(distance, origin=(0.0, 0.0, 0.0), voxel_size=1.0) -> GridSolid:
    """A `GridSolid` from sampled distances (see the class)."""
    return GridSolid(distance, origin=origin, voxel_size=voxel_size)
