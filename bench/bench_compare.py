"""Representations compared on the benchmark part at growing resolution.

Run: ``.venv/bin/python bench/bench_compare.py [--resolutions 32 64 128]``

Prints, per resolution, each representation's bytes in memory, build seconds,
volume error against the exact volume and seconds for 10^5 membership queries,
and the occupancy grid's memory against its error up to N = 128.
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from implicit import box, cylinder, sphere  # noqa: E402
from spatial.compare import compare, grid_sweep  # noqa: E402

EXACT = 0.988789504774


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--resolutions", type=int, nargs="+", default=[32, 64, 128])
    args = ap.parse_args(argv)
    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    print(f"load average {os.getloadavg()[0]:.1f}")
    for n in args.resolutions:
        table = compare(part, resolution=n, reference=EXACT, claims=False, progress=False)
        print(f"\nN = {n}")
        print(f"{'representation':<36}{'bytes':>12}{'build s':>10}{'vol err':>10}{'1e5 q s':>10}")
        for r in table.rows:
            if r.applies:
                err = "-" if r.volume_error is None else f"{r.volume_error:.2e}"
                q = "-" if r.query_seconds is None else f"{r.query_seconds:.3g}"
                print(f"{r.name:<36}{r.bytes:>12}{r.build_seconds:>10.3g}{err:>10}{q:>10}")
    print("\noccupancy grid: N, bytes (bool), error (count), error (fraction)")
    for row in grid_sweep(part, EXACT, (8, 16, 32, 64, 128)):
        print(f"{row['N']:>4} {row['bytes_bool']:>10} {row['error_count']:.2e} {row['error_fraction']:.2e}")


if __name__ == "__main__":
    main()
