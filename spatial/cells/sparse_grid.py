"""A solid over a sparse level set: tiles of sampled values where the surface is, a bound elsewhere.

A narrow-band level set (an OpenVDB grid) holds values only near the
surface; its inside and outside away from the band are constants.  Reading
it into one dense array costs its whole box -- 4 GB of floats for two small
balls a thousand voxels apart, 275 GB for a part at N = 4096 -- while its
band holds a few thousand voxels, or about ``6 A / h**2``.  `SparseGridSolid`
keeps the band only: tiles of ``TILE**3`` voxels (the leaves of an OpenVDB
tree) holding their ``(TILE + 1)**3`` corner samples, so that a point is
interpolated from its own tile alone.

Inside a tile the field is the trilinear interpolant of its samples.  At a
point ``p`` outside every tile, with ``x`` the nearest point of the nearest
tile and ``d = |p - x|``: no surface lies between ``p`` and ``x`` (the
surface lies in the tiles), so ``p`` takes the sign of ``f(x)``, and the
value ``sign * max(d, |f(x)| - d)`` is a lower bound of the distance to the
surface (every surface point lies in a tile, at least ``d`` away, and at
least ``|f(x)|`` from ``x``): conservative for the octree, continuous at the
tiles' faces.
"""

from __future__ import annotations

import base64

import numpy as np

from implicit.solid import Solid, as_positive, as_vector

__all__ = ["SparseGridSolid", "TILE"]

#: Voxels per side of a tile (an OpenVDB leaf node).
TILE = 8
#: Nearest tile centres looked at for a point outside the tiles (the nearest tile by distance is among them).
NEAREST = 8


def _b64(array, dtype):
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


class SparseGridSolid(Solid):
    """A solid whose field is sampled in tiles near its surface (see the module notes).

    Parameters
    ----------
    keys : (k, 3) array_like of int
        Tile indices: tile ``t`` holds the voxels ``TILE * t + (0 .. TILE)``
        along each axis.
    samples : (k, TILE + 1, TILE + 1, TILE + 1) array_like of float
        The signed distances (negative inside) at those voxels; voxel
        ``(i, j, k)`` sits at ``origin + (i, j, k) * voxel_size``.
    origin : (3,) array_like
    voxel_size : float

    Examples
    --------
    >>> import numpy as np
    >>> u = np.arange(TILE + 1) * 0.1
    >>> X, Y, Z = np.meshgrid(u, u, u, indexing="ij")
    >>> plane = SparseGridSolid([[0, 0, 0]], [X - 0.4], origin=(0, 0, 0), voxel_size=0.1)
    >>> round(float(plane([[0.25, 0.3, 0.3]])[0]), 6)
    -0.15
    """

    kind = "sparse_grid"
    __slots__ = ("_keys", "_codes", "_base", "_dims", "_samples", "_origin", "_h", "_tree")

    def __init__(self, keys, samples, origin=(0.0, 0.0, 0.0), voxel_size=1.0):
        from scipy.spatial import cKDTree

        keys = np.asarray(keys, dtype=np.int64).reshape(-1, 3)
        try:
            data = np.asarray(samples, dtype=np.float32)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"samples: expected an array of numbers, got {type(samples).__name__}") from exc
        n = TILE + 1
        if keys.shape[0] == 0:
            raise ValueError("keys: expected at least one tile")
        if data.shape != (keys.shape[0], n, n, n):
            raise ValueError(f"samples: expected shape {(keys.shape[0], n, n, n)}, got {data.shape}")
        if not np.isfinite(data).all():
            raise ValueError("samples: expected finite numbers (no NaN or inf)")
        o = as_vector(origin, "origin")
        h = as_positive(voxel_size, "voxel_size")
        base = keys.min(axis=0) - 1
        dims = keys.max(axis=0) - base + 2
        codes = ((keys[:, 0] - base[0]) * dims[1] + keys[:, 1] - base[1]) * dims[2] + keys[:, 2] - base[2]
        order = np.argsort(codes)
        if np.any(np.diff(codes[order]) == 0):
            raise ValueError("keys: expected distinct tiles")
        keys, codes, data = keys[order], codes[order], np.ascontiguousarray(data[order])
        data.flags.writeable = False
        # Lipschitz constant of the interpolant (as `implicit.fields.GridSolid`); 1 outside the tiles
        slope = max(float(np.abs(np.diff(data, axis=a)).max()) for a in (1, 2, 3)) / h
        lip = max(float(np.hypot(np.sqrt(3.0) * slope, 1.0)), 1.0)
        inside = (data < 0).reshape(keys.shape[0], -1).any(axis=1)
        if inside.any():
            # the inside is enclosed by the tiles its surface crosses
            lo = o + keys[inside].min(axis=0) * TILE * h
            hi = o + (keys[inside].max(axis=0) + 1) * TILE * h
        else:
            lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        super().__init__((), {"tiles": int(keys.shape[0]), "origin": o.tolist(), "voxel_size": h},
                         (lo, hi), exact=False, lipschitz=lip)
        for name, value in (("_keys", keys), ("_codes", codes), ("_base", base), ("_dims", dims),
                            ("_samples", data), ("_origin", o), ("_h", h),
                            ("_tree", cKDTree((keys + 0.5) * TILE))):
            object.__setattr__(self, name, value)

    # -- data -----------------------------------------------------------------
    @property
    def voxel_size(self) -> float:
        return self._h

    @property
    def origin(self) -> np.ndarray:
        return self._origin.copy()

    @property
    def tiles(self) -> int:
        """Number of tiles held."""
        return int(self._keys.shape[0])

    @property
    def nbytes(self) -> int:
        """Bytes of the samples and their index (the memory the solid holds, about)."""
        return int(self._samples.nbytes + self._keys.nbytes + self._codes.nbytes + self._keys.nbytes)

    def to_params(self) -> dict:
        """JSON-safe parameters: the tiles' keys (int64) and samples (float32), base64 little-endian."""
        return {"tiles": int(self._keys.shape[0]), "origin": self._origin.tolist(), "voxel_size": self._h,
                "keys": _b64(self._keys, "<i8"), "samples": _b64(self._samples, "<f4")}

    @classmethod
    def from_params(cls, children, params):
        if "keys" not in params or "samples" not in params:
            raise ValueError("sparse_grid: params need 'keys' and 'samples' (base64) to rebuild the solid")
        k, n = int(params["tiles"]), TILE + 1
        keys = np.frombuffer(base64.b64decode(params["keys"]), dtype="<i8").reshape(k, 3)
        samples = np.frombuffer(base64.b64decode(params["samples"]), dtype="<f4").reshape(k, n, n, n)
        return cls(keys, samples, origin=params["origin"], voxel_size=params["voxel_size"])

    # -- evaluation -------------------------------------------------------------
    def _find(self, tiles):
        """Row of each tile index (m, 3) among the held tiles, -1 where none is held."""
        inside = np.all((tiles > self._base) & (tiles < self._base + self._dims - 1), axis=1)
        t = tiles - self._base
        code = (t[:, 0] * self._dims[1] + t[:, 1]) * self._dims[2] + t[:, 2]
        at = np.minimum(np.searchsorted(self._codes, code), self._codes.size - 1)
        return np.where(inside & (self._codes[at] == code), at, -1)

    def _interpolate(self, rows, u):
        """Trilinear values at voxel coordinates `u` (m, 3), each inside tile `rows` (m,)."""
        local = u - self._keys[rows] * TILE
        i = np.clip(np.floor(local).astype(np.int64), 0, TILE - 1)
        f = np.clip(local - i, 0.0, 1.0)
        d = self._samples
        i0, j0, k0 = i[:, 0], i[:, 1], i[:, 2]
        fx, fy, fz = f[:, 0], f[:, 1], f[:, 2]
        c00 = d[rows, i0, j0, k0] * (1 - fx) + d[rows, i0 + 1, j0, k0] * fx
        c01 = d[rows, i0, j0, k0 + 1] * (1 - fx) + d[rows, i0 + 1, j0, k0 + 1] * fx
        c10 = d[rows, i0, j0 + 1, k0] * (1 - fx) + d[rows, i0 + 1, j0 + 1, k0] * fx
        c11 = d[rows, i0, j0 + 1, k0 + 1] * (1 - fx) + d[rows, i0 + 1, j0 + 1, k0 + 1] * fx
        return (c00 * (1 - fy) + c10 * fy) * (1 - fz) + (c01 * (1 - fy) + c11 * fy) * fz

    def _evaluate(self, p):
        u = (np.asarray(p, dtype=np.float64) - self._origin) / self._h
        out = np.empty(u.shape[0])
        rows = self._find(np.floor(u / TILE).astype(np.int64))
        held = rows >= 0
        if held.any():
            out[held] = self._interpolate(rows[held], u[held])
        far = np.flatnonzero(~held)
        if far.size:
            q = u[far]
            k = min(NEAREST, self._keys.shape[0])
            _, near = self._tree.query(q, k=k)
            near = np.asarray(near).reshape(far.size, k)
            lo = self._keys[near] * TILE                                    # (f, k, 3)
            x = np.clip(q[:, None, :], lo, lo + TILE)
            gap = np.linalg.norm(q[:, None, :] - x, axis=2)
            best = np.argmin(gap, axis=1)
            pick = np.arange(far.size)
            x, d = x[pick, best], gap[pick, best] * self._h
            fx = self._interpolate(near[pick, best], x)
            mag = np.maximum(d, np.abs(fx) - d)
            out[far] = np.where(fx < 0, -mag, mag)
        return out
