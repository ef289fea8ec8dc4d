"""Volume error of the benchmark part's feature mesh against h^2, and the chord errors behind it.

    .venv/bin/python bench/bench_feature_volume.py [--sizes 64 128 256 512 1024]

For each N the raw mesh volume error ``e(N) = V_mesh - V`` (V = 0.988789504774) of
`spatial.mesh(part, resolution=N)` (features on: the default) is compared with ``C h^2``,
``C = |e(64)| / h(64)^2`` fixed from the coarsest size: the claim is ``|e(N)| <= C h^2`` for every N.

The error is then split by the CSG face its triangles lie on.  With every vertex on the surface,
what a triangle misses is the thin shell between it and the true face, ``int_T f dA`` to second
order (the field ``f`` is an exact distance on these faces), summed by the edge-midpoint rule
``A/3 (f(m_ab) + f(m_bc) + f(m_ca))`` -- the thin-shell term of `spatial.analysis.mass_solid`.
Summed per face, it gives each face's chord error: the sphere's (convex, the chords lie inside,
negative) and the drills' (concave walls, the chords cut into the holes, positive); flat faces give
nothing.  The two are each O(h^2) with coefficients of opposite signs; the total is their difference.
The box faces' term is the second-order error of the triangles that straddle their edges, once the
refinement's stop tolerances shrink with h (`spatial.meshing.arrays.refine_scale`: it was -2.6e-3 / N,
first order, before).  N=1024 takes about 1.5 minutes and 7 GB (the face split of 15 M triangles).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

EXACT = 0.988789504774


def part():
    from implicit import box, cylinder, sphere

    return (sphere(1.0) & box(1.5)) - cylinder(0.5, 4.0, axis=(1, 0, 0)) - cylinder(0.5, 4.0, axis=(0, 1, 0)) \
        - cylinder(0.5, 4.0, axis=(0, 0, 1))


def chord_errors(solid, m):
    """``{face group: int_T f dA summed}`` of the mesh's triangles, grouped by the CSG face at their centroid."""
    from implicit.facets import FacetField

    pts = np.asarray(m.points, dtype=np.float64)
    tri = np.asarray(m.faces).reshape(-1, 4)[:, 1:]
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    f = solid(0.5 * (a + b)) + solid(0.5 * (b + c)) + solid(0.5 * (c + a))
    ff = FacetField(solid)
    _, dec, _ = ff((a + b + c) / 3.0)
    names = np.array([n.split("_")[0] for n in ff.names])[dec]
    shell = area / 3.0 * f
    return {g: float(shell[names == g].sum()) for g in sorted(set(names))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512, 1024])
    args = parser.parse_args(argv)
    from spatial import mesh

    solid = part()
    rows = []
    for n in args.sizes:
        t0 = time.perf_counter()
        m = mesh(solid, resolution=n, progress=False)
        seconds = time.perf_counter() - t0
        h = float(m.field_data["voxel_size"][0])
        rows.append((n, h, m.volume - EXACT, chord_errors(solid, m), seconds))
    c = abs(rows[0][2]) / rows[0][1] ** 2
    groups = sorted({g for r in rows for g in r[3]})
    print(f"C = |e({rows[0][0]})| / h^2 = {c:.4g}")
    print("| N | h | error e | C h^2 | abs(e) / (C h^2) | " + " | ".join(f"chord {g}" for g in groups)
          + " | chord sum | s |")
    print("| --- " * (7 + len(groups)) + "|")
    for n, h, e, ch, s in rows:
        total = sum(ch.values())
        print(f"| {n} | {h:.5g} | {e:+.3e} | {c * h * h:.3e} | {abs(e) / (c * h * h):.3f} | "
              + " | ".join(f"{ch.get(g, 0.0):+.3e}" for g in groups) + f" | {total:+.3e} | {s:.2f} |")
    print("chord errors times N^2: " + "; ".join(
        f"N={n}: " + ", ".join(f"{g} {ch.get(g, 0.0) * n * n:+.3f}" for g in groups) for n, _, _, ch, _ in rows))
    bad = [n for n, h, e, _, _ in rows if abs(e) > c * h * h * (1 + 1e-12)]
    print("|e(N)| <= C h^2 for every N" if not bad else f"|e(N)| > C h^2 at N = {bad}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
