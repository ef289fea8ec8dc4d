"""Benchmark: whole processes and the mesh command of several source trees, side by side with fogleman/sdf.

A change to start-up cost (imports, numba's cache loads) shows only in whole
processes, and on a shared machine only when the runs being compared alternate.
This runs, round by round, each source tree's whole process (a fresh interpreter
that imports and meshes the benchmark part once at h = 1.6/N: the child of
`bench/whole_process.py`) and fogleman/sdf's, then each tree's
``implicad mesh examples/benchmark_part.py -o part.stl --resolution N``; it
prints medians of wall, CPU (user + system of the child) and peak MB, and the
ratios to sdf.  A tree is a checkout of implicad run by this Python with the
tree first on ``sys.path`` (its numba cache primed beforehand: a first run
compiles).  Also prints where a whole process of each tree spends its CPU:
imports, the first mesh and a second one.  The meshes are what a user gets by
default (sharp features rebuilt, as the command does); ``--no-features`` runs the
plain mesh instead (``features=False``, the figures recorded before features
became the default).

    .venv/bin/python bench/bench_startup.py --tree main=/tmp/main --tree branch=. \\
        --sizes 256 512 --repeat 5 --sdf-python /tmp/sdfvenv/bin/python --command 256
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import whole_process as wp  # noqa: E402

#: The console script of a tree: `console` (which ends the process without the interpreter's teardown) where the
#: tree has it, else `main`.
COMMAND = ("import sys; sys.path.insert(0, {root!r}); import spatial.cli as cli; "
           "cli.console() if hasattr(cli, 'console') else sys.exit(cli.main())")

PHASES = r"""
import json, sys, time
sys.path.insert(0, {root!r})
T = time.process_time
t = [T()]
import numpy; t.append(T())
import implicit; t.append(T())
import spatial; t.append(T())
from implicit import box, cylinder, sphere
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
spatial.mesh(part, resolution={n}, progress=False, features=False); t.append(T())
spatial.mesh(part, resolution={n}, progress=False, features=False); t.append(T())
print(json.dumps(dict(zip(("numpy", "implicit", "spatial", "mesh 1", "mesh 2"), (b - a for a, b in zip(t, t[1:]))))))
"""


def _with_features(child: str) -> str:
    """The child's mesh calls with `spatial.mesh`'s default (features on) instead of ``features=False``."""
    assert ", features=False" in child
    return child.replace(", features=False", "")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", action="append", metavar="NAME=PATH",
                        help="a source tree to run (repeatable; default: this one)")
    parser.add_argument("--sizes", type=int, nargs="*", default=[256])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--sdf-python", default=None, metavar="PATH")
    parser.add_argument("--command", type=int, default=0, metavar="N")
    parser.add_argument("--no-features", action="store_true", help="whole processes mesh without features")
    args = parser.parse_args(argv)
    child, phases = (wp.IMPLICAD_CHILD, PHASES) if args.no_features else \
        (_with_features(wp.IMPLICAD_CHILD), _with_features(PHASES))
    trees = dict(t.split("=", 1) for t in (args.tree or [f"this={os.path.dirname(HERE)}"]))
    trees = {name: os.path.abspath(path) for name, path in trees.items()}
    why = wp.sdf_usable(args.sdf_python)
    med = statistics.median
    print(f"load average {os.getloadavg()[0]:.1f} at {time.strftime('%H:%M')}; trees: {trees}; "
          f"features {'off' if args.no_features else 'on'}"
          + (f"; sdf skipped ({why})" if why else ""))
    for n in args.sizes:
        runs = {name: [] for name in trees}
        peer = []
        for _ in range(args.repeat):
            for name, root in trees.items():
                runs[name].append(wp.run_child([sys.executable, "-c", child.format(root=root, n=n)]))
            if not why:
                peer.append(wp.sdf_run(args.sdf_python, n))
        other = {k: med(r[k] for r in peer) for k in ("wall", "cpu", "peak")} if peer else None
        for name in trees:
            row = {k: med(r[k] for r in runs[name]) for k in ("wall", "cpu", "peak", "mesh")}
            line = f"N={n} {name}: wall {row['wall']:.2f} s, cpu {row['cpu']:.2f} s, peak {row['peak']:.0f} MB"
            if other:
                line += (f" | x sdf: wall {row['wall'] / other['wall']:.3f}, cpu {row['cpu'] / other['cpu']:.3f}, "
                         f"peak {row['peak'] / other['peak']:.3f}")
            print(line, flush=True)
        if other:
            print(f"N={n} sdf: wall {other['wall']:.2f} s, cpu {other['cpu']:.2f} s, peak {other['peak']:.0f} MB, "
                  f"{peer[0]['triangles']:,d} triangles, volume {peer[0]['volume']:.5f}", flush=True)
    if args.command:
        with tempfile.TemporaryDirectory() as tmp:
            runs = {name: [] for name in trees}
            for _ in range(args.repeat):
                for name, root in trees.items():
                    runs[name].append(wp.run_child(
                        [sys.executable, "-c", COMMAND.format(root=root), "mesh",
                         os.path.join(root, "examples", "benchmark_part.py"), "-o", os.path.join(tmp, "part.stl"),
                         "--resolution", str(args.command)]))
        for name, r in runs.items():
            print(f"command N={args.command} {name}: wall {med(x['wall'] for x in r):.2f} s, "
                  f"cpu {med(x['cpu'] for x in r):.2f} s, peak {med(x['peak'] for x in r):.0f} MB", flush=True)
    n = args.sizes[0] if args.sizes else 256
    for name, root in trees.items():
        rows = [wp.run_child([sys.executable, "-c", phases.format(root=root, n=n)]) for _ in range(3)]
        print(f"CPU of a whole process at N={n}, {name} (median of 3): "
              + ", ".join(f"{k} {med(r[k] for r in rows):.2f} s" for k in ("numpy", "implicit", "spatial",
                                                                          "mesh 1", "mesh 2")), flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at {time.strftime('%H:%M')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
