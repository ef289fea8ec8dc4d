"""`mass_properties(part)` with no options: value, bound, true error, time and the cells of each level.

Parts with closed-form volumes: the 100 x 100 x 1 plate, the same plate turned
30 degrees about x then y and moved to (1000, -500, 200), a boss on a plate,
the benchmark part, a sphere and examples/bracket.py.  Each part runs the
default route (the levels meshed with sharp edges rebuilt) and, for
comparison, the plain meshes' Richardson extrapolation at the same
tolerance (``mesher=default_mesher()``), interleaved; wall seconds are the
median of `--runs` runs (default 1) after one warm-up call of each route
(on a small part: the compilation of the evaluator and the mesher).

    .venv/bin/python bench/bench_mass_default.py [--runs 1] [--parts plate rplate bench]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import implicit as I
from spatial.analysis import mass_solid
from spatial.analysis.mass import ToleranceError, mass_properties


def parts():
    from examples.bracket import solid as bracket

    plate = I.box((100.0, 100.0, 1.0))
    bench = ((I.sphere(1.0) & I.box(1.5)) - I.cylinder(0.5, 4, axis=(1, 0, 0)) - I.cylinder(0.5, 4, axis=(0, 1, 0))
             - I.cylinder(0.5, 4, axis=(0, 0, 1)))
    return {
        "plate": (plate, 1e4),
        "rplate": (I.translate(I.rotate(I.rotate(plate, 30, (1, 0, 0)), 30, (0, 1, 0)), (1000, -500, 200)), 1e4),
        "boss": (I.box((4.0, 4.0, 1.0)) | I.box((1.0, 1.0, 1.0), center=(0.0, 0.0, 1.0)), 17.0),
        "bench": (bench, 0.988789504774),
        "sphere": (I.sphere(1.0), 4 * np.pi / 3),
        "bracket": (bracket, 10320.0 - 4 * np.pi * 9.0 * 4.0),
    }


def measure(solid, volume, mesher, tolerance):
    levels = []
    level = mass_solid._solid_level

    def spy(solid, h, c0, mesher, correct=True, check=False):
        vec = level(solid, h, c0, mesher, correct=correct, check=check)
        levels.append((h, vec[0]))
        return vec

    mass_solid._solid_level = spy
    try:
        t = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                p = mass_properties(solid, tolerance=tolerance, mesher=mesher)
        except ToleranceError as exc:
            return time.perf_counter() - t, None, levels, str(exc)
        return time.perf_counter() - t, p, levels, ""
    finally:
        mass_solid._solid_level = level


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--tolerance", type=float, default=1e-4)
    ap.add_argument("--parts", nargs="*", default=["plate", "rplate", "boss", "bench", "sphere", "bracket"])
    args = ap.parse_args(argv)
    table = parts()
    routes = {"features (default)": None, "plain + Richardson": mass_solid.default_mesher()}
    print(f"load average {os.getloadavg()[0]:.1f}, tolerance {args.tolerance:g}")
    print("| part | route | volume | bound (rel.) | true error (rel.) | brackets | s (median) | levels: cells, rel. error |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for mesher in routes.values():                # warm-up: the one-off compilation of evaluator and mesher
        measure(I.box((2.0, 1.0, 0.5)) - I.cylinder(0.2, 1.0), 1.0, mesher, 1e-3)
    for name in args.parts:
        solid, V = table[name]
        extent = float(np.max(solid.bounds[1] - solid.bounds[0]))
        times = {r: [] for r in routes}
        last = {}
        for _ in range(args.runs):
            for route, mesher in routes.items():
                dt, p, levels, why = measure(solid, V, mesher, args.tolerance)
                times[route].append(dt)
                last[route] = (p, levels, why)
        for route in routes:
            p, levels, why = last[route]
            lv = ", ".join(f"{round(extent / h)}: {(v - V) / V:+.1e}" for h, v in levels)
            s = statistics.median(times[route])
            if p is None:
                print(f"| {name} | {route} | refused: {why.split(':')[1].strip()[:60]} | | | | {s:.2f} | {lv} |")
                continue
            err = p.volume - V
            print(f"| {name} | {route} | {p.volume:.10g} | {p.error.volume:.3g} ({p.error.volume / V:.1e}) | "
                  f"{err:+.3g} ({err / V:+.1e}) | {'yes' if abs(err) <= p.error.volume else 'NO'} | {s:.2f} | {lv} |",
                  flush=True)
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
