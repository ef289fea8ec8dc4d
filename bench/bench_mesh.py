"""Benchmark: boundary mesh of the benchmark part at N = 128 ... 1024 cells across.

Each size runs in its own subprocess so that the peak resident memory
(``resource.getrusage(RUSAGE_SELF).ru_maxrss``) belongs to that size alone.
Prints one table row per N: wall and processor seconds (medians of the runs;
processor time is the fairer figure on a shared machine), distance
evaluations (boxes bounded + points sampled), peak MB (imports and the
compiled evaluator take about 280 MB before meshing starts), triangles and
checks.

Targets: N=512 in <= 3 s and 500 MB, N=1024 in <= 15 s and 1.5 GB, at most 6
million evaluations at N=512 growing <= 4.5x per doubling.

    .venv/bin/python bench/bench_mesh.py [--sizes 128 256 512 1024] [--repeat 3] [--no-refine]

With ``--features`` each size is meshed with and without the feature pass
(`mesh(..., features=True)`) and the table gives both times, their ratio, the
triangle ratio and both volume errors; ``--edges N`` then measures, at N
cells across, the distance from points of the exact CSG edges and corners
(`bench/feature_truth.py`) to both meshes of the benchmark part, an L
bracket, a stepped shaft with a keyway and a box with pockets, in voxels:

    .venv/bin/python bench/bench_mesh.py --features --sizes 256 512 --edges 128

Whole process (`bench/whole_process.py`): with ``--sdf-python PATH`` each size
is also run as a user meets it -- a fresh interpreter that imports and meshes
the part once, nothing warmed -- interleaved run by run with fogleman/sdf
meshing the same part at the same step h = 1.6/N from that Python; the table
gives wall, CPU and peak MB of both whole processes, their ratios, and both
in-process meshing times.  Without a usable sdf the comparison is skipped with
a message.  ``--command N`` times ``implicad mesh examples/benchmark_part.py
-o part.stl --resolution N`` as a whole command:

    .venv/bin/python bench/bench_mesh.py --sizes 256 512 --repeat 5 --sdf-python /tmp/sdfvenv/bin/python
    .venv/bin/python bench/bench_mesh.py --sizes --command 256 --repeat 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, {root!r})
from implicit import box, cylinder, sphere
from spatial import mesh
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
import numpy, pyvista, skimage.measure  # imports outside the timing
part(numpy.zeros((200000, 3)))  # warm any compiled evaluation path outside the timing
t0 = time.perf_counter()
c0 = time.process_time()
m = mesh(part, resolution={n}, refine={refine}, progress=False, features={features})
wall = time.perf_counter() - t0
cpu = time.process_time() - c0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
out = dict(wall=wall, cpu=cpu, peak=peak, evaluations=int(m.field_data["evaluations"][0]), triangles=m.n_cells,
           vertices=m.n_points, volume=float(m.volume), manifold=bool(m.is_manifold),
           euler=int(m.n_points - m.extract_all_edges().n_cells + m.n_cells) if {n} <= 256 else None)
print(json.dumps(out))
"""


def run_one(n, refine, features=False):
    code = CHILD.format(root=ROOT, n=n, refine=refine, features=features)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[128, 256, 512, 1024])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-refine", action="store_true")
    parser.add_argument("--features", action="store_true", help="compare with mesh(..., features=True)")
    parser.add_argument("--edges", type=int, default=0, help="edge and corner distances at this N")
    parser.add_argument("--sdf-python", default=None, metavar="PATH",
                        help="a Python that imports fogleman/sdf: whole-process comparison with it")
    parser.add_argument("--command", type=int, default=0, metavar="N",
                        help="time `implicad mesh examples/benchmark_part.py --resolution N` as a whole command")
    args = parser.parse_args(argv)
    refine = not args.no_refine
    if args.features:
        return compare_features(args.sizes, args.repeat, refine, args.edges)
    if args.sizes:
        in_process(args.sizes, args.repeat, refine)
        whole_process_table(args.sizes, args.repeat, args.sdf_python)
    if args.command:
        command_table(args.command, args.repeat)
    return 0


def in_process(sizes, repeat, refine):
    print(f"in process: benchmark part, spatial.mesh(refine={refine}) after a warm-up evaluation; "
          f"median of {repeat} runs, one process each")
    print(f"{'N':>6} {'wall s':>8} {'cpu s':>7} {'evaluations':>12} {'peak MB':>8} {'triangles':>10} {'volume':>11} manifold")
    prev = None
    for n in sizes:
        runs = [run_one(n, refine) for _ in range(repeat)]
        wall = statistics.median(r["wall"] for r in runs)
        cpu = statistics.median(r["cpu"] for r in runs)
        peak = max(r["peak"] for r in runs)
        r = runs[0]
        growth = f"  (x{r['evaluations'] / prev:.2f})" if prev else ""
        prev = r["evaluations"]
        print(f"{n:>6} {wall:>8.2f} {cpu:>7.2f} {r['evaluations']:>12,d} {peak:>8.0f} {r['triangles']:>10,d} "
              f"{r['volume']:>11.8f} {'yes' if r['manifold'] else 'NO'}{growth}", flush=True)
    print(f"exact volume {EXACT_VOLUME}")


def whole_process_table(sizes, repeat, sdf_python):
    """Whole processes of implicad and fogleman/sdf, interleaved run by run; medians and their ratios."""
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import whole_process as wp

    why = wp.sdf_usable(sdf_python)
    if why:
        print(f"\nwhole process vs fogleman/sdf: skipped ({why}; give --sdf-python PATH)")
    title = "implicad" if why else "implicad vs fogleman/sdf, interleaved"
    print(f"\nwhole process (fresh interpreter: imports + one mesh, h = 1.6/N), {title}; median of {repeat}")
    head = f"{'N':>6} {'wall s':>7} {'cpu s':>6} {'peak MB':>7} {'mesh s':>6}"
    if not why:
        head += f" | {'sdf wall':>8} {'cpu':>6} {'peak':>6} {'mesh':>6} | {'wall x':>6} {'cpu x':>6} {'peak x':>6}" \
                f" {'mesh x':>6} | {'sdf tri':>9} {'sdf vol':>8}"
    print(head)
    med = statistics.median
    for n in sizes:
        ours, peer = [], []
        for _ in range(repeat):
            ours.append(wp.implicad_run(sys.executable, n))
            if not why:
                peer.append(wp.sdf_run(sdf_python, n))
        row = [med(r[k] for r in ours) for k in ("wall", "cpu", "peak", "mesh")]
        line = f"{n:>6} {row[0]:>7.2f} {row[1]:>6.2f} {row[2]:>7.0f} {row[3]:>6.2f}"
        if not why:
            other = [med(r[k] for r in peer) for k in ("wall", "cpu", "peak", "mesh")]
            ratio = [a / b for a, b in zip(row, other)]
            line += f" | {other[0]:>8.2f} {other[1]:>6.2f} {other[2]:>6.0f} {other[3]:>6.2f} | " \
                    + " ".join(f"{r:>6.3f}" for r in ratio) \
                    + f" | {peer[0]['triangles']:>9,d} {peer[0]['volume']:>8.5f}"
        print(line, flush=True)


def command_table(n, repeat):
    """`implicad mesh examples/benchmark_part.py -o part.stl --resolution n`, whole command, median."""
    import tempfile

    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import whole_process as wp

    implicad = os.path.join(os.path.dirname(sys.executable), "implicad")
    with tempfile.TemporaryDirectory() as tmp:
        runs = [wp.command_run(implicad, n, os.path.join(tmp, "part.stl")) for _ in range(repeat)]
    med = statistics.median
    print(f"\n`implicad mesh examples/benchmark_part.py -o part.stl --resolution {n}`, whole command, "
          f"median of {repeat}: wall {med(r['wall'] for r in runs):.2f} s, cpu {med(r['cpu'] for r in runs):.2f} s, "
          f"peak {med(r['peak'] for r in runs):.0f} MB (first run {runs[0]['wall']:.2f} s wall)")


EXACT_VOLUME = 0.988789504774


def compare_features(sizes, repeat, refine, edges_n):
    print(f"benchmark part, spatial.mesh with and without features; median of {repeat} runs, one process each")
    print(f"{'N':>6} {'plain s':>8} {'feat s':>8} {'ratio':>6} {'tri ratio':>9} {'vol err plain':>14} "
          f"{'vol err feat':>13}")
    for n in sizes:
        plain = [run_one(n, refine) for _ in range(repeat)]
        feat = [run_one(n, refine, True) for _ in range(repeat)]
        wp = statistics.median(r["wall"] for r in plain)
        wf = statistics.median(r["wall"] for r in feat)
        print(f"{n:>6} {wp:>8.2f} {wf:>8.2f} {wf / wp:>6.2f} {feat[0]['triangles'] / plain[0]['triangles']:>9.3f} "
              f"{plain[0]['volume'] - EXACT_VOLUME:>14.2e} {feat[0]['volume'] - EXACT_VOLUME:>13.2e}", flush=True)
    if edges_n:
        edge_table(edges_n)
    return 0


def edge_parts():
    from implicit import box, cylinder, sphere
    from implicit.families import instance

    bench = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))
    bracket = instance("l_bracket", width=30.0, leg_a=50.0, leg_b=40.0, thickness=4.0, hole_diameter=6.0,
                       holes_per_leg=2)
    shaft = (cylinder(0.5, 1.2, center=(0, 0, -0.6)) | cylinder(0.35, 1.0, center=(0, 0, 0.5))) \
        - box((0.2, 0.3, 0.6), center=(0.0, 0.3, 0.45))
    pockets = box((2.0, 1.4, 0.6)) - box((0.6, 0.5, 0.4), center=(-0.5, 0.0, 0.2)) \
        - box((0.5, 0.8, 0.3), center=(0.5, 0.1, 0.25)) - cylinder(0.15, 1.0, center=(0.0, -0.45, 0.0))
    return [("benchmark part", bench), ("L bracket", bracket), ("stepped shaft + keyway", shaft),
            ("box with pockets", pockets)]


def edge_table(n):
    import numpy as np

    sys.path.insert(0, ROOT)
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    from feature_truth import distances, exact_features
    from spatial import mesh

    print(f"\ndistances to the mesh at N={n}, in voxels h (exact edges sampled from a mesh at 2N)")
    print(f"{'part':<24} {'edge pts':>8} {'plain max':>9} {'feat max':>8} {'feat p99':>8} {'feat med':>8} "
          f"{'corners':>7} {'plain max':>9} {'feat max':>8}")
    for name, part in edge_parts():
        edges, _, corners, _, _ = exact_features(part, resolution=2 * n)
        row = [f"{name:<24} {edges.shape[0]:>8d}"]
        res = {}
        for feat in (False, True):
            m = mesh(part, resolution=n, features=feat, progress=False)
            h = float(m.field_data["voxel_size"][0])
            res[feat] = (distances(m, edges) / h, distances(m, corners) / h)
        de0, dc0 = res[False]
        de1, dc1 = res[True]
        row.append(f"{de0.max():>9.3f} {de1.max():>8.3f} {np.percentile(de1, 99):>8.3f} {np.median(de1):>8.4f}")
        cmax = (lambda d: f"{d.max():.3f}" if d.size else "-")
        row.append(f"{corners.shape[0]:>7d} {cmax(dc0):>9} {cmax(dc1):>8}")
        print(" ".join(row), flush=True)


if __name__ == "__main__":
    sys.exit(main())
