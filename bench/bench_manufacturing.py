"""Manufacturing and inspection figures: slices, tool paths and their verification, scans, stack-up.

Rows:
* slices of the benchmark part (volume 0.988789504774) at layer heights H:
  the error of sum(area) x H (the midpoint rule of the layer model);
* the milled plate of examples/milled_plate.py (mm), flat end mill r = 3:
  planning time, moves, and the verification on a 0.5 mm dexel grid
  (removed volume against the exact 86400 - 54309.8 mm^3, gouge, excess);
* inspection of the benchmark part: a scan (its mesh) moved by 7 degrees and
  (0.05, -0.03, 0.08), the alignment's largest error in the 4x4 matrix;
* stack-up of examples/stackup.py with 2000 Monte-Carlo samples.

Times are medians of a few runs after a warm-up run (noisy on a shared machine).

    .venv/bin/python bench/bench_manufacturing.py
"""

from __future__ import annotations

import math
import os
import runpy
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "examples"))


def timed(fn, repeat=3):
    fn()
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def main():
    from implicit import box, cylinder, sphere
    from implicit.transforms import rotation_matrix
    from spatial.inspection import inspect, stackup
    from spatial.manufacturing import slice as slice_solid, toolpath, verify
    from spatial.meshing import mesh

    part = (sphere(1.0) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    print("| slices of the benchmark part, H | layers | s | volume error |")
    print("| --- | --- | --- | --- |")
    for H in (0.02, 0.01, 0.005):
        t, s = timed(lambda H=H: slice_solid(part, H, resolution=128), repeat=1)
        print(f"| {H:g} | {len(s.layers)} | {t:.2f} | {s.volume - 0.988789504774:+.2e} |")

    plate = runpy.run_path(os.path.join(HERE, "..", "examples", "milled_plate.py"))["model"]()
    t_plan, tp = timed(lambda: toolpath(plate, 3.0, resolution=128), repeat=1)
    t_ver, v = timed(lambda: verify(plate, tp, resolution=160), repeat=1)
    exact_removed = 86400.0 - (48000 + 9600 - 1600 - math.pi * 16 * 18 - math.pi * 25 * 10)
    print()
    print("| milled plate, r = 3 mm | value |")
    print("| --- | --- |")
    print(f"| planning s (resolution 128) | {t_plan:.2f} |")
    print(f"| depths / operations / moves | {len(tp.depths)} / {len(tp.operations)} / {tp.move_count} |")
    print(f"| verification s (160 columns across) | {t_ver:.2f} |")
    print(f"| removed mm^3 (exact {exact_removed:.1f}) | {v.removed_volume:.1f} |")
    print(f"| gouge / excess mm^3 beyond {v.tolerance:.2f} mm | {v.gouge_volume:.3g} / {v.excess_volume:.3g} |")
    print(f"| material cut by rapids mm^3 | {v.rapid_volume:.3g} |")

    T = np.eye(4)
    T[:3, :3] = rotation_matrix(7.0, (1, 2, 3))
    T[:3, 3] = (0.05, -0.03, 0.08)
    pts = mesh(part, resolution=64).points
    moved = pts @ T[:3, :3].T + T[:3, 3]
    t_ins, r = timed(lambda: inspect(part, moved, tolerance=0.01))
    print()
    print("| inspection, benchmark part | value |")
    print("| --- | --- |")
    print(f"| points | {len(pts)} |")
    print(f"| alignment s | {t_ins:.2f} |")
    print(f"| max abs(T_found T_applied - I) | {np.abs(r.transform @ T - np.eye(4)).max():.1e} |")
    print(f"| RMS deviation after the fit | {r.rms_deviation:.1e} |")

    ns = runpy.run_path(os.path.join(HERE, "..", "examples", "stackup.py"))
    t_st, st = timed(lambda: stackup(ns["parts"], ns["tolerances"], between=ns["between"], samples=2000, seed=0),
                     repeat=1)
    print()
    print("| stack-up, examples/stackup.py, 2000 samples | value |")
    print("| --- | --- |")
    print(f"| s | {t_st:.1f} |")
    print(f"| worst case (closed form 0.005 .. 0.07) | {st.worst_min:.6f} .. {st.worst_max:.6f} |")
    print(f"| Monte-Carlo mean / sigma | {st.mc_mean:.5f} / {st.mc_std:.5f} |")
    print(f"| P(interference) | {st.probability_interference:.4f} |")
    print(f"| largest share | {max(st.contributions, key=st.contributions.get)} |")


if __name__ == "__main__":
    main()
