"""Benchmark: wall, CPU and peak memory of one in-process mesh of the benchmark part, and its digest.

Each run is a fresh process: a warm-up mesh at N=64, then the timed `spatial.mesh(part, resolution=N,
progress=False, features=...)` (the second call in the process, as a session meets it).  Peak memory is
the process's ``ru_maxrss`` (imports and the compiled evaluator included); the digest is the SHA-256 of
the points' and faces' bytes, with the evaluation count, so that two codes can be shown to give the same
mesh bit for bit.  Codes alternate run by run; medians, with the load average before each run.

    .venv/bin/python bench/bench_wall.py [--sizes 512 1024] [--repeat 3] [--features] [--root CLONE]
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
import sys, time, json, resource, hashlib
sys.path.insert(0, sys.argv[1])
n = int(sys.argv[2]); feat = sys.argv[3] == "1"
import numpy as np
from implicit import box, cylinder, sphere
from spatial import mesh
part = ((sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0))
        - cylinder(0.5, 4, axis=(0, 0, 1)))
mesh(part, resolution=64, progress=False, features=feat)
c0 = time.process_time(); t0 = time.perf_counter()
m = mesh(part, resolution=n, progress=False, features=feat)
wall = time.perf_counter() - t0; cpu = time.process_time() - c0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
pts = np.ascontiguousarray(m.points, dtype=np.float64)
faces = np.asarray(m.faces)
digest = hashlib.sha256(pts.tobytes() + np.ascontiguousarray(faces, dtype=np.int64).tobytes()).hexdigest()
print(json.dumps(dict(wall=wall, cpu=cpu, peak=peak, sha=digest[:16], points=int(pts.shape[0]),
                      evaluations=int(m.field_data["evaluations"][0]))))
"""


def _load():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--features", action="store_true", help="features=True (the default mesh)")
    parser.add_argument("--root", default=None, help="another clone to mesh with, in the same runs")
    parser.add_argument("--python", default=None, help="the interpreter of --root's runs (default: its .venv)")
    args = parser.parse_args(argv)
    roots = [ROOT] + ([os.path.abspath(args.root)] if args.root else [])
    print(f"{'N':<5} {'code':<6} {'wall':>7} {'cpu':>7} {'peak MB':>8} {'load':>5} {'evaluations':>12} sha")
    for n in args.sizes:
        runs = {r: [] for r in roots}
        for _ in range(args.repeat):
            for r in roots:
                py = sys.executable if r == ROOT else (args.python or os.path.join(r, ".venv", "bin", "python"))
                load = _load()
                res = subprocess.run([py, "-c", CHILD, r, str(n), "1" if args.features else "0"],
                                     capture_output=True, text=True, check=True)
                out = json.loads(res.stdout.strip().splitlines()[-1])
                out["load"] = load
                runs[r].append(out)
        for r in roots:
            rs = runs[r]
            med = {f: statistics.median(x[f] for x in rs) for f in ("wall", "cpu", "peak", "load")}
            shas = sorted({x["sha"] for x in rs})
            evs = sorted({x["evaluations"] for x in rs})
            print(f"{n:<5} {os.path.basename(r.rstrip('/')):<6} {med['wall']:7.3f} {med['cpu']:7.3f} "
                  f"{med['peak']:8.0f} {med['load']:5.1f} {','.join(map(str, evs)):>12} {','.join(shas)}",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
