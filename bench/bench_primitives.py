"""Million points per second of the kernel's numpy fields, and JSON speed.

Each primitive, sweep and family is evaluated with its plain numpy
``_evaluate`` (no compiled fast path) on the same uniformly spread points of
its padded bounds; figures are the median of several runs.  The JSON rows
time `to_json` and `from_json` of a family part, of the benchmark part and
of a flat union of many spheres.

Run: ``.venv/bin/python bench/bench_primitives.py [--runs 5] [--points 200000]``
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import implicit as I
from implicit.families import instance
from implicit.serialize import from_json, to_json


def _hexagon(r=1.0, n=6):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def cases():
    return {
        "sphere": I.sphere(1.0),
        "box": I.box((1, 2, 3)),
        "cylinder (tilted)": I.cylinder(1, 2, axis=(1, 1, 0)),
        "frustum": I.frustum(1, 0.5, 2),
        "torus": I.torus(1, 0.3),
        "ellipsoid (bound)": I.ellipsoid((1, 2, 3)),
        "capsule": I.capsule((0, 0, 0), (1, 1, 1), 0.3),
        "wedge (5 planes)": I.wedge((1, 1, 1)),
        "pyramid (8-gon base)": I.pyramid(_hexagon(1, 8), 1.0),
        "convex_polyhedron (20 planes)": I.convex_polyhedron(
            *(lambda n: (n, n))(np.array([[np.cos(t) * np.sin(p), np.sin(t) * np.sin(p), np.cos(p)]
                                          for t, p in zip(np.linspace(0, 20, 20), np.arccos(np.linspace(-0.95, 0.95, 20)))]))),
        "prism (hexagon)": I.prism(_hexagon(), 1.0),
        "prism (64-gon)": I.prism(_hexagon(1, 64), 1.0),
        "extrude (profile boolean)": I.extrude(I.circle(1) - I.rectangle(0.5) | I.circle(0.3, (1.2, 0)), 1.0),
        "revolve (full)": I.revolve(I.polygon([(0.3, -0.5), (1, -0.5), (0.8, 0.5), (0.3, 0.5)])),
        "revolve (270 deg)": I.revolve(I.polygon([(0.3, -0.5), (1, -0.5), (0.8, 0.5), (0.3, 0.5)]), 270),
        "hole_plate family (9 nodes)": instance("hole_plate"),
        "flanged_pipe family (11 nodes)": instance("flanged_pipe"),
    }


def median_time(func, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        func()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--points", type=int, default=200_000)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(0)
    print(f"| field | Mpoints/s (numpy, {args.points} points) |")
    print("| --- | --- |")
    for name, solid in cases().items():
        lo, hi = solid.bounds
        pad = 0.2 * (hi - lo)
        pts = np.ascontiguousarray(rng.uniform(lo - pad, hi + pad, (args.points, 3)))
        t = median_time(lambda: solid._evaluate(pts), args.runs)
        print(f"| {name} | {args.points / t / 1e6:.1f} |")
    part = I.sphere(1) & I.box(1.5)
    part = part - I.cylinder(0.5, 4, axis=(1, 0, 0)) - I.cylinder(0.5, 4, axis=(0, 1, 0)) - I.cylinder(0.5, 4)
    many = I.union(*[I.sphere(0.1, center=c) for c in rng.uniform(-1, 1, (10000, 3))])
    print()
    print("| tree | nodes | to_json ms | from_json ms |")
    print("| --- | --- | --- | --- |")
    for name, solid in (("benchmark part", part), ("flanged_pipe family", instance("flanged_pipe")),
                        ("union of 10000 spheres", many)):
        text = to_json(solid)
        t_out = median_time(lambda: to_json(solid), args.runs)
        t_in = median_time(lambda: from_json(text), args.runs)
        print(f"| {name} | {solid.count_nodes()} | {t_out * 1e3:.2f} | {t_in * 1e3:.2f} |")


if __name__ == "__main__":
    main()
