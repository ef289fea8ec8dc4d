"""Benchmark: CPU per stage and thread of one in-process mesh of the benchmark part, and its two-core estimate.

Each run is a fresh process: a warm-up mesh at N=64, then one timed `spatial.mesh` at N (the second
call) with the slabs on one thread, so that every slab's prepare and mesh CPU times are read apart
(`time.thread_time`).  The **two-core estimate** is the process CPU with the slab loop replaced by
its pipeline on two free cores (prepare k after prepare k-1 and mesh k-2, mesh k after prepare k and
mesh k-1) and the evaluation chunks by their schedule on two threads, the lost-feature search (its own
thread beside the mesh) counted only past the pipeline's idle core time; it ignores the GIL.  On a
shared machine, where walls say little, CPU figures are the ones to read.  Codes alternate run by
run; medians.

    .venv/bin/python bench/bench_stages.py [--sizes 512] [--repeat 3] [--plain] [--root CLONE]
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
import sys, time, threading, collections, json, resource
sys.path.insert(0, sys.argv[1])
n = int(sys.argv[2]); feat = sys.argv[3] == "1"
from implicit import box, cylinder, sphere
from spatial import mesh
import spatial.meshing.cells as cm, spatial.meshing.boundary as bm, spatial.meshing.slab as sm
part = ((sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0))
        - cylinder(0.5, 4, axis=(0, 0, 1)))
T = collections.defaultdict(float)
P, M = [], []
ASIDE = set()   # stages that ran on a thread of their own
def wrap(mod, name, label, store=None):
    f = getattr(mod, name)
    def g(*a, **k):
        t = time.thread_time(); r = f(*a, **k); d = time.thread_time() - t
        T[label] += d
        if threading.current_thread() is not threading.main_thread(): ASIDE.add(label)
        if store is not None: store.append(d)
        return r
    setattr(mod, name, g)
wrap(bm, "_boundary_cells_2h", "classify")
wrap(cm, "merge_blocks", "merge")
wrap(cm, "_refine_on_edges", "refine")
wrap(cm, "sharp_polydata_lent", "features")
wrap(sm._SlabJob, "prepare", "prepare", P)
wrap(sm._SlabJob, "mesh", "mesh", M)
import spatial.cells.specks as sp
wrap(sp, "lost_feature", "specks")   # on its own thread beside the mesh
import spatial.meshing.arrays as am, spatial.meshing.refine as rm
C = []   # per call of _chunks_on_threads: the chunks' CPU times
real_chunks = getattr(am, "_chunks_on_threads", None)
def chunks_spy(work, n, chunk=am.EVAL_CHUNK, threads=2):
    times = []
    def timed(a, b):
        t = time.thread_time(); work(a, b); times.append(time.thread_time() - t)
    real_chunks(timed, n, chunk, threads)
    C.append((threads, times))
bm._chunks_on_threads = chunks_spy
rm._chunks_on_threads = chunks_spy
import spatial.meshing.blocks as blm
for mod in (blm, cm):   # the merge's parts (the column: this thread's share), the vertex stage on two threads
    if hasattr(mod, "_chunks_on_threads"):
        mod._chunks_on_threads = chunks_spy
orig = sm.run_slabs
cm.run_slabs = lambda tasks, parts, overlap=False: orig(tasks, parts, overlap=False)
mesh(part, resolution=64, progress=False, features=feat)
T.clear(); P.clear(); M.clear(); C.clear()
c0 = time.process_time(); t0 = time.perf_counter()
m = mesh(part, resolution=n, progress=False, features=feat)
wall = time.perf_counter() - t0; cpu = time.process_time() - c0
# pipeline on two free cores: prepare k after prepare k-1 and mesh k-2 (two slots);
# mesh k after prepare k and mesh k-1
pe, me = [], []
for k in range(len(P)):
    start = max(pe[k - 1] if k else 0.0, me[k - 2] if k >= 2 else 0.0)
    pe.append(start + P[k])
    me.append(max(pe[k], me[k - 1] if k else 0.0) + M[k])
pipe = me[-1]
rest = cpu - sum(T.values())
chunk_cpu = sum(sum(t) for _, t in C)
span = 0.0
for threads, times in C:   # list scheduling on the threads, in submit order
    free = [0.0] * max(1, threads if len(times) > 1 else 1)
    for d in times:
        i = free.index(min(free)); free[i] += d
    span += max(free) if free else 0.0
# (the chunks run on pool threads: their CPU is in `cpu`, not in the stages' thread times)
# the lost-feature search runs on a thread of its own beside the mesh: it costs the wall only past the
# pipeline's idle core time, shared by the two cores
idle = 2 * pipe - T["prepare"] - T["mesh"]
aside = T["specks"] if "specks" in ASIDE else 0.0   # (a code that searches on the main thread: serial)
est = cpu - T["prepare"] - T["mesh"] + pipe - chunk_cpu + span - aside + max(0.0, aside - idle) / 2
print(json.dumps(dict(n=n, feat=feat, wall=round(wall, 2), cpu=round(cpu, 3), two_core_estimate=round(est, 3),
      pipeline=round(pipe, 3), chunk_cpu=round(chunk_cpu, 3), chunk_span=round(span, 3), rest=round(rest, 3),
      slabs=len(P), tri=m.n_cells,
      peak=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024, **{k: round(v, 3) for k, v in T.items()})))
"""

FIELDS = ("cpu", "two_core_estimate", "classify", "specks", "prepare", "mesh", "merge", "features", "peak")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--plain", action="store_true", help="features=False (the plain mesh)")
    parser.add_argument("--root", default=None, help="another clone to mesh with, in the same runs")
    args = parser.parse_args(argv)
    roots = [ROOT] + ([os.path.abspath(args.root)] if args.root else [])
    print("N     code" + "".join(f" {f:>9.9}" for f in FIELDS))
    for n in args.sizes:
        runs = {r: [] for r in roots}
        for _ in range(args.repeat):
            for r in roots:
                res = subprocess.run([sys.executable, "-c", CHILD, r, str(n), "0" if args.plain else "1"],
                                     capture_output=True, text=True, check=True)
                runs[r].append(json.loads(res.stdout.strip().splitlines()[-1]))
        for r in roots:
            med = [statistics.median(x.get(f, 0.0) for x in runs[r]) for f in FIELDS]
            print(f"{n:<5} {os.path.basename(r.rstrip('/')):<4}" + "".join(f" {v:>9.3f}" for v in med), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
