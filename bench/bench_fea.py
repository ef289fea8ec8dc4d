"""Tetrahedral meshes of the benchmark part: implicad against gmsh at a similar tet count.

Run: ``.venv/bin/python bench/bench_fea.py [--repeat N] [--size H] [--threads T]``.

The part is ``(sphere(1) & box(1.5)) - cylinder(0.5, 4)`` along x, y and z (volume
0.988789504774).  implicad meshes it with `tet_mesh` (surface remeshing, TetGen, sliver
smoothing and flips); gmsh meshes the same CSG built with its OpenCASCADE kernel, with
its HXT and Delaunay 3D algorithms, at a mesh size chosen to give about the same number
of tetrahedra.  Both meshes are then measured by gmsh itself (element qualities
``gamma`` and ``minSICN``) and by implicad's dihedral angles (slivers: elements with a
dihedral angle under 10 degrees).  Times are wall-clock medians of the runs (implicad:
surface plus tetrahedra; gmsh: 3D generation of the OCC model, 1D/2D included).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from implicit import box, cylinder, sphere  # noqa: E402
from spatial.fea import tet_mesh, write_fea  # noqa: E402
from spatial.fea.quality import dihedral_angles, tet_volumes  # noqa: E402

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
VOLUME = 0.988789504774


def _gmsh():
    import gmsh

    if not gmsh.isInitialized():
        gmsh.initialize(["-nopopup"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    return gmsh


def gmsh_mesh(size, algorithm, threads):
    """The benchmark part meshed by gmsh: (points, tets 0-based, seconds)."""
    gmsh = _gmsh()
    gmsh.clear()
    occ = gmsh.model.occ
    ball = occ.addSphere(0, 0, 0, 1.0)
    cube = occ.addBox(-0.75, -0.75, -0.75, 1.5, 1.5, 1.5)
    body, _ = occ.intersect([(3, ball)], [(3, cube)])
    tools = [(3, occ.addCylinder(-2, 0, 0, 4, 0, 0, 0.5)), (3, occ.addCylinder(0, -2, 0, 0, 4, 0, 0.5)),
             (3, occ.addCylinder(0, 0, -2, 0, 0, 4, 0.5))]
    occ.cut(body, tools)
    occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", {"hxt": 10, "delaunay": 1}[algorithm])
    gmsh.option.setNumber("General.NumThreads", threads)
    gmsh.option.setNumber("Mesh.MaxNumThreads3D", threads)
    t0 = time.perf_counter()
    gmsh.model.mesh.generate(3)
    seconds = time.perf_counter() - t0
    tags, coords, _ = gmsh.model.mesh.getNodes()
    pts = coords.reshape(-1, 3)
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(tags.size)
    types, _, nodes = gmsh.model.mesh.getElements(3)
    tets = index[nodes[list(types).index(4)].astype(np.int64)].reshape(-1, 4)
    return pts, tets, seconds


def gmsh_qualities(points, tets):
    """gmsh's gamma and minSICN of a linear tet mesh (written as .msh and opened by gmsh)."""
    gmsh = _gmsh()
    gmsh.clear()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "m.msh")
        import meshio

        meshio.write(path, meshio.Mesh(points, [("tetra", tets)]), file_format="gmsh22", binary=False)
        gmsh.open(path)
    _, tags, _ = gmsh.model.mesh.getElements(3)
    return (gmsh.model.mesh.getElementQualities(tags[0], "gamma"),
            gmsh.model.mesh.getElementQualities(tags[0], "minSICN"))


def measures(points, tets):
    gamma, sicn = gmsh_qualities(points, tets)
    dmin = dihedral_angles(points, tets).min(axis=1)
    vol = float(tet_volumes(points, tets).sum())
    return {"tets": len(tets), "gamma min": gamma.min(), "gamma p1": np.percentile(gamma, 1),
            "SICN min": sicn.min(), "SICN p1": np.percentile(sicn, 1), "slivers <10": int((dmin < 10).sum()),
            "min dih": dmin.min(), "vol err %": 100 * abs(vol - VOLUME) / VOLUME}


def implicad_mesh(size, allow_poor=False):
    t0 = time.perf_counter()
    m = tet_mesh(BENCH, size=size, reference_volume=VOLUME, allow_poor=allow_poor)
    return m.points, m.tets, time.perf_counter() - t0


def main(argv=None):
    warnings.simplefilter("ignore")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--size", type=float, default=0.08, help="implicad target edge length")
    ap.add_argument("--threads", type=int, default=1, help="gmsh threads (1: the same as implicad)")
    args = ap.parse_args(argv)
    implicad_mesh(0.2, allow_poor=True)  # warm-up: compiling the field evaluator and kernels
    runs = [implicad_mesh(args.size) for _ in range(args.repeat)]
    pts, tets, _ = runs[-1]
    rows = {f"implicad size {args.size:g}": (measures(pts, tets), float(np.median([r[2] for r in runs])))}
    # gmsh's size for the same tet count: one probe, then the cube-root rule.
    _, probe, _ = gmsh_mesh(args.size, "hxt", args.threads)
    gsize = args.size * (len(probe) / len(tets)) ** (1.0 / 3.0)
    for algorithm in ("hxt", "delaunay"):
        g = [gmsh_mesh(gsize, algorithm, args.threads) for _ in range(args.repeat)]
        rows[f"gmsh {algorithm} size {gsize:.4g}"] = (measures(g[-1][0], g[-1][1]), float(np.median([r[2] for r in g])))
    keys = ["tets", "gamma min", "gamma p1", "SICN min", "SICN p1", "slivers <10", "min dih", "vol err %"]
    print(f"benchmark part, median of {args.repeat} runs, gmsh threads {args.threads}")
    print(f"{'mesher':<26}" + "".join(f"{k:>12}" for k in keys) + f"{'time s':>9}")
    for name, (m, t) in rows.items():
        cells = "".join(f"{m[k]:>12d}" if isinstance(m[k], int) else f"{m[k]:>12.4f}" for k in keys)
        print(f"{name:<26}{cells}{t:>9.2f}")
    mine = rows[f"implicad size {args.size:g}"]
    hxt = rows[f"gmsh hxt size {gsize:.4g}"]
    print(f"targets: min gamma >= 0.25: {'met' if mine[0]['gamma min'] >= 0.25 else 'MISSED'} "
          f"({mine[0]['gamma min']:.3f}); time within 2x of HXT: "
          f"{'met' if mine[1] <= 2 * hxt[1] else 'MISSED'} ({mine[1] / max(hxt[1], 1e-9):.1f}x)")


if __name__ == "__main__":
    main()
