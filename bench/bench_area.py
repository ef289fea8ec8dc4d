"""CPU time of `mass_properties(benchmark part, tolerance=1e-4)` and its area against the exact one.

Median of 5 runs in a warm process (one run first compiles and fills the caches), CPU time of this
process (`time.process_time`): the machine is shared, wall time is noisier.

    .venv/bin/python bench/bench_area.py
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "examples")]

from benchmark_part import model  # noqa: E402

from spatial.analysis.mass import mass_properties  # noqa: E402

AREA, VOLUME = 12.327770219, 0.988789504774


def main():
    part = model()
    mass_properties(part, tolerance=1e-4)
    times = []
    for _ in range(5):
        t = time.process_time()
        p = mass_properties(part, tolerance=1e-4)
        times.append(time.process_time() - t)
    print(f"mass_properties(benchmark, tolerance=1e-4): median CPU {np.median(times):.3f} s "
          f"(runs {', '.join(f'{t:.3f}' for t in times)})")
    print(f"  area   {p.area:.9f} +- {p.error.area:.2g} (exact {AREA}; error {p.area / AREA - 1:+.2e}, "
          f"bracketed: {abs(p.area - AREA) <= p.error.area})")
    print(f"  volume {p.volume:.9f} +- {p.error.volume:.2g} (exact {VOLUME}; error {p.volume / VOLUME - 1:+.2e}, "
          f"bracketed: {abs(p.volume - VOLUME) <= p.error.volume})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
