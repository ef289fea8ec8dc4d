"""The gear of examples/gear.py at sizes coarser than its tooth gap (graded size field), order 1.

    nice .venv/bin/python bench/bench_gear_sizes.py 3 5

Prints per size: elements, nodes, surface points and the size the surface was remeshed at, smallest
dihedral angle and elements under 10 degrees, largest radius-edge ratio, whether the mesh meets
`tet_mesh`'s default quality (10 degrees, radius-edge 3), volume error against mass properties,
tooth-tip corners that are nodes (of 80), the mesh the surface was clustered from and the rounds of
local caps of its size field where the surface crosses itself and where elements missed the quality
(`spatial.fea.graded_surface`), wall and CPU seconds.
"""

import os
import runpy
import sys
import time
import warnings

import numpy as np

from spatial.fea import tet_mesh

GEAR = os.path.join(os.path.dirname(__file__), "..", "examples", "gear.py")


def main(sizes):
    ns = runpy.run_path(GEAR)
    outline = ns["gear_outline"]()
    tips = outline[np.isclose(np.hypot(*outline.T), ns["MODULE"] * (ns["TEETH"] / 2 + 1))]
    corners = np.concatenate([np.column_stack([tips, np.full(len(tips), z)]) for z in (0.0, ns["FACE_WIDTH"])])
    print("| size | elements | nodes | surface points (at size) | min dihedral | under 10 deg | max radius-edge | "
          "default quality | volume error % | tip corners as nodes | start (local caps, quality caps) | wall / CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for size in sizes:
        t, c = time.perf_counter(), time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = tet_mesh(ns["solid"], size=size, allow_poor=True)
        sec, cpu = time.perf_counter() - t, time.process_time() - c
        q = m.quality
        bn = m.points[np.unique(m.boundary)]
        hit = int((np.linalg.norm(corners[:, None] - bn[None], axis=2).min(axis=1) < 1e-6).sum())
        ok = "met" if not m.info["problems"] else "missed"
        print(f"| {size:g} | {q.n_elements:,} | {q.n_nodes:,} | {m.info['surface_points']:,} ({m.info['surface_size']:g}) | "
              f"{q.min_dihedral:.2f} | {q.n_below} | {q.max_radius_edge:.2f} | {ok} | {100 * m.info['volume_error']:.2f} | "
              f"{hit} of {len(corners)} | {m.info.get('surface_start', '-')} ({m.info.get('local_caps', '-')}, {m.info.get('quality_caps', '-')}) | "
              f"{sec:.0f} / {cpu:.0f} |", flush=True)


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [3.0, 5.0])
