"""Conversions between parametric curves/surfaces and solids: timings and accuracy.

Prints (median of several runs):

* closest-point projection of 10^5 points onto a bicubic B-spline surface
  (8 x 8 control net): `parametric.projection.project_to_surface` and the
  cached-tree `implicit.parametric_solids.SurfaceProjector` (tree build
  included), with the largest disagreement between the two and the error on
  an exact NURBS sphere;
* evaluation rates of the converted solids (points per second);
* section fitting, lofting and star-surface fitting times, and the volume
  change of the round trip solid -> grid -> surface -> solid.

Run: ``.venv/bin/python bench/bench_convert.py``
"""

from __future__ import annotations

import time

import numpy as np

REPEATS = 3


#: CPU seconds of the last `_median_time` (median), printed beside wall time:
#: on a shared machine the wall clock also counts other processes.
LAST_CPU = [0.0]


def _median_time(fn, repeats=REPEATS):
    times, cpu, out = [], [], None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    LAST_CPU[0] = float(np.median(cpu))
    return float(np.median(times)), out


def _cpu():
    return f"{LAST_CPU[0]:.2f}"


def _grid(solid, cells):
    from spatial.cells.grid import OccupancyGrid

    lo, hi = solid.bounds
    h = float(np.max(hi - lo)) / cells
    origin = lo - 2 * h
    shape = np.ceil((hi - lo) / h).astype(int) + 4
    axes = [origin[i] + h * (np.arange(shape[i]) + 0.5) for i in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), -1)
    return OccupancyGrid(solid(pts.reshape(-1, 3)).reshape(pts.shape[:3]), origin=origin, voxel_size=h)


def bench_projection():
    from implicit.parametric_solids import SurfaceProjector
    from parametric.projection import project_to_surface
    from parametric.tensor import BSplineSurface, sphere

    g = np.linspace(0.0, 1.0, 8)
    P = np.stack(np.meshgrid(g, g, indexing="ij"), -1)
    P = np.concatenate([P, 0.2 * np.sin(3 * P[..., :1]) * np.cos(2 * P[..., 1:])], -1)
    surf = BSplineSurface(P, 3, 3)
    X = np.random.default_rng(0).uniform(-0.2, 1.2, (100_000, 3))
    print("closest-point projection, 10^5 points")
    print("| method | surface | wall (s) | cpu (s) | notes |")
    print("| --- | --- | --- | --- | --- |")
    t_par, (_, _, d_par) = _median_time(lambda: project_to_surface(surf, X))
    print(f"| parametric.project_to_surface | B-spline 8x8 bicubic | {t_par:.2f} | {_cpu()} | tree built per call |")
    t_own, (_, _, d_own) = _median_time(lambda: SurfaceProjector(surf).project(X))
    print(f"| SurfaceProjector (build + project) | B-spline 8x8 bicubic | {t_own:.2f} | {_cpu()} | "
          f"max |d - d_parametric| = {np.max(np.abs(d_own - d_par)):.1e} |")
    proj = SurfaceProjector(surf)
    t_cached, _ = _median_time(lambda: proj.project(X))
    print(f"| SurfaceProjector (tree cached) | B-spline 8x8 bicubic | {t_cached:.2f} | {_cpu()} | |")
    ball = SurfaceProjector(sphere(1.0))
    Y = np.random.default_rng(1).uniform(-2, 2, (100_000, 3))
    t_sph, (_, _, d_sph) = _median_time(lambda: ball.project(Y))
    err_sph = float(np.max(np.abs(d_sph - np.abs(np.linalg.norm(Y, axis=1) - 1.0))))
    print(f"| SurfaceProjector (tree cached) | NURBS sphere 9x5 | {t_sph:.2f} | {_cpu()} | max error {err_sph:.1e} |")
    print()


def bench_solids():
    from implicit import extrude_curve, revolve_curve, surface_solid, sweep, thicken, volume_solid
    from implicit.sweeps import circle
    from parametric.conics import arc, ellipse
    from parametric.curves import BSpline
    from parametric.tensor import BezierSurface, torus
    from parametric.volumes import NURBSVolume

    solids = {
        "revolve_curve (rectangle)": revolve_curve(BSpline([[0.5, -1], [1.5, -1], [1.5, 1], [0.5, 1], [0.5, -1]], 1)),
        "extrude_curve (NURBS ellipse)": extrude_curve(ellipse(1.5, 1.0, center=(0.0, 0.0)), 2.0),
        "sweep (circle along arc)": sweep(circle(0.4), arc(2.0, 0.0, np.pi / 2, center=(0.0, 0.0, 0.0))),
        "thicken (bilinear patch)": thicken(BezierSurface([[[-1, -1, 0], [-1, 1, 0.5]], [[1, -1, 0.5], [1, 1, 0]]]), 0.3),
        "surface_solid (NURBS torus)": surface_solid(torus(1.5, 0.5)),
        "volume_solid (NURBS tube)": volume_solid(NURBSVolume.revolve_rectangle(0.5, 1.0, -1.0, 1.0)),
    }
    X = np.random.default_rng(2).uniform(-2.5, 2.5, (32768, 3))
    print("evaluation of converted solids, 32768 points")
    print("| solid | wall (s) | cpu (s) | points / cpu s |")
    print("| --- | --- | --- | --- |")
    for name, s in solids.items():
        t, _ = _median_time(lambda s=s: s(X))
        print(f"| {name} | {t:.3f} | {_cpu()} | {X.shape[0] / max(LAST_CPU[0], 1e-9):,.0f} |")
    print()


def bench_fitting():
    from implicit import ellipsoid, revolve_curve
    from parametric.curves import BSpline
    from spatial.convert.fitting import fit_section_curve, fit_star_surface, loft_sections

    e = ellipsoid((2.0, 1.5, 1.0))
    exact = 4.0 / 3.0 * np.pi * 3.0
    t_sec, fit = _median_time(lambda: fit_section_curve(e, "z=0.3", tolerance=1e-4))
    t_loft, lres = _median_time(lambda: loft_sections(e, "z", 8, tolerance=1e-3), 1)
    t_star, star = _median_time(lambda: fit_star_surface(e, n_control=(24, 12)), 1)
    print("fitting")
    print("| task | time (s) | result |")
    print("| --- | --- | --- |")
    print(f"| fit_section_curve, ellipsoid z=0.3, tol 1e-4 | {t_sec:.2f} | "
          f"{fit.n_control} control points, deviation {fit.max_deviation:.1e} |")
    print(f"| loft_sections, 8 levels, tol 1e-3 | {t_loft:.2f} | net {np.asarray(lres.surface.control_points).shape[:2]}, "
          f"deviation {lres.max_deviation:.1e} |")
    print(f"| fit_star_surface, 64 x 33 rays, 24 x 12 control | {t_star:.2f} | deviation {star.max_deviation:.1e}, "
          f"volume error {star.solid.volume() / exact - 1:+.1e} |")
    for cells in (64, 128):
        grid = _grid(e, cells)
        t_rt, rt = _median_time(lambda grid=grid: fit_star_surface(grid, n_control=(24, 12)), 1)
        print(f"| round trip via a {cells}-cell grid | {t_rt:.2f} | volume change {rt.solid.volume() / exact - 1:+.1e} |")
    try:
        from spatial import mass_properties

        tube = revolve_curve(BSpline([[0.5, -1], [1.5, -1], [1.5, 1], [0.5, 1], [0.5, -1]], 1))
        t_m, props = _median_time(lambda: mass_properties(tube, resolution=64), 1)
        v = np.pi * (1.5 ** 2 - 0.5 ** 2) * 2.0
        print(f"| mass_properties(revolve_curve tube, 64 cells) | {t_m:.2f} | volume error {props.volume / v - 1:+.1e} |")
    except ImportError:  # pragma: no cover - spatial mass properties missing
        pass
    print()


def main():
    bench_projection()
    bench_solids()
    bench_fitting()


if __name__ == "__main__":
    main()
