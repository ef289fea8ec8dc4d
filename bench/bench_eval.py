"""Points per second of evaluating a 50-node CSG tree, step by step.

The part: a rounded plate with six bosses, two rotated ribs and two rotated
brackets (each a box minus a bore), all joined by a smooth union (fillets),
minus twenty through-holes, six boss bores, two countersink cones and a ring
groove: 50 nodes by ``count_nodes()``.  It is evaluated on 10^6 points spread
uniformly over its bounds, and on 10^6 points within 0.05 of its surface
(as the mesher queries them).

Rows (median of several runs, each on the same points):

* hand numpy      - the tree written by hand in plain numpy, whole arrays
* Solid numpy     - the plain `Solid` evaluation (chunks of `EVAL_CHUNK` rows)
* numpy chunk=N   - the same with other chunk sizes
* tape            - the numba tape interpreter, no pruning
* tape + pruning  - binned points, operands switched off per bin (the default
                    of ``solid(points)`` from 100k points)
* ... 2 threads   - the same on two cores (pruned: each thread bins and
                    evaluates half of the points; unpruned: ``prange``)

Also: the plate with a rotated wedge added, a kind without a fast-path rule
(evaluated by numpy as an input column of the tape).

Run: ``.venv/bin/python bench/bench_eval.py [--runs 7] [--points 1000000]``
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from implicit import (box, cone, cylinder, difference, rounded_box, smooth_union,  # noqa: E402
                      torus)
from implicit.polyhedra import wedge  # noqa: E402
from implicit import compile as fast  # noqa: E402
from implicit import solid as solid_module  # noqa: E402


def make_part():
    """The 50-node benchmark plate."""
    plate = rounded_box((10.0, 6.0, 0.6), 0.1)
    bosses = [cylinder(0.5, 1.2, center=(x, y, 0.5)) for x in (-3.0, 0.0, 3.0) for y in (-1.5, 1.5)]
    ribs = [box((6.0, 0.3, 0.8), center=(0, 0, 0.3)).rotate(a, (0, 0, 1)) for a in (25.0, -25.0)]
    brackets = [(box((1.6, 0.4, 1.6)) - cylinder(0.35, 1.0, axis=(0, 1, 0)))
                .rotate(15 * s, (0, 0, 1)).translate((4.2 * s, 0, 1.0)) for s in (-1, 1)]
    body = smooth_union(plate, *bosses, *ribs, *brackets, blend=0.2)
    holes = [cylinder(0.15, 2.0, center=(x, y, 0)) for x in np.linspace(-4.5, 4.5, 10) for y in (-2.6, 2.6)]
    bores = [cylinder(0.25, 3.0, center=(x, y, 0.5)) for x in (-3.0, 0.0, 3.0) for y in (-1.5, 1.5)]
    sinks = [cone(0.4, 0.5, center=(x, 0.0, 0.05)) for x in (-1.5, 1.5)]
    groove = torus(0.8, 0.08, center=(0.0, 0.0, 0.3))
    return difference(body, *holes, *bores, *sinks, groove)


# -- the same part by hand in plain numpy ------------------------------------

def _rot_z(deg):
    a = np.radians(deg)
    return np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])


def _box(p, size, center=(0, 0, 0), radius=0.0):
    q = np.abs(p - np.asarray(center)) - (np.asarray(size) / 2 - radius)
    return (np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)) - radius


def _cyl(p, r, h, center, axis=2):
    d = p - np.asarray(center)
    other = [i for i in range(3) if i != axis]
    dr = np.hypot(d[:, other[0]], d[:, other[1]]) - r
    dz = np.abs(d[:, axis]) - h / 2
    return np.hypot(np.maximum(dr, 0), np.maximum(dz, 0)) + np.minimum(np.maximum(dr, dz), 0)


def _cone(p, r1, h, center):
    d = p - np.asarray(center)
    qx = np.hypot(d[:, 0], d[:, 1])
    hh = h / 2
    qy = d[:, 2] - hh
    k2x, k2y = -r1, 2 * hh
    cax = qx - np.minimum(qx, np.where(qy < 0, r1, 0.0))
    cay = np.abs(qy) - hh
    t = np.clip(((0.0 - qx) * k2x + (hh - qy) * k2y) / (k2x * k2x + k2y * k2y), 0, 1)
    cbx = qx + k2x * t
    cby = qy - hh + k2y * t
    s = np.where((cbx < 0) & (cay < 0), -1.0, 1.0)
    return s * np.sqrt(np.minimum(cax * cax + cay * cay, cbx * cbx + cby * cby))


def _smin(a, b, k):
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0, 1)
    return b + (a - b) * h - k * h * (1 - h)


def hand_numpy(p):
    """The benchmark plate written directly in numpy."""
    d = _box(p, (10.0, 6.0, 0.6), radius=0.1)
    for x in (-3.0, 0.0, 3.0):
        for y in (-1.5, 1.5):
            d = _smin(d, _cyl(p, 0.5, 1.2, (x, y, 0.5)), 0.2)
    for a in (25.0, -25.0):
        d = _smin(d, _box(p @ _rot_z(a), (6.0, 0.3, 0.8), (0, 0, 0.3)), 0.2)
    for s in (-1, 1):
        q = (p - np.array([4.2 * s, 0, 1.0])) @ _rot_z(15 * s)
        d = _smin(d, np.maximum(_box(q, (1.6, 0.4, 1.6)), -_cyl(q, 0.35, 1.0, (0, 0, 0), axis=1)), 0.2)
    for x in np.linspace(-4.5, 4.5, 10):
        for y in (-2.6, 2.6):
            d = np.maximum(d, -_cyl(p, 0.15, 2.0, (x, y, 0)))
    for x in (-3.0, 0.0, 3.0):
        for y in (-1.5, 1.5):
            d = np.maximum(d, -_cyl(p, 0.25, 3.0, (x, y, 0.5)))
    for x in (-1.5, 1.5):
        d = np.maximum(d, -_cone(p, 0.4, 0.5, (x, 0.0, 0.05)))
    g = p - np.array([0.0, 0.0, 0.3])
    d = np.maximum(d, -(np.hypot(np.hypot(g[:, 0], g[:, 1]) - 0.8, g[:, 2]) - 0.08))
    return d


# -- measurement ---------------------------------------------------------------

def median_rate(func, points, runs):
    """Median points per second of `func(points)` over `runs` runs: by the
    wall clock, and by the process's CPU time (all threads: per core)."""
    wall, cpu = [], []
    for _ in range(runs):
        start, start_cpu = time.perf_counter(), time.process_time()
        func(points)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    n = points.shape[0]
    return n / float(np.median(wall)), n / float(np.median(cpu))


def numpy_chunked(part, chunk):
    def run(points):
        old = solid_module.EVAL_CHUNK
        solid_module.EVAL_CHUNK = chunk
        try:
            return fast._numpy_evaluate(part, points)
        finally:
            solid_module.EVAL_CHUNK = old
    return run


def compile_seconds_fresh() -> dict:
    """Compile times measured in a fresh interpreter (numba's first calls)."""
    code = ("import time; t = time.perf_counter(); import implicit.evaluate.compile as c; "
            "c._kernel('serial'); c._kernel('bin'); c._kernel('unsort'); c._kernel('bounds'); "
            "s = time.perf_counter() - t; c._kernel('parallel'); "
            "print(s, c.COMPILE_SECONDS['parallel'])")
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True)
    serial, parallel = (float(v) for v in out.stdout.split())
    return {"serial": serial, "parallel": parallel}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--slow-runs", type=int, default=3, help="runs of the slow numpy rows")
    args = parser.parse_args(argv)

    part = make_part()
    n = args.points
    rng = np.random.default_rng(0)
    lo, hi = part.bounds
    uniform = lo + (hi - lo) * rng.random((n, 3))
    print(f"tree: {part.count_nodes()} nodes, {part.count_primitives()} primitives, depth {part.depth()}; "
          f"{n} points; numba {'yes' if fast.numba_available() else 'no'}; {os.cpu_count()} cores")

    compiled = fast.compile_solid(part)
    times = compile_seconds_fresh()
    print(f"numba compile (fresh process): interpreter + binning {times['serial']:.2f} s, "
          f"parallel interpreter {times['parallel']:.2f} s; tape of this tree: "
          f"{len(compiled.tape)} operations, {compiled.tape.nreg} registers, {len(compiled.tape.flags)} flags")

    # Points within 0.05 of the surface.
    cand = lo + (hi - lo) * rng.random((8 * n, 3))
    dist = compiled(cand)
    near = cand[np.abs(dist) < 0.05]
    near = near[rng.integers(0, near.shape[0], n)] + rng.normal(0, 1e-3, (n, 3))
    near = np.ascontiguousarray(near)

    # A kind without a fast-path rule: a rotated wedge joined to the body is
    # evaluated by numpy as an input of the tape, in the bins that read it.
    body, *tools = part.children
    ribbed = difference(smooth_union(body, wedge((1.0, 0.4, 0.8), (2.0, -0.2, 0.3)).rotate(30.0, (0, 0, 1)),
                                     blend=0.1), *tools)
    fast_ribbed = fast.compile_solid(ribbed)
    ref = fast._numpy_evaluate(ribbed, uniform)
    assert np.abs(fast_ribbed(uniform) - ref).max() <= 1e-12
    print(f"plate + rotated wedge ({ribbed.count_nodes()} nodes, {len(fast_ribbed.tape.opaque)} numpy input), "
          "uniform points, wall and core M/s:")
    for name, func, runs in (("  Solid numpy", lambda p: fast._numpy_evaluate(ribbed, p), args.slow_runs),
                             ("  tape + pruning, 1 core", fast_ribbed, args.runs)):
        uw, uc = median_rate(func, uniform, runs)
        print(f"{name:36s} {uw / 1e6:12.2f} {uc / 1e6:6.2f}", flush=True)

    ref_u = fast._numpy_evaluate(part, uniform)
    err = np.abs(hand_numpy(uniform) - ref_u).max()
    # Threads of the parallel kernel spin for a while after use: its rows come last.
    parallel = fast.compile_solid(part, parallel=True, warm=False)
    rows = [
        ("hand numpy (whole arrays)", hand_numpy, args.slow_runs),
        ("Solid numpy, chunk 32768 (before)", numpy_chunked(part, 32768), args.slow_runs),
        ("Solid numpy, chunk 4096", numpy_chunked(part, 4096), args.slow_runs),
        ("Solid numpy, chunk 16384 (now)", numpy_chunked(part, 16384), args.slow_runs),
        ("Solid numpy, chunk 131072", numpy_chunked(part, 131072), args.slow_runs),
        ("tape, 1 core", lambda p: compiled(p, prune=False), args.runs),
        ("tape + pruning, 1 core (default)", lambda p: compiled(p, prune=True), args.runs),
        ("tape, 2 threads", lambda p: parallel(p, prune=False), args.runs),
        ("tape + pruning, 2 threads", lambda p: parallel(p, prune=True), args.runs),
    ]
    print(f"hand numpy vs Solid: max difference {err:.1e}; load average {os.getloadavg()[0]:.1f}")
    print("M points/s, median; wall = by the clock, core = by CPU time (per core)")
    print(f"{'step':36s} {'uniform wall':>12s} {'core':>6s} {'near-surface wall':>18s} {'core':>6s}")
    for name, func, runs in rows:
        for pts in (uniform, near):
            func(pts[:1000])
        uw, uc = median_rate(func, uniform, runs)
        nw, nc = median_rate(func, near, runs)
        print(f"{name:36s} {uw / 1e6:12.2f} {uc / 1e6:6.2f} {nw / 1e6:18.2f} {nc / 1e6:6.2f}", flush=True)
    for pts, ref in ((uniform, ref_u), (near, fast._numpy_evaluate(part, near))):
        for func in (compiled, parallel):
            diff = np.abs(func(pts) - ref).max()
            assert diff <= 1e-12, diff
    print("compiled results equal the numpy evaluation to 1e-12")

    return 0


if __name__ == "__main__":
    sys.exit(main())
