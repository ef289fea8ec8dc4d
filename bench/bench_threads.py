"""Benchmark: the benchmark part meshed in process with one slab thread and with two, on a shared machine.

Each run is a fresh process: a warm-up mesh at N=64, then one timed `spatial.mesh` at N (the second
call).  Besides wall and CPU it prints a quiet-machine estimate: the wall minus the time the main
thread spent runnable but waiting for a core (``/proc/self/task/<tid>/schedstat``, field 2; Linux
only).  For one thread that is its CPU time; with two it keeps the main thread's waits for the GIL
and for the other thread.  Modes alternate run by run; medians.

    .venv/bin/python bench/bench_threads.py [--sizes 512 1024] [--repeat 5] [--root CLONE] [--plain]

``--plain`` meshes with ``features=False`` (the plain marching-cubes mesh); the default is
`spatial.mesh`'s default, the feature mesh.

``--root`` meshes with another clone's code (main's, say) in the same runs; its rows say ``code``
(that code's default, whatever it is) rather than a thread count.
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
import functools, json, resource, sys, threading, time
sys.path.insert(0, {root!r})
from implicit import box, cylinder, sphere
from spatial import mesh
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
if {threads} in (1, 2):
    import spatial.meshing.cells as cells_mod
    from spatial.meshing.slab import run_slabs
    cells_mod.run_slabs = lambda tasks, parts, overlap=False: run_slabs(tasks, parts, overlap={threads} == 2)
tid = threading.get_native_id()
def stat():
    a = open(f"/proc/self/task/{{tid}}/schedstat").read().split()
    return int(a[1]) / 1e9
mesh(part, resolution=64, progress=False, features={features})
q0, t0, c0 = stat(), time.perf_counter(), time.process_time()
m = mesh(part, resolution={n}, progress=False, features={features})
wall, cpu, queued = time.perf_counter() - t0, time.process_time() - c0, stat() - q0
print(json.dumps(dict(wall=wall, cpu=cpu, quiet=wall - queued, triangles=m.n_cells,
                      peak=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)))
"""


def run_one(root, n, threads, features=True):
    code = CHILD.format(root=root, n=n, threads=threads, features=features)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--root", default=None, help="another clone to mesh with, in the same runs")
    parser.add_argument("--plain", action="store_true", help="the plain mesh (features=False), not the default")
    args = parser.parse_args(argv)
    modes = [(ROOT, 1, "1 thread"), (ROOT, 2, "2 threads")]
    if args.root:
        modes.insert(0, (os.path.abspath(args.root), 0, "code at " + os.path.basename(args.root.rstrip("/"))))
    print(f"{'N':>5} {'mode':<24} {'quiet est s':>11} {'wall s':>7} {'cpu s':>6} {'peak MB':>7} {'triangles':>11}")
    for n in args.sizes:
        runs = {label: [] for _, _, label in modes}
        for _ in range(args.repeat):
            for root, threads, label in modes:
                runs[label].append(run_one(root, n, threads, not args.plain))
        for _, _, label in modes:
            r = runs[label]
            med = {k: statistics.median(x[k] for x in r) for k in ("quiet", "wall", "cpu", "peak")}
            print(f"{n:>5} {label:<24} {med['quiet']:>11.2f} {med['wall']:>7.2f} {med['cpu']:>6.2f} "
                  f"{med['peak']:>7.0f} {r[-1]['triangles']:>11,d}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
