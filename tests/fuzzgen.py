"""Seeded random CSG trees for the mesh fuzz (`tests/meshing/test_fuzz.py`, `bench/fuzz.py`).

Only `implicit` and numpy: the trees do not depend on the mesher they test.
`random_case(seed)` returns a `Case`: the solid, the voxel size to mesh it
at, the region (None, or a box smaller than the part: a part larger than its
bounds) and a short text naming the tree.  The trees cover every primitive
kind, sharp and smooth Booleans, offsets and shells, rigid and non-uniform
transforms, and the cases a lattice finds hard: solids touching along a face,
flush (coplanar) cuts, tangent spheres, walls one voxel thick, and faces on
lattice planes (`snap`: a value on the lattice, or 1e-12 or half a voxel
off it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import implicit as I


@dataclass
class Case:
    seed: int
    solid: object
    voxel_size: float
    bounds: object  # None or (lo, hi)
    text: str


def _v(rng, lo, hi):
    return rng.uniform(lo, hi, 3)


def _axis(rng):
    if rng.random() < 0.4:
        a = np.zeros(3)
        a[rng.integers(3)] = 1.0
        return a
    a = rng.normal(size=3)
    return a / np.linalg.norm(a)


class _Gen:
    def __init__(self, rng, h):
        self.rng, self.h = rng, h

    def snap(self, x):
        """A value on the lattice (lattice origin one voxel below the bounds: unknown here, so the
        value is a multiple of h, which lands on the lattice when the bounds are too), 1e-12 off it,
        half a voxel off it, or left alone."""
        r = self.rng.random()
        x = np.asarray(x, dtype=float)
        q = np.round(x / self.h) * self.h
        out = q if r < 0.25 else q + 1e-12 if r < 0.35 else q + 0.5 * self.h if r < 0.45 else x
        return float(out) if out.ndim == 0 else out

    # -- leaves --------------------------------------------------------------------------------
    def leaf(self):
        rng, h = self.rng, self.h
        kind = rng.choice(LEAVES)
        c = _v(rng, -0.4, 0.4)
        if kind == "sphere":
            return I.sphere(rng.uniform(0.3, 0.9), c), "sphere"
        if kind == "box":
            size = self.snap(_v(rng, 0.3, 1.4))
            return I.box(np.maximum(size, 2 * h), self.snap(c)), "box"
        if kind == "rounded_box":
            size = _v(rng, 0.4, 1.4)
            return I.rounded_box(size, rng.uniform(0.02, 0.9) * size.min() / 2, c), "rounded_box"
        if kind == "cylinder":
            return I.cylinder(rng.uniform(0.2, 0.7), rng.uniform(0.3, 1.5), c, _axis(rng)), "cylinder"
        if kind == "cone":
            return I.cone(rng.uniform(0.2, 0.9), rng.uniform(0.2, 1.5), c, _axis(rng)), "cone"
        if kind == "frustum":
            return I.frustum(rng.uniform(0.2, 0.8), rng.uniform(0.05, 0.6), rng.uniform(0.3, 1.2), c,
                             _axis(rng)), "frustum"
        if kind == "torus":
            major = rng.uniform(0.4, 0.8)
            return I.torus(major, rng.uniform(0.1, 0.9) * major, c, _axis(rng)), "torus"
        if kind == "ellipsoid":
            return I.ellipsoid(_v(rng, 0.2, 0.9), c), "ellipsoid"
        if kind == "capsule":
            return I.capsule(c, c + _v(rng, -0.7, 0.7), rng.uniform(0.1, 0.5)), "capsule"
        if kind == "pyramid":
            s = rng.uniform(0.3, 0.8)
            base = [(-s, -s), (s, -s), (s, s), (-s, s)]
            return I.pyramid(base, rng.uniform(0.3, 1.2), c, _axis(rng)), "pyramid"
        if kind == "wedge":
            return I.wedge(_v(rng, 0.3, 1.2), self.snap(c)), "wedge"
        if kind == "prism":
            ang = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 7)))
            r = rng.uniform(0.3, 0.8)
            pts = np.stack([r * np.cos(ang), r * np.sin(ang)], 1)
            if _area2(pts) < 0.02:
                pts = np.array([(-r, -r), (r, -r), (0, r)])
            return I.prism(pts, rng.uniform(0.3, 1.2), c, _axis(rng)), "prism"
        if kind == "extrude":
            prof = I.rectangle(tuple(rng.uniform(0.3, 1.2, 2))) if rng.random() < 0.5 else I.circle(rng.uniform(0.2, 0.6))
            return I.extrude(prof, rng.uniform(0.3, 1.2), c, _axis(rng)), "extrude"
        if kind == "revolve":
            prof = I.rectangle((rng.uniform(0.1, 0.4), rng.uniform(0.2, 0.8)), (rng.uniform(0.25, 0.6), 0.0))
            angle = 360.0 if rng.random() < 0.6 else rng.uniform(60, 300)
            return I.revolve(prof, angle, c, _axis(rng)), "revolve"
        if kind == "halfspace":
            cube = I.box(rng.uniform(0.6, 1.4), c)
            return cube & I.halfspace(_axis(rng), c + _v(rng, -0.2, 0.2)), "box&halfspace"
        if kind == "polyhedron":
            q, _ = np.linalg.qr(rng.normal(size=(3, 3)))  # a rotated cube's normals keep it bounded
            n = np.concatenate([q, -q, rng.normal(size=(rng.integers(0, 5), 3))])
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            pts = c + n * rng.uniform(0.3, 0.7, (n.shape[0], 1))
            return I.convex_polyhedron(n, pts), "polyhedron"
        raise AssertionError(kind)

    # -- the hard cases -------------------------------------------------------------------------
    def special(self):
        rng, h = self.rng, self.h
        kind = rng.choice(SPECIALS)
        if kind == "boss":  # a boss standing on a plate: one face shared
            t = self.snap(rng.uniform(0.2, 0.6))
            plate = I.box((1.6, 1.6, t), (0, 0, 0))
            bh = rng.uniform(0.2, 0.8)
            boss = I.box((rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.8), bh), (0, 0, t / 2 + bh / 2))
            return plate | boss, "boss on plate"
        if kind == "side":  # two boxes side by side, sharing a face
            a = self.snap(rng.uniform(0.3, 0.8))
            return I.box(a, (0, 0, 0)) | I.box(a, (a, rng.uniform(-0.2, 0.2), 0)), "boxes sharing a face"
        if kind == "flush":  # a pocket cut flush with the top face
            t = self.snap(rng.uniform(0.4, 1.0))
            d = self.snap(rng.uniform(0.1, 0.9) * t)
            return I.box((1.4, 1.4, t)) - I.box((0.6, 0.7, d), (0, 0, t / 2 - d / 2)), "flush pocket"
        if kind == "coplanar_and":
            a = self.snap(rng.uniform(0.5, 1.2))
            return I.box(a) & I.box((a, 0.6 * a, 1.5 * a), (0, 0, 0)), "coplanar intersection"
        if kind == "tangent":
            r1, r2 = rng.uniform(0.2, 0.6, 2)
            d = _axis(rng)
            return I.sphere(r1) | I.sphere(r2, (r1 + r2) * d), "tangent spheres"
        if kind == "wall":  # a wall of one to one and a half voxels
            t = h * rng.uniform(1.0, 1.5)
            return I.box((1.2, 1.0, t), _v(rng, -0.1, 0.1)), "one-voxel wall"
        if kind == "thin_shell":
            return I.shell(I.sphere(rng.uniform(0.4, 0.9)), h * rng.uniform(1.2, 2.0)), "one-voxel shell"
        raise AssertionError(kind)

    # -- trees ----------------------------------------------------------------------------------
    def tree(self, depth):
        rng, h = self.rng, self.h
        if depth == 0:
            return self.special() if rng.random() < 0.25 else self.leaf()
        op = rng.choice(OPS)
        if op in ("union", "intersection", "difference", "smooth_union", "smooth_intersection",
                  "smooth_difference"):
            (a, ta), (b, tb) = self.tree(depth - 1), self.tree(rng.integers(0, depth))
            if op == "union":
                return a | b, f"({ta} | {tb})"
            if op == "intersection":
                return a & b, f"({ta} & {tb})"
            if op == "difference":
                return a - b, f"({ta} - {tb})"
            k = float(rng.uniform(0.02, 0.3))
            fn = getattr(I, op)
            return fn(a, b, blend=k), f"{op}({ta}, {tb}, {k:.2f})"
        a, ta = self.tree(depth - 1)
        if op == "offset":
            d = float(rng.uniform(-0.1, 0.15))
            return I.offset(a, d), f"offset({ta}, {d:.3f})"
        if op == "shell":
            t = float(rng.uniform(1.2 * h, 0.2))
            return I.shell(a, t), f"shell({ta}, {t:.3f})"
        if op == "rotate":
            ang = float(rng.uniform(0, 360))
            return I.rotate(a, ang, _axis(rng)), f"rotate({ta}, {ang:.0f})"
        if op == "translate":
            return I.translate(a, self.snap(_v(rng, -0.3, 0.3))), f"translate({ta})"
        if op == "mirror":
            return I.mirror(a, _axis(rng)), f"mirror({ta})"
        if op == "scale":
            f = _v(rng, 0.6, 1.5) if rng.random() < 0.7 else float(rng.uniform(0.6, 1.5))
            return I.scale(a, f), f"scale({ta})"
        if op == "affine":
            m = np.eye(3) + rng.uniform(-0.3, 0.3, (3, 3))
            return I.affine(a, m), f"affine({ta})"
        raise AssertionError(op)


LEAVES = ("sphere", "box", "rounded_box", "cylinder", "cone", "frustum", "torus", "ellipsoid", "capsule",
          "pyramid", "wedge", "prism", "extrude", "revolve", "halfspace", "polyhedron")
SPECIALS = ("boss", "side", "flush", "coplanar_and", "tangent", "wall", "thin_shell")
OPS = ("union", "intersection", "difference", "smooth_union", "smooth_intersection", "smooth_difference",
       "offset", "shell", "rotate", "translate", "mirror", "scale", "affine")


def _area2(pts):
    x, y = pts[:, 0], pts[:, 1]
    return abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))) / 2


def random_case(seed, resolutions=(16, 48), max_depth=4):
    """The random tree of `seed`: a `Case` meshed at ``voxel_size = 2 / N``, N drawn from `resolutions`."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(resolutions[0], resolutions[1] + 1))
    h = 2.0 / n
    gen = _Gen(rng, h)
    solid, text = gen.tree(int(rng.integers(0, max_depth + 1)))
    bounds = None
    if solid.is_bounded and not solid.is_empty_bounds and rng.random() < 0.1:
        # a part larger than the region meshed: clipped to it
        lo, hi = (np.asarray(b, float) for b in solid.bounds)
        mid, half = (lo + hi) / 2, (hi - lo) / 2
        shrink = rng.uniform(0.5, 0.95, 3)
        bounds = (mid - shrink * half, mid + shrink * half)
        text = f"clip({text})"
    return Case(int(seed), solid, h, bounds, text)
