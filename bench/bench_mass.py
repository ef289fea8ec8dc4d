"""Time to the volume of the benchmark part at a relative error of 1e-4.

The benchmark part (REFERENCE.md): ``(sphere(1) & box(1.5))`` minus three
cylinders of radius 0.5 along x, y and z; volume 0.988789504774.

Rows:
* ``mass_properties(tolerance=...)``: corrected marching-cubes meshes with
  Richardson extrapolation, refined until the error estimate meets the
  tolerance (meshing included);
* the same at fixed resolutions;
* without meshing: an octree's FULL cells integrated exactly plus its
  BOUNDARY cells by fractional occupancy.

Each figure is the median of several runs after one warm-up run (which pays
the one-off compilation of the evaluator and mesher).

    .venv/bin/python bench/bench_mass.py
"""

from __future__ import annotations

import statistics
import sys
import time

from implicit import box, cylinder, sphere
from spatial.analysis.mass import mass_properties
from spatial.cells.octree import Octree

VOLUME = 0.988789504774
RUNS = 5


def part():
    return (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))


def timed(func, runs=RUNS):
    func()
    times, out = [], None
    for _ in range(runs):
        t0 = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(runs=RUNS):
    solid = part()
    rows = []
    from spatial.analysis.mass import ToleranceError

    for tol in (1e-3, 1e-4, 1e-5):
        try:
            t, p = timed(lambda: mass_properties(solid, tolerance=tol), runs if tol > 1e-5 else 1)
        except ToleranceError as exc:      # refused, not warned: the sharp part's floor
            print(f"tolerance {tol:g}: {exc}")
            continue
        rows.append((f"mesh + Richardson, tolerance {tol:g}", t, p.volume, p.error.volume, p.voxel_size))
    for n in (64, 128, 256):
        t, p = timed(lambda: mass_properties(solid, resolution=n), max(1, runs // 2) if n > 128 else runs)
        rows.append((f"mesh + Richardson, N = {n}", t, p.volume, p.error.volume, p.voxel_size))
    for n in (64, 128, 256):
        t, p = timed(lambda: mass_properties(Octree.from_solid(solid, resolution=n, progress=False)),
                     max(1, runs // 2) if n > 128 else runs)
        rows.append((f"octree, fractional occupancy, N = {n}", t, p.volume, p.error.volume, p.voxel_size))
    print(f"benchmark part, true volume {VOLUME}; median of {runs} runs")
    print(f"{'method':<42} {'time s':>8} {'rel. error':>11} {'estimate':>10} {'h':>8}")
    for name, t, v, e, h in rows:
        print(f"{name:<42} {t:8.3f} {abs(v - VOLUME) / VOLUME:11.2e} {e / VOLUME:10.2e} {h:8.4f}"
              f"{'' if abs(v - VOLUME) <= e else '  (bound does not bracket)'}")
    return rows


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else RUNS)
