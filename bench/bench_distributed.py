"""Benchmark: the benchmark part meshed brick by brick on a Dask LocalCluster, parts written to disk.

One fresh `LocalCluster` (worker processes, one thread each, loopback, no
dashboard) per N, so that each worker's peak resident memory belongs to that
N alone.  The mesh is written as .vtp parts under a .pvtp index (nothing
gathered on the client).  Prints per N: wall seconds, triangles, parts, disk
MB, peak MB of each worker and of the client, and the per-brick costs (CPU
seconds, triangles, boundary cells, write seconds: median and max) from which
larger runs are planned.

    .venv/bin/python bench/bench_distributed.py [--sizes 512 2048] [--workers 2] [--brick 256] [--keep DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)


def part():
    from implicit import box, cylinder, sphere

    return (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))


def run_one(n, workers, brick, folder):
    import distributed

    from spatial.distributed import local_cluster, mesh
    from spatial.distributed.worker import peak_rss, solid_from_json
    from implicit.serialize import to_json

    solid = part()
    with local_cluster(workers) as cluster, distributed.Client(cluster) as client:
        text = to_json(solid)
        # the solid and its compiled evaluator, outside the timing (each worker's first task imports the meshing)
        client.run(lambda t: solid_from_json(t) is not None, text)
        base = client.run(peak_rss)
        t0 = time.perf_counter()
        out = mesh(solid, resolution=n, client=client, brick=brick, parts=os.path.join(folder, f"part_{n}.pvtp"),
                   progress=False)
        wall = time.perf_counter() - t0
        peaks = client.run(peak_rss)
    bricks = [b for b in out.bricks if b["triangles"]]
    disk = sum(os.path.getsize(p) for p in out.parts)

    def stats(key):
        vals = [b[key] for b in bricks]
        return dict(median=statistics.median(vals), max=max(vals), total=sum(vals))

    return dict(n=n, workers=workers, brick=brick, wall=wall, triangles=out.triangles, parts=len(out.parts),
                tasks=len(out.bricks), disk_mb=disk / 2 ** 20, evaluations=out.evaluations,
                worker_peak_mb=sorted(v / 2 ** 20 for v in peaks.values()),
                worker_base_mb=sorted(v / 2 ** 20 for v in base.values()),
                client_peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
                cpu=stats("cpu_seconds"), mesh_seconds=stats("seconds"), write=stats("write_seconds"),
                tri=stats("triangles"), cells=stats("boundary_cells"), write_cpu=stats("write_cpu_seconds"))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 2048])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--brick", type=int, default=256)
    parser.add_argument("--keep", metavar="DIR", help="write the parts here and keep them")
    args = parser.parse_args(argv)
    print("| N | workers | brick | wall s | triangles | tasks | disk MB | peak MB per worker | client MB | "
          "CPU s per brick (median / max / total) | triangles per brick (median / max) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for n in args.sizes:
        folder = args.keep or tempfile.mkdtemp(prefix=f"bench_distributed_{n}_")
        os.makedirs(folder, exist_ok=True)
        try:
            r = run_one(n, args.workers, args.brick, folder)
        finally:
            if not args.keep:
                shutil.rmtree(folder, ignore_errors=True)
        print(json.dumps(r), file=sys.stderr)
        print(f"| {n} | {r['workers']} | {r['brick']} | {r['wall']:.1f} | {r['triangles']:,} | {r['tasks']} | "
              f"{r['disk_mb']:.0f} | {' / '.join(f'{v:.0f}' for v in r['worker_peak_mb'])} | "
              f"{r['client_peak_mb']:.0f} | {r['cpu']['median']:.2f} / {r['cpu']['max']:.2f} / "
              f"{r['cpu']['total']:.0f} | {r['tri']['median']:,.0f} / {r['tri']['max']:,} |", flush=True)


if __name__ == "__main__":
    main()
