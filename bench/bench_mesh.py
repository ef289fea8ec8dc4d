"""Benchmark: boundary mesh of the benchmark part at N = 128 ... 1024 cells across.

Each size runs in its own subprocess so that the peak resident memory
(``resource.getrusage(RUSAGE_SELF).ru_maxrss``) belongs to that size alone.
Prints one table row per N: wall and processor seconds (medians of the runs;
processor time is the fairer figure on a shared machine), distance
evaluations (boxes bounded + points sampled), peak MB (imports and the
compiled evaluator take about 280 MB before meshing starts), triangles and
checks.

Targets: N=512 in <= 3 s and 500 MB, N=1024 in <= 15 s and 1.5 GB, at most 6
million evaluations at N=512 growing <= 4.5x per doubling.

    .venv/bin/python bench/bench_mesh.py [--sizes 128 256 512 1024] [--repeat 3] [--no-refine]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, {root!r})
from implicit import box, cylinder, sphere
from spatial import mesh
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
import numpy, pyvista, skimage.measure  # imports outside the timing
part(numpy.zeros((200000, 3)))  # warm any compiled evaluation path outside the timing
t0 = time.perf_counter()
c0 = time.process_time()
m = mesh(part, resolution={n}, refine={refine}, progress=False)
wall = time.perf_counter() - t0
cpu = time.process_time() - c0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
out = dict(wall=wall, cpu=cpu, peak=peak, evaluations=int(m.field_data["evaluations"][0]), triangles=m.n_cells,
           vertices=m.n_points, volume=float(m.volume), manifold=bool(m.is_manifold),
           euler=int(m.n_points - m.extract_all_edges().n_cells + m.n_cells) if {n} <= 256 else None)
print(json.dumps(out))
"""


def run_one(n, refine):
    code = CHILD.format(root=ROOT, n=n, refine=refine)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[128, 256, 512, 1024])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-refine", action="store_true")
    args = parser.parse_args(argv)
    refine = not args.no_refine
    print(f"benchmark part, spatial.mesh(refine={refine}); median of {args.repeat} runs, one process each")
    print(f"{'N':>6} {'wall s':>8} {'cpu s':>7} {'evaluations':>12} {'peak MB':>8} {'triangles':>10} {'volume':>11} manifold")
    prev = None
    for n in args.sizes:
        runs = [run_one(n, refine) for _ in range(args.repeat)]
        wall = statistics.median(r["wall"] for r in runs)
        cpu = statistics.median(r["cpu"] for r in runs)
        peak = max(r["peak"] for r in runs)
        r = runs[0]
        growth = f"  (x{r['evaluations'] / prev:.2f})" if prev else ""
        prev = r["evaluations"]
        print(f"{n:>6} {wall:>8.2f} {cpu:>7.2f} {r['evaluations']:>12,d} {peak:>8.0f} {r['triangles']:>10,d} "
              f"{r['volume']:>11.8f} {'yes' if r['manifold'] else 'NO'}{growth}", flush=True)
    print("exact volume 0.98878635")
    return 0


if __name__ == "__main__":
    sys.exit(main())
