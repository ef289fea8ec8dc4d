"""Benchmark: the feature pass's cost against the plain mesh, two trees interleaved run by run.

Each run is a child process that imports a tree (``--tree name=PATH``: a clone with its numba cache
primed), warms the evaluator outside the timing as `bench_mesh.CHILD` does and meshes the benchmark
part with ``features=False`` and ``features=True``:

* ``--mode fresh``: one mesh per child (what `bench_mesh.py --features` times: the feature
  kernels' cached loads included);
* ``--mode inproc``: plain, features, plain, features in one child; the first pair dropped.

Prints per tree the medians of CPU seconds (``time.process_time``: user + system of every thread),
system seconds, minor page faults, the pass alone (`spatial.meshing.features.sharpen`), walls and
the peak resident MB of the children.  On a shared machine the CPU figures are the ones to read.

    .venv/bin/python bench/bench_feature_pass.py --tree before=/tmp/before --tree now=. \\
        --mode fresh --sizes 256 512 --repeat 5
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

CHILD = r"""
import gc, json, resource, sys, time
sys.path.insert(0, {root!r})
import implicit
assert implicit.__file__.startswith({root!r}), implicit.__file__
from implicit import box, cylinder, sphere
from spatial import mesh
from spatial.meshing import features as F
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
import numpy, pyvista, skimage.measure  # imports outside the timing
part(numpy.zeros((200000, 3)))  # warm any compiled evaluation path outside the timing
spent = {{}}
real = F.sharpen if not hasattr(F, "_sharpen") else F._sharpen
def timed(*a, **k):
    c = time.process_time(); r = real(*a, **k); spent["pass"] = time.process_time() - c; return r
setattr(F, "_sharpen" if hasattr(F, "_sharpen") else "sharpen", timed)
res = []
for feat in {feats}:
    spent.clear(); gc.collect()
    r0 = resource.getrusage(resource.RUSAGE_SELF); c0 = time.process_time(); t0 = time.perf_counter()
    m = mesh(part, resolution={n}, progress=False, features=feat)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    res.append(dict(feat=feat, cpu=cpu, wall=wall, sys=r1.ru_stime - r0.ru_stime, faults=r1.ru_minflt - r0.ru_minflt,
                    peak=r1.ru_maxrss / 1024, triangles=m.n_cells, pass_cpu=spent.get("pass", 0.0)))
    del m
print(json.dumps(res))
"""


def child(root, n, feats):
    out = subprocess.run([sys.executable, "-c", CHILD.format(root=root, n=n, feats=feats)], capture_output=True,
                         text=True)
    if out.returncode:
        raise RuntimeError(f"the child for {root} at N={n} failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", action="append", required=True, metavar="NAME=PATH")
    parser.add_argument("--mode", choices=("fresh", "inproc"), default="fresh")
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    trees = dict(t.split("=", 1) for t in args.tree)
    med = statistics.median
    for n in args.sizes:
        rows = {(t, f): [] for t in trees for f in (False, True)}
        for _ in range(args.repeat):
            for t, root in trees.items():
                if args.mode == "fresh":
                    for f in (False, True):
                        rows[(t, f)].append(child(root, n, [f])[0])
                else:
                    for r in child(root, n, [False, True, False, True])[2:]:
                        rows[(t, r["feat"])].append(r)
        print(f"\n{args.mode}, N={n}, medians of {args.repeat}")
        print(f"{'tree':<10} {'plain cpu':>9} {'sys':>6} {'faults':>8} {'feat cpu':>9} {'sys':>6} {'faults':>8} "
              f"{'ratio':>6} {'pass':>6} {'walls':>12} {'peak MB':>10}")
        for t in trees:
            p, f = rows[(t, False)], rows[(t, True)]
            m = {k: (med(r[k] for r in p), med(r[k] for r in f)) for k in ("cpu", "sys", "faults", "wall")}
            print(f"{t:<10} {m['cpu'][0]:>9.3f} {m['sys'][0]:>6.3f} {m['faults'][0]:>8.0f} {m['cpu'][1]:>9.3f} "
                  f"{m['sys'][1]:>6.3f} {m['faults'][1]:>8.0f} {m['cpu'][1] / m['cpu'][0]:>6.3f} "
                  f"{med(r['pass_cpu'] for r in f):>6.3f} {m['wall'][0]:>5.2f}/{m['wall'][1]:<6.2f} "
                  f"{max(r['peak'] for r in p):>4.0f}/{max(r['peak'] for r in f):<5.0f}", flush=True)
        plain = [r["cpu"] for t in trees for r in rows[(t, False)]]
        print(f"plain CPU of all trees pooled: median {med(plain):.3f} s of {len(plain)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
