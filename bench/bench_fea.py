"""Tetrahedral meshes of the benchmark part: time, element counts and quality at three sizes.

Run: ``.venv/bin/python bench/bench_fea.py [--repeat N] [--order 2]``.  Prints a table
(median wall time of the runs; surface remeshing and tet meshing apart), then the
example parts at one size each against the targets (min dihedral >= 10, max <= 165,
no inverted element, volume within 0.5 percent of the closed form).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from implicit import box, cylinder, sphere, torus  # noqa: E402
from spatial.fea import surface_for_fea, surface_quality, tet_mesh  # noqa: E402
from spatial.fea.tetmesh import MeshQualityWarning  # noqa: E402

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
PARTS = {
    "sphere R=1": (sphere(1.0), 4.0 / 3.0 * np.pi, 0.08),
    "torus 1/0.3": (torus(1.0, 0.3), 2 * np.pi**2 * 0.09, 0.05),
    "box with hole": (box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0), 1.0 - np.pi * 0.0625 * 0.5, 0.08),
    "benchmark part": (BENCH, 0.988789504774, 0.06),
}


def run(solid, size, order):
    t0 = time.perf_counter()
    surf = surface_for_fea(solid, size=size)
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshQualityWarning)
        m = tet_mesh(solid, size=size, order=order, surface=surf)
    t2 = time.perf_counter()
    return surf, m, t1 - t0, t2 - t1, [str(w.message) for w in caught]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--order", type=int, default=1, choices=(1, 2))
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.1, 0.06, 0.045])
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    run(BENCH, 0.2, args.order)
    print(f"warm-up (compiling the field evaluator, size 0.2): {time.perf_counter() - t0:.1f} s")
    print(f"benchmark part, order {args.order}, median of {args.repeat} runs")
    print(f"{'size':>6} {'tets':>8} {'nodes':>8} {'surf s':>7} {'tets s':>7} {'total s':>8} {'min dih':>8} "
          f"{'max dih':>8} {'p1 min':>7} {'max r/e':>8} {'min SJ':>7} {'vol err %':>9} {'surf dev':>9}")
    for size in args.sizes:
        runs = [run(BENCH, size, args.order) for _ in range(args.repeat)]
        ts = np.median([r[2] for r in runs])
        tt = np.median([r[3] for r in runs])
        surf, m, *_ , msgs = runs[-1]
        q = m.quality
        err = 100 * abs(m.volume - 0.988789504774) / 0.988789504774
        print(f"{size:6.3f} {q.n_elements:8d} {q.n_nodes:8d} {ts:7.2f} {tt:7.2f} {ts + tt:8.2f} {q.min_dihedral:8.2f} "
              f"{q.max_dihedral:8.2f} {q.dihedral_p1:7.2f} {q.max_radius_edge:8.2f} {q.min_scaled_jacobian:7.3f} "
              f"{err:9.4f} {m.surface_deviation:9.2e}")
        for msg in msgs:
            print(f"       warning: {msg}")
    print()
    print("example parts (one run each)")
    print(f"{'part':<15} {'size':>6} {'tets':>8} {'s':>6} {'min dih':>8} {'max dih':>8} {'min SJ':>7} "
          f"{'vol err %':>9} {'surf min ang':>12} {'targets':>8}")
    for name, (solid, volume, size) in PARTS.items():
        surf, m, ts, tt, msgs = run(solid, size, args.order)
        q = m.quality
        err = 100 * abs(m.volume - volume) / volume
        ok = q.min_dihedral >= 10 and q.max_dihedral <= 165 and q.min_scaled_jacobian > 0 and err < 0.5
        print(f"{name:<15} {size:6.3f} {q.n_elements:8d} {ts + tt:6.2f} {q.min_dihedral:8.2f} {q.max_dihedral:8.2f} "
              f"{q.min_scaled_jacobian:7.3f} {err:9.4f} {surface_quality(surf).min_angle:12.1f} {'met' if ok else 'MISSED':>8}")
    print()
    print("quality of the benchmark part at size 0.05")
    print(run(BENCH, 0.05, args.order)[1].quality.table())


if __name__ == "__main__":
    main()
