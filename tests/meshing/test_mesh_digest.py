"""The boundary mesh pinned triangle by triangle: speed work on the mesher must not change it.

Each digest is the SHA-256 of the mesh's triangles, every triangle written as
its three vertex positions (rounded to 1e-7) starting from its smallest
vertex with the winding kept, the triangles sorted: the same mesh up to the
numbering of its vertices gives the same digest, and any moved, added,
dropped or flipped triangle a different one.
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
from parts import benchmark_part, holed_plate

from implicit import capsule, smooth_union, sphere, translate
from spatial import mesh
from spatial.meshing.arrays import faces_array


def triangle_digest(m):
    points, tri = faces_array(m)
    corners = np.round(points[tri], 7)  # (f, 3, 3)
    # rotate each triangle so its lexicographically smallest vertex comes first (winding kept)
    rank = np.zeros((corners.shape[0], 3), dtype=np.int64)
    for a in range(3):
        for b in range(3):
            if a != b:
                less = _lex_less(corners[:, b], corners[:, a])
                rank[:, a] += less
    order = np.argmin(rank, axis=1)
    rolled = np.stack([corners[np.arange(corners.shape[0]), (order + k) % 3] for k in range(3)], axis=1)
    keys = rolled.reshape(rolled.shape[0], -1)
    keys = keys[np.lexsort(keys.T[::-1])]
    keys = keys + 0.0  # no negative zeros
    return hashlib.sha256(np.ascontiguousarray(keys).tobytes()).hexdigest()[:16], int(keys.shape[0])


def _lex_less(p, q):
    """Row-wise lexicographic ``p < q`` of (n, 3) arrays."""
    return (p[:, 0] < q[:, 0]) | ((p[:, 0] == q[:, 0]) & ((p[:, 1] < q[:, 1]) | ((p[:, 1] == q[:, 1]) & (p[:, 2] < q[:, 2]))))


_bench, _plate = benchmark_part, holed_plate


def _blobs():
    return smooth_union(sphere(0.6), translate(sphere(0.5), (0.7, 0.2, 0.1)),
                        capsule((-0.5, -0.5, 0.0), (0.2, 0.6, 0.4), 0.25), blend=0.2)


# the plain path (marching cubes, refined), asked for explicitly (the default is the feature path)
CASES = {
    "benchmark part N=40": (_bench, dict(resolution=40, features=False)),
    "benchmark part N=40 unrefined": (_bench, dict(resolution=40, refine=False, features=False)),
    "benchmark part N=72 block 8": (_bench, dict(resolution=72, block=8, features=False)),
    "plate with holes N=48": (_plate, dict(resolution=48, features=False)),
    "smooth blobs N=36": (_blobs, dict(resolution=36, features=False)),
    # the feature path on top of the plain one
    "benchmark part N=40 features": (_bench, dict(resolution=40, features=True)),
    "plate with holes N=48 features": (_plate, dict(resolution=48, features=True)),
}

#: Digests and triangle counts of the current mesher (see the module docstring).
PINNED = {
    "benchmark part N=40": ("9cd816a575b38a1a", 21472),
    "benchmark part N=40 unrefined": ("7db850d954a19e6e", 21472),
    "benchmark part N=72 block 8": ("82813a8bfc5a55f0", 71872),
    "plate with holes N=48": ("82827a2865586273", 5804),
    "smooth blobs N=36": ("f8be51919acac7d5", 5892),
    "benchmark part N=40 features": ("c3330a34c86d8230", 21700),
    "plate with holes N=48 features": ("a95dc2cf7e7449d7", 5944),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_mesh_is_pinned(name):
    make, kwargs = CASES[name]
    digest, n = triangle_digest(mesh(make(), progress=False, **kwargs))
    assert (digest, n) == PINNED[name]


@pytest.mark.parametrize("name", ["benchmark part N=40 features", "plate with holes N=48 features"])
def test_default_mesh_is_the_feature_mesh(name):
    """Without `features`, `spatial.mesh` gives the feature mesh, triangle for triangle."""
    make, kwargs = CASES[name]
    kwargs = {k: v for k, v in kwargs.items() if k != "features"}
    assert triangle_digest(mesh(make(), progress=False, **kwargs)) == PINNED[name]


def test_digest_sees_one_flipped_triangle():
    m = mesh(_bench(), resolution=24, progress=False, features=False)
    points, tri = faces_array(m)
    flipped = tri.copy()
    flipped[0] = flipped[0, ::-1]
    import pyvista as pv

    assert triangle_digest(pv.PolyData.from_regular_faces(points, flipped))[0] != triangle_digest(m)[0]
    renumbered = np.random.default_rng(0).permutation(points.shape[0])
    inverse = np.argsort(renumbered)
    same = pv.PolyData.from_regular_faces(points[renumbered], inverse[tri][np.random.default_rng(1).permutation(tri.shape[0])][:, [1, 2, 0]])
    assert triangle_digest(same) == triangle_digest(m)
