"""Cost of the lost-feature detection (`spatial.cells.specks`) against the mesh it guards.

Meshes the benchmark part at N = 128 and 256 with the detection and without it (the
same process, alternating, median of `--repeat` runs each), and times the detection
alone on the classification's output.

    .venv/bin/python bench/bench_specks.py [--repeat 5] [--sizes 128 256]

With ``--against FILE`` (another version of spatial/cells/specks.py, e.g. from a clone of an older
commit) the detection alone of both versions is timed alternating in one process, on the benchmark
part at `--sizes`, examples/bracket_fillet.py at its default voxel and 100 specks of radius 0.3 h
beside a box (tests/speckparts.py), with the plain mesh beside it:

    .venv/bin/python bench/bench_specks.py --against /path/to/old/spatial/cells/specks.py
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
sys.path.append(os.path.join(ROOT, "tests"))

from benchmark_part import model  # noqa: E402

from spatial import mesh  # noqa: E402
from spatial.cells import specks  # noqa: E402
from spatial.cells.lattice import make_lattice  # noqa: E402
from spatial.meshing.boundary import boundary_cells_2h  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--sizes", type=int, nargs="+", default=[128, 256])
    ap.add_argument("--against", help="another specks.py: both versions' detection alone, alternating")
    args = ap.parse_args(argv)
    if args.against:
        return against(args)
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


def _load(path):
    """Another version of spatial/cells/specks.py as a module of the package (its kernels are this one's)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("spatial.cells.specks_other", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def against(args):
    import bracket_fillet
    from speckparts import many_specks

    from spatial.cells.thickness import default_voxel_size

    other = _load(args.against)
    cases = [(f"benchmark part N={n}", model(), dict(resolution=n)) for n in args.sizes]
    cases += [("bracket_fillet, default voxel", bracket_fillet.solid,
               dict(voxel_size=default_voxel_size(bracket_fillet.solid, None))),
              ("100 specks beside a box, h=0.1", many_specks(0.1), dict(voxel_size=0.1))]
    mesh(model(), resolution=32, progress=False)
    for name, part, kw in cases:
        lat = make_lattice(part, **kw)
        found = boundary_cells_2h(lat, False)
        a = (lat.solid, lat.origin, lat.voxel_size, found["cells"], found["centres"])
        k = dict(uniform=found["uniform"], uniform_parents=found["uniform_parents"])
        t, res = {"other": [], "this": [], "mesh": []}, {}
        for _ in range(args.repeat):
            for key, mod in (("other", other), ("this", specks)):
                t0 = time.perf_counter()
                res[key] = mod.lost_feature(*a, **k)
                t[key].append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                mesh(part, progress=False, features=False, **kw)
            t["mesh"].append(time.perf_counter() - t0)
        o, n, m = (float(np.median(t[x])) for x in ("other", "this", "mesh"))

        def short(r):
            return None if r is None else (r.kind, r.count, getattr(r, "unexamined", 0))

        print(f"{name}: {found['cells'].shape[0]} BOUNDARY cells of 2h; plain mesh {m:.3f} s; detection "
              f"{args.against}: {o * 1e3:.1f} ms ({100 * o / m:.1f} %) {short(res['other'])}; this: "
              f"{n * 1e3:.1f} ms ({100 * n / m:.1f} %) {short(res['this'])}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
