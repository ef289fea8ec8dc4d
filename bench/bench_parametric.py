"""Timings of the parametric package (median of several runs).

Run: ``.venv/bin/python bench/bench_parametric.py [--repeat N]``

Targets: 10^6 points on a cubic NURBS curve <= 0.1 s; a 1000 x 1000 grid on a
bicubic B-spline surface <= 1 s; closest-point projection of 10^5 points onto a
B-spline surface <= 2 s.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from parametric import (NURBS, BSplineSurface, NURBSVolume, fit_curve,  # noqa: E402
                        project_to_surface, sphere)


def median_time(fn, repeat):
    """Median wall-clock and CPU (process) seconds of ``fn()``.

    On a shared machine the CPU time shows the work done, the wall time what a
    user waits; both are printed with the load average.
    """
    fn()  # warm-up (builds caches, imports)
    wall, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return float(np.median(wall)), float(np.median(cpu))


def main(repeat=7):
    rng = np.random.default_rng(0)
    rows = []

    curve = NURBS(rng.normal(size=(50, 3)), rng.uniform(0.5, 2.0, 50), 3)
    u = rng.uniform(0, 1, 10 ** 6)
    rows.append(("cubic NURBS curve, 10^6 points (uniform knots)",
                 median_time(lambda: curve(u), repeat), 0.1))
    inner = np.sort(rng.uniform(0, 1, 46))
    curve2 = NURBS(rng.normal(size=(50, 3)), rng.uniform(0.5, 2.0, 50), 3,
                   np.concatenate([[0.0] * 4, inner, [1.0] * 4]))
    rows.append(("cubic NURBS curve, 10^6 points (random knots)",
                 median_time(lambda: curve2(u), repeat), 0.1))

    g = np.stack(np.meshgrid(np.linspace(0, 1, 20), np.linspace(0, 1, 20), indexing="ij"), -1)
    net = np.concatenate([g, 0.2 * rng.random((20, 20, 1))], -1)
    surf = BSplineSurface(net, 3, 3)
    t = np.linspace(0, 1, 1000)
    rows.append(("bicubic B-spline surface, 1000 x 1000 grid",
                 median_time(lambda: surf.grid(t, t), repeat), 1.0))
    uu, vv = rng.uniform(0, 1, (2, 10 ** 6))
    rows.append(("bicubic B-spline surface, 10^6 scattered points",
                 median_time(lambda: surf(uu, vv), max(3, repeat // 2)), None))

    uv0 = rng.uniform(0, 1, (10 ** 5, 2))
    base = surf(uv0[:, 0], uv0[:, 1])
    P = base + 0.01 * rng.uniform(-1, 1, (10 ** 5, 1)) * surf.normal(uv0[:, 0], uv0[:, 1])
    rows.append(("closest point, 10^5 points onto a 20 x 20 bicubic B-spline surface",
                 median_time(lambda: project_to_surface(surf, P), max(3, repeat // 2)), 2.0))
    Q = rng.normal(size=(10 ** 5, 3)) * 2
    rows.append(("closest point, 10^5 points onto the NURBS sphere",
                 median_time(lambda: project_to_surface(sphere(1.0), Q), max(3, repeat // 2)),
                 None))

    x = np.linspace(0, 1, 24)
    X, Y = np.meshgrid(x, x, indexing="ij")
    wavy = BSplineSurface(np.stack([X, Y, 0.3 * np.sin(6 * np.pi * X) * np.cos(5 * np.pi * Y)],
                                   -1), 3, 3)
    W = np.concatenate([rng.uniform(-0.2, 1.2, (10 ** 5, 2)), rng.uniform(-1.5, 1.5, (10 ** 5, 1))],
                       1)
    rows.append(("closest point, 10^5 points well off a wavy 24 x 24 bicubic patch",
                 median_time(lambda: project_to_surface(wavy, W), max(3, repeat // 2)), 2.0))
    rows.append(("same, one Newton seed per point (no extra seeds)",
                 median_time(lambda: project_to_surface(wavy, W, seeds=1), max(3, repeat // 2)),
                 None))
    rows.append(("NURBS derivative curve (50 control points, cubic -> degree 6)",
                 median_time(lambda: curve2.derivative_curve(), repeat), None))
    ball = sphere(1.0)
    rows.append(("NURBS sphere tessellation 256 x 256, seams and poles welded",
                 median_time(lambda: ball.tessellate(256, 256), repeat), None))

    th = np.linspace(0, 4 * np.pi, 2000)
    helix = np.stack([np.cos(th), np.sin(th), 0.2 * th], 1)
    rows.append(("fit_curve, 2000 helix points to 1e-4",
                 median_time(lambda: fit_curve(helix, 3, tolerance=1e-4), 3), None))
    cyl = NURBSVolume.revolve_rectangle(0.0, 1.0, 0.0, 2.0)
    rows.append(("NURBS solid cylinder mass properties (default rule)",
                 median_time(lambda: cyl.mass_properties(), repeat), None))

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"numpy {np.__version__}, {os.cpu_count()} CPUs, load average {load:.2f}")
    print("| operation | median wall s | median CPU s | target s | ok (wall) |")
    print("| --- | --- | --- | --- | --- |")
    for name, (sec, cpu), target in rows:
        ok = "" if target is None else ("yes" if sec <= target else "NO")
        tgt = "" if target is None else f"{target:g}"
        print(f"| {name} | {sec:.4f} | {cpu:.4f} | {tgt} | {ok} |")
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="timed runs per figure (median)")
    main(ap.parse_args().repeat)
