"""Cost of the lost-feature detection (`spatial.cells.specks`) against the mesh it guards.

Meshes the benchmark part at N = 128 and 256 with the detection and without it (the
same process, alternating, median of `--repeat` runs each), and times the detection
alone on the classification's output.

    .venv/bin/python bench/bench_specks.py [--repeat 5] [--sizes 128 256]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "examples")]

from benchmark_part import model  # noqa: E402

from spatial import mesh  # noqa: E402
from spatial.cells import specks  # noqa: E402
from spatial.cells.lattice import make_lattice  # noqa: E402
from spatial.meshing.boundary import boundary_cells_2h  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--sizes", type=int, nargs="+", default=[128, 256])
    args = ap.parse_args(argv)
    part = model()
    real = specks.warn_lost
    mesh(part, resolution=32, progress=False)         # compile and warm up
    for n in args.sizes:
        on, off, alone = [], [], []
        lat = make_lattice(part, resolution=n)
        found = boundary_cells_2h(lat, False)
        for _ in range(args.repeat):
            for use, times in ((True, on), (False, off)):
                specks.warn_lost = real if use else (lambda *a, **k: None)
                t = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    mesh(part, resolution=n, progress=False)
                times.append(time.perf_counter() - t)
            specks.warn_lost = real
            t = time.perf_counter()
            f = specks.lost_feature(lat.solid, lat.origin, lat.voxel_size, found["cells"], found["centres"],
                                    uniform=found["uniform"], uniform_parents=found["uniform_parents"])
            alone.append(time.perf_counter() - t)
        a, b, c = (float(np.median(x)) for x in (on, off, alone))
        print(f"N={n}: mesh {b:.3f} s without, {a:.3f} s with the detection; detection alone {c * 1e3:.1f} ms "
              f"({100 * c / b:.1f} % of the mesh), {found['cells'].shape[0]} BOUNDARY cells of 2h, feature {f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
