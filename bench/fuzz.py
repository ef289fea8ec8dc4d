"""Fuzz: random CSG trees meshed by `spatial.mesh`, every mesh checked; counts by kind of failure.

The trees come from `tests/fuzzgen.py` (seeded: case ``s`` is the same tree
on every machine) and each mesh is checked by `tests/fuzzcheck.py`: closed,
2-manifold, oriented outward, no zero-area, repeated-index or duplicate
triangles, finite vertices, and a volume that agrees with a Monte-Carlo
estimate.  Prints the count of valid meshes and the count of each kind of
failure, and the seeds of the first failures of each kind (to turn into
regression tests).

    .venv/bin/python bench/fuzz.py [--cases 10000] [--start 0] [--jobs 2] [--min-res 16] [--max-res 96]
        [--features on|off|default]
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "tests")]

import fuzzcheck  # noqa: E402
from fuzzcheck import NOT_INVALID, failures  # noqa: E402
from fuzzgen import random_case  # noqa: E402

_RES = (16, 96)


def _init(res, features=None):
    global _RES
    _RES = res
    fuzzcheck.FEATURES = features


def _one(seed):
    case = random_case(seed, resolutions=_RES, max_depth=5)
    return seed, failures(case), case.text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=10000)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--min-res", type=int, default=16)
    ap.add_argument("--max-res", type=int, default=96)
    ap.add_argument("--features", choices=("on", "off", "default"), default="default",
                    help="mesh with features=True / False, or the mesher's default")
    args = ap.parse_args(argv)
    feats = {"on": True, "off": False, "default": None}[args.features]
    res = (args.min_res, args.max_res)
    t0 = time.perf_counter()
    counts = collections.Counter()
    examples = collections.defaultdict(list)
    valid = done = 0
    seeds = range(args.start, args.start + args.cases)
    with ProcessPoolExecutor(args.jobs, initializer=_init, initargs=(res, feats)) as pool:
        for seed, found, text in pool.map(_one, seeds, chunksize=8):
            done += 1
            invalid = [k for k in found if k not in NOT_INVALID]
            valid += not invalid
            for k in found:
                counts[k] += 1
                if len(examples[k]) < 5:
                    examples[k].append((seed, text[:120]))
            if done % 1000 == 0:
                print(f"{done} cases, {valid} valid, {time.perf_counter() - t0:.0f} s", flush=True)
    print(f"cases {done} (seeds {args.start}..{args.start + args.cases - 1}, resolution {res[0]}-{res[1]}, "
          f"depth 0-5, features {args.features}): valid meshes {valid} of {done}, crashes "
          f"{sum(v for k, v in counts.items() if k.startswith('crash'))}, {time.perf_counter() - t0:.0f} s")
    for k, v in counts.most_common():
        print(f"  {v:6d}  {k}")
        for seed, text in examples[k]:
            print(f"          seed {seed}: {text}")
    return 0 if valid == done else 1


if __name__ == "__main__":
    sys.exit(main())
