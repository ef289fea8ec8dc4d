"""Walls measured on the field itself: the thin ones a Boolean, an offset or a blend made.

The CSG tree knows the sizes of its primitives, not what the Booleans leave
of them: ``box(10) - box(10, center=(0.05, 0, 0))`` is a wall 0.05 thick
built from two boxes of 10.  `thin_wall` measures walls where they are:

1. the field is sampled on a coarse grid (32 points a side); every sample
   within reach of the surface (``|f| < L * half-diagonal``, rigorous for a
   field of Lipschitz constant ``L``) is pushed onto it by Newton steps
   along the gradient -- a wall thinner than the grid is still found, since
   the samples beside it project onto its faces;
2. from each surface point a ray goes inward (against the gradient) until
   it leaves the material, by steps of ``|f| / L`` (never past the surface:
   a thin wall takes short steps, a thick part doubles them) or a quarter of
   the way travelled, whichever is longer;
3. the ray's length is a wall's thickness where the normal at the exit faces
   the entry's (the two faces of a wall are parallel; across a convex edge
   they are not, and a ray that leaves by the neighbouring face measures no
   wall);
4. the thinnest wall is the `RANK`-th smallest of the thinnest rays per
   grid cell (a wall has an extent, a stray ray or a pinch does not).

The facets deciding the field at the two faces (`implicit.facets`) name the
wall, e.g. ``between box_0.+x and box_1.-x``.

Examples
--------
>>> from implicit import box
>>> w = thin_wall(box(10) - box(10, center=(0.05, 0, 0)))
>>> round(w.thickness, 4), w.between
(0.05, 'box_0.-x and box_1.-x')
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np

__all__ = ["Wall", "thin_wall", "GRID", "OPPOSED"]

#: Grid points a side of the sampling.
GRID = 32
#: Entry and exit normals at least this opposed (cosine below -OPPOSED) make a wall.
OPPOSED = 0.99
#: Most surface points followed (a deterministic subset beyond).
MAX_PROBES = 20_000
#: The wall reported is the RANK-th thinnest of the grid cells' thinnest rays (a wall has an extent;
#: a wall pinched to nothing by a blend reports where it is still a few cells wide).
RANK = 4
#: Walls up to this fraction of the region's extent are measured (thicker ones need no warning:
#: the tree's primitives tell those, and a default voxel is at most 1/128 of the extent).
CAP = 1.0 / 8
#: Steps of the inward march (a field much below the distance may not reach the far face).
MARCH_STEPS = 48


@dataclass(frozen=True)
class Wall:
    """The thinnest wall found: its `thickness`, a point on its face `at`, and the facets `between`."""

    thickness: float
    at: tuple
    between: str

    def describe(self) -> str:
        """One phrase naming the wall: ``'a wall 0.05 thick between ... near (x, y, z)'``."""
        where = ", ".join(f"{v:.4g}" for v in self.at)
        who = f" between {self.between}" if self.between else ""
        return f"a wall {self.thickness:.4g} thick{who} near ({where})"


_CACHE: dict = {}


def thin_wall(solid, *, bounds=None, n=GRID):
    """The thinnest wall of `solid` measured on its field (see the module notes), or None.

    Parameters
    ----------
    solid : Solid
    bounds : (lo, hi), optional
        Region searched (default the solid's bounds).
    n : int
        Grid points a side of the sampling.

    Returns
    -------
    Wall or None
        None when no wall thinner than `CAP` times the region's extent is
        found (no surface in the region, or no ray whose faces are parallel).  The result is kept per solid and region.
    """
    lo, hi = (np.asarray(b, dtype=np.float64) for b in (solid.bounds if bounds is None else bounds))
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi > lo)):
        return None
    key = (id(solid), tuple(lo.tolist()), tuple(hi.tolist()), int(n))
    hit = _CACHE.get(key)
    if hit is not None and hit[0]() is solid:
        return hit[1]
    wall = _measure(solid, lo, hi, int(n))
    try:
        ref = weakref.ref(solid, lambda _r, k=key: _CACHE.pop(k, None))
    except TypeError:       # not weakly referable: measured each time
        return wall
    _CACHE[key] = (ref, wall)
    return wall


def _gradient(solid, x, fx, step):
    """Forward differences from the known values `fx` (a direction is all the walls need)."""
    probe = np.repeat(x, 3, axis=0)
    probe.reshape(-1, 3, 3)[:, [0, 1, 2], [0, 1, 2]] += step
    return (np.asarray(solid(probe), dtype=np.float64).reshape(-1, 3) - fx[:, None]) / step


def _smooth_at(solid, x, fx, g, step):
    """Points where the forward-difference gradient `g` agrees with the backward one (not on an edge)."""
    gb = _gradient(solid, x, fx, -step)
    num = np.einsum("ij,ij->i", g, gb)
    den = np.linalg.norm(g, axis=1) * np.linalg.norm(gb, axis=1)
    return num > 0.999 * np.maximum(den, 1e-300)


def _measure(solid, lo, hi, n):
    ext = float(np.max(hi - lo))
    axes = [np.linspace(lo[i], hi[i], n) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    f = np.asarray(solid(grid), dtype=np.float64)
    lip = max(float(getattr(solid, "lipschitz", 1.0) or 1.0), 1.0)
    if not math.isfinite(lip):
        lip = 1.0
    spacing = (hi - lo) / (n - 1)
    reach = lip * 0.5 * float(np.linalg.norm(spacing)) * 1.01
    pick = np.flatnonzero(np.isfinite(f) & (np.abs(f) < reach))
    if pick.size == 0:
        return None
    if pick.size > MAX_PROBES:
        pick = pick[:: int(math.ceil(pick.size / MAX_PROBES))]
    x, fx = grid[pick], f[pick]
    step = 1e-6 * ext
    # Newton onto the surface (a step never longer than the sample's reach)
    for _ in range(3):
        g = _gradient(solid, x, fx, step)
        gg = np.einsum("ij,ij->i", g, g)
        ok = gg > 1e-24
        move = np.where(ok, fx / np.where(ok, gg, 1.0), 0.0)[:, None] * g
        norm = np.linalg.norm(move, axis=1)
        move *= np.minimum(1.0, 2 * reach / np.maximum(norm, 1e-300))[:, None]
        x = x - move
        fx = np.asarray(solid(x), dtype=np.float64)
    g = _gradient(solid, x, fx, step)
    gn = np.linalg.norm(g, axis=1)
    on = (np.abs(fx) < 1e-7 * ext) & (gn > 1e-12) & np.all((x >= lo) & (x <= hi), axis=1)
    # a point on an edge (where Newton steps from symmetric samples like to land) has no normal:
    # its forward and backward differences disagree
    on &= _smooth_at(solid, x, fx, g, step)
    x, g, gn = x[on], g[on], gn[on]
    if x.shape[0] == 0:
        return None
    inward = -g / gn[:, None]
    t_min = 1e-5 * ext
    jump = 1e-3 * ext         # the first step past t_min (a thinner wall is found by the bisection)
    cap = CAP * ext
    tau = np.full(x.shape[0], t_min)
    fin = np.asarray(solid(x + tau[:, None] * inward), dtype=np.float64)
    alive = fin < 0                     # no material under the face: a skin, not a wall
    exit_t = np.full(x.shape[0], np.inf)
    prev = tau.copy()
    act = np.flatnonzero(alive)
    for _ in range(MARCH_STEPS):
        if act.size == 0:
            break
        fa = np.asarray(solid(x[act] + tau[act, None] * inward[act]), dtype=np.float64)
        out = fa >= 0
        exit_t[act[out]] = tau[act[out]]
        act = act[~out]
        fa = fa[~out]
        prev[act] = tau[act]
        # at least a quarter of the way travelled (a field far below the distance would crawl; a
        # step past the exit is caught by the bisection below)
        tau[act] = tau[act] + np.maximum(-fa / lip, np.maximum(0.25 * tau[act], jump))
        act = act[tau[act] < cap]
    done = np.flatnonzero(np.isfinite(exit_t))
    if done.size == 0:
        return None
    # bisect the exit between the last step inside and the first outside
    a, b = prev[done].copy(), exit_t[done].copy()
    xs, ds = x[done], inward[done]
    for _ in range(16):
        mid = 0.5 * (a + b)
        inside = np.asarray(solid(xs + mid[:, None] * ds), dtype=np.float64) < 0
        a = np.where(inside, mid, a)
        b = np.where(inside, b, mid)
    far = xs + b[:, None] * ds
    ffar = np.asarray(solid(far), dtype=np.float64)
    g2 = _gradient(solid, far, ffar, step)
    # the exit's outward normal along the ray: the far face faces away from the near one
    cos = np.einsum("ij,ij->i", g2, ds) / np.maximum(np.linalg.norm(g2, axis=1), 1e-300)
    wall = (cos > OPPOSED) & _smooth_at(solid, far, ffar, g2, step)
    if not wall.any():
        return None
    thick, pts, far = b[wall], xs[wall], far[wall]
    cell = np.floor((pts - lo) / np.maximum(spacing, 1e-300)).astype(np.int64)
    cid = (cell[:, 0] * (n + 1) + cell[:, 1]) * (n + 1) + cell[:, 2]
    order = np.lexsort((thick, cid))
    first = order[np.r_[True, cid[order][1:] != cid[order][:-1]]]    # thinnest ray per cell
    if first.size < RANK:
        return None
    best = first[np.argsort(thick[first], kind="stable")[RANK - 1]]
    return Wall(float(thick[best]), tuple(float(v) for v in pts[best]), _between(solid, pts[best], far[best]))


def _between(solid, near, far):
    """Names of the facets deciding the field at the wall's two faces ('' when unknown)."""
    try:
        from implicit.facets import FacetField

        ff = FacetField(solid)
        _, dec, _ = ff(np.stack([near, far]))
        a, b = ff.names[int(dec[0])], ff.names[int(dec[1])]
    except Exception:  # noqa: BLE001 - a name is a courtesy; the thickness stands without it
        return ""
    return a if a == b else " and ".join(sorted((a, b)))
