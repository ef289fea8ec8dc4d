"""Mass properties on a Dask LocalCluster against one process: seconds and agreement, benchmark part.

Each N: the single-process `spatial.analysis.mass_properties(part, resolution=N)` and the cluster's
`spatial.mass_properties(part, resolution=N, client=...)` (two rounds of tasks per level: meshes and
their rim normals, then the moments), median wall seconds of `--repeat` runs, and the largest relative
difference over volume, area and the inertia tensor.
"""

import argparse
import statistics
import sys
import time


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[128])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--brick", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)

    import distributed
    import numpy as np

    sys.path.insert(0, "examples")
    from benchmark_part import model as make_part

    import spatial
    from spatial.analysis import mass_properties as single
    from spatial.distributed import local_cluster

    part = make_part()
    print("| N | one process s | cluster s | volume rel. diff | area rel. diff | inertia rel. diff |")
    print("| --- | --- | --- | --- | --- | --- |")
    with local_cluster(args.workers) as cluster, distributed.Client(cluster) as client:
        for n in args.sizes:
            t_one, t_cl = [], []
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                ref = single(part, resolution=n)
                t_one.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                out = spatial.mass_properties(part, resolution=n, client=client, brick=args.brick)
                t_cl.append(time.perf_counter() - t0)
            dv = abs(out.volume / ref.volume - 1)
            da = abs(out.area / ref.area - 1)
            di = float(np.abs(out.inertia - ref.inertia).max() / np.abs(ref.inertia).max())
            print(f"| {n} | {statistics.median(t_one):.2f} | {statistics.median(t_cl):.2f} | {dv:.1e} | "
                  f"{da:.1e} | {di:.1e} |", flush=True)


if __name__ == "__main__":
    main()
