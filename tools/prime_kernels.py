"""Compile the numba kernels of the everyday jobs into numba's on-disk cache (`make setup` runs it).

Every kernel is ``@njit(cache=True)``: the first process that calls one compiles it (seconds)
and stores it beside its source; later processes load it (milliseconds).  This runs the jobs
a first `implicad mesh`, `mass` or `fea` run would, on a small part, so that the first real
run after set-up compiles nothing.  Prints the seconds it took.

    .venv/bin/python tools/prime_kernels.py
"""

from __future__ import annotations

import time

import numpy as np
import warnings


def main() -> int:
    start = time.perf_counter()
    from implicit.evaluate.kernels import numba_available, prime_cache

    if not numba_available():
        print("prime_kernels: numba is not importable; evaluation falls back to numpy")
        return 0
    prime_cache()
    from implicit import box, cylinder, sphere

    import spatial

    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for features in (False, True):
            spatial.mesh(part, resolution=48, progress=False, features=features)
        spatial.mass_properties(part, resolution=32)
    # the feature pass on a part of many primitives folds each Boolean's operands by a compiled loop, and
    # evaluates capsules (a lattice's struts) by theirs
    from implicit import capsule, union
    from implicit.facets import PRUNE_MIN_LEAVES, PRUNE_MIN_POINTS, FacetField

    many = union(*[capsule((float(x), 0.0, 0.0), (float(x), 1.0, 0.0), 0.3) for x in range(PRUNE_MIN_LEAVES)])
    at = np.random.default_rng(0).uniform(-1.0, PRUNE_MIN_LEAVES, (PRUNE_MIN_POINTS, 3))
    ff = FacetField(many)
    ff.gradients_of(at, ff.decide(at)[1])
    # outlines of many edges (a gear's) are measured by their own compiled loop
    from implicit.profiles import POLYGON_KERNEL_EDGES, polygon_distance

    turn = np.linspace(0, 2 * np.pi, POLYGON_KERNEL_EDGES, endpoint=False)
    polygon_distance(np.zeros((64, 2)), np.c_[np.cos(turn), np.sin(turn)])
    # `implicad mesh -o part.stl` fills the file's records and counts the edges by compiled passes
    from spatial.files.kernels import RECORD, edges_twice, stl_records

    stl_records(np.eye(3), np.array([[0, 1, 2]]), 0, 1, np.empty(RECORD, dtype=np.uint8))
    edges_twice(np.array([[0, 1, 2]]), 3)
    # `tet_mesh`'s sliver smoothing: element scores, the moving set of a round and its best trials
    from spatial.fea.score_kernel import best_trials, corner_measures, element_scores, smoothing_set

    p = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    t = np.array([[0, 1, 3, 2]])
    element_scores(p, t, 10.0, 165.0, 3.0)
    corner_measures(p, t)
    one = np.array([0])
    smoothing_set(p, t, np.array([0, 1, 2, 3, 4]), np.arange(4) // 4, np.ones(4, dtype=bool), np.arange(4))
    best_trials(p, t, one, one, np.array([1]), p[None, :1].repeat(2, axis=0), 10.0, 165.0, 3.0)
    # `surface_for_fea`'s proof that its surface crosses nowhere
    from spatial.fea.crossing_kernel import surely_apart

    surely_apart(p, np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]))
    # `tet_mesh`'s volume check on one feature mesh: its triangles' centroids and the shell's error sums
    from spatial.analysis.mass_kernels import centroids, shell_error

    tri = np.array([[0, 1, 2]])
    shell_error(p, tri, np.ones(3), np.zeros(3), np.zeros(4), np.zeros(len(centroids(p, tri))))
    print(f"prime_kernels: numba kernels compiled or loaded in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
