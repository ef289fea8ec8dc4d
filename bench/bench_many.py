"""Benchmark: parts with many primitives, meshed at N = 256 in process.

Three parts whose trees are large: a plate 100 x 60 x 5 with a 10 x 10 grid of
holes (101 primitives), a 24-tooth gear minus its bore (26), and a lattice of
5^3 cells of capsules along the cells' edges (540) intersected with a box; and, on
request (``--parts benchmark``), the benchmark part of `bench/bench_mesh.py` (4).
Each size runs in its own process after a warm-up mesh at N = 64 (the second
call, as in a session); wall and CPU seconds are medians of the runs.

Targets at N = 256: plate <= 0.8 s, gear <= 0.8 s, lattice <= 2.5 s.

    .venv/bin/python bench/bench_many.py [--resolution 256] [--repeat 3] [--parts plate gear lattice benchmark] [--plain]
        [--root CLONE]

``--plain``: the plain mesh (``features=False``) rather than `spatial.mesh`'s default, the feature
mesh; ``--root``: mesh with another clone's code (the parts are built by this file).
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
sys.path.insert(0, {bench!r})
sys.path.insert(0, {root!r})
from bench_many import build
from spatial import mesh
part = build({name!r})
mesh(part, resolution=64, progress=False, features={features})
runs = []
for _ in range({repeat}):
    t0, c0 = time.perf_counter(), time.process_time()
    m = mesh(part, resolution={n}, progress=False, features={features})
    runs.append((time.perf_counter() - t0, time.process_time() - c0))
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps(dict(runs=runs, peak=peak, triangles=int(m.n_cells), volume=float(m.volume),
                      primitives=int(part.count_primitives()), evaluations=int(m.field_data["evaluations"][0]))))
"""

TARGETS = {"plate": 0.8, "gear": 0.8, "lattice": 2.5}
#: Parts measured beside the targets: the benchmark part (4 primitives), whose pass must not get slower.
OTHERS = ("benchmark",)


def build(name):
    """The named benchmark part."""
    import numpy as np

    from implicit import box, capsule, cylinder, instance, rotate, union

    if name == "plate":
        return instance("hole_plate", length=100.0, width=60.0, thickness=5.0, hole_diameter=3.0, rows=10,
                        cols=10, margin=6.0)
    if name == "gear":
        tooth = box((3.0, 4.0, 8.0), center=(21.0, 0.0, 0.0))
        teeth = [rotate(tooth, 360.0 * k / 24) for k in range(24)]
        return union(cylinder(20.0, 8.0), *teeth) - cylinder(5.0, 20.0)
    if name == "lattice":
        pitch, cells, radius = 1.0, 5, 0.12
        ticks = np.arange(cells + 1) * pitch
        caps = []
        for axis in range(3):
            for i in ticks[:cells]:
                for j in ticks:
                    for k in ticks:
                        a = np.roll(np.array([i, j, k]), axis)
                        b = a + np.roll(np.array([pitch, 0.0, 0.0]), axis)
                        caps.append(capsule(tuple(a), tuple(b), radius))
        span = cells * pitch
        return union(*caps) & box((span, span, span), center=(span / 2,) * 3)
    if name == "benchmark":
        from implicit import sphere

        return ((sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0))
                - cylinder(0.5, 4, axis=(0, 0, 1)))
    raise ValueError(f"name: expected one of {sorted(TARGETS) + list(OTHERS)}, got {name!r}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--parts", nargs="+", default=list(TARGETS), choices=list(TARGETS) + list(OTHERS))
    parser.add_argument("--plain", action="store_true", help="features=False (the plain mesh)")
    parser.add_argument("--root", default=ROOT, help="the clone whose code meshes")
    args = parser.parse_args(argv)
    print(f"parts with many primitives, spatial.mesh at N={args.resolution} in process after a warm-up; "
          f"median of {args.repeat}")
    print(f"{'part':<8} {'prims':>5} {'wall s':>7} {'cpu s':>6} {'target':>6} {'peak MB':>7} {'evaluations':>12} "
          f"{'triangles':>10} {'volume':>10}")
    for name in args.parts:
        code = CHILD.format(root=os.path.abspath(args.root), bench=os.path.join(ROOT, "bench"), name=name,
                            n=args.resolution, repeat=args.repeat, features=not args.plain)
        res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        r = json.loads(res.stdout.strip().splitlines()[-1])
        wall = statistics.median(w for w, _ in r["runs"])
        cpu = statistics.median(c for _, c in r["runs"])
        print(f"{name:<8} {r['primitives']:>5d} {wall:>7.2f} {cpu:>6.2f} {TARGETS.get(name, 0):>6.1f} "
              f"{r['peak']:>7.0f} {r['evaluations']:>12,d} {r['triangles']:>10,d} {r['volume']:>10.4f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
