"""Tetrahedral meshes of the benchmark part: implicad against gmsh at a similar tet count.

Run: ``.venv/bin/python bench/bench_fea.py [--repeat N] [--size H] [--threads T] [--beam]``.

The part is ``(sphere(1) & box(1.5)) - cylinder(0.5, 4)`` along x, y and z (volume
0.988789504774).  implicad meshes it with `tet_mesh` (surface remeshing, TetGen, sliver
smoothing and flips); gmsh meshes the same CSG built with its OpenCASCADE kernel, with
its HXT and Delaunay 3D algorithms, at a mesh size chosen to give about the same number
of tetrahedra.  Both meshes are then measured by gmsh itself (element qualities
``gamma`` and ``minSICN``) and by implicad's dihedral angles (slivers: elements with a
dihedral angle under 10 degrees).  Times are wall-clock (and CPU) medians of the runs, interleaved
(implicad: the whole `tet_mesh` from the CSG tree: surface, TetGen, smoothing and checks; gmsh:
`generate(3)` of the OCC model, 1D, 2D, 3D and its optimisation; both exclude building the model).
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
BEAM = box((100, 10, 10), center=(50, 0, 0))
BEAM_VOLUME = 1e4


def _gmsh():
    import gmsh

    if not gmsh.isInitialized():
        gmsh.initialize(["-nopopup"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    return gmsh


def gmsh_mesh(size, algorithm, threads, part="bench"):
    """The benchmark part (or the beam) meshed by gmsh: (points, tets 0-based, wall s, CPU s)."""
    gmsh = _gmsh()
    gmsh.clear()
    occ = gmsh.model.occ
    if part == "beam":
        occ.addBox(0, -5, -5, 100, 10, 10)
    else:
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
    t0, c0 = time.perf_counter(), time.process_time()
    gmsh.model.mesh.generate(3)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    tags, coords, _ = gmsh.model.mesh.getNodes()
    pts = coords.reshape(-1, 3)
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(tags.size)
    types, _, nodes = gmsh.model.mesh.getElements(3)
    tets = index[nodes[list(types).index(4)].astype(np.int64)].reshape(-1, 4)
    return pts, tets, seconds, cpu


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


def implicad_mesh(size, allow_poor=False, part="bench", estimate=False):
    """implicad's mesh: (points, tets, wall s, CPU s, stage wall seconds).

    With `estimate`, no reference volume is given, so `tet_mesh` measures the solid's volume
    for its volume check (on its feature meshes), as it does when a user calls it on a new part.
    """
    solid, volume = (BEAM, BEAM_VOLUME) if part == "beam" else (BENCH, VOLUME)
    t0, c0 = time.perf_counter(), time.process_time()
    m = tet_mesh(solid, size=size, reference_volume=None if estimate else volume, allow_poor=allow_poor)
    return m.points, m.tets, time.perf_counter() - t0, time.process_time() - c0, m.info["seconds"]


def beam(repeat, threads):
    """The beam 100 x 10 x 10 at sizes 10 and 5: implicad and gmsh HXT at the same size, medians."""
    print("beam 100 x 10 x 10, same size on both sides (tets differ), medians of "
          f"{repeat}: size, implicad tets / min dihedral / wall s / CPU s, gmsh HXT tets / wall s / CPU s")
    for size in (10.0, 5.0):
        implicad_mesh(size, part="beam")
        gmsh_mesh(size, "hxt", threads, part="beam")
        mine, theirs = [], []
        for _ in range(repeat):
            mine.append(implicad_mesh(size, part="beam"))
            theirs.append(gmsh_mesh(size, "hxt", threads, part="beam"))
        dmin = dihedral_angles(mine[-1][0], mine[-1][1]).min()
        print(f"  {size:g}: implicad {len(mine[-1][1])} tets, {dmin:.2f} deg, "
              f"{np.median([r[2] for r in mine]):.3f} s / {np.median([r[3] for r in mine]):.3f} s CPU; "
              f"gmsh {len(theirs[-1][1])} tets, {np.median([r[2] for r in theirs]):.3f} s / "
              f"{np.median([r[3] for r in theirs]):.3f} s CPU")


def main(argv=None):
    warnings.simplefilter("ignore")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--size", type=float, default=0.08, help="implicad target edge length")
    ap.add_argument("--threads", type=int, default=1, help="gmsh threads (1: the same as implicad)")
    ap.add_argument("--beam", action="store_true", help="also the beam 100 x 10 x 10 at sizes 10 and 5")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()[0]
    implicad_mesh(0.2, allow_poor=True)  # warm-up: compiling the field evaluator and kernels
    pts, tets, *_ = implicad_mesh(args.size)
    # gmsh's size for the same tet count: one probe (also its warm-up), then the cube-root rule.
    _, probe, _, _ = gmsh_mesh(args.size, "hxt", args.threads)
    gsize = args.size * (len(probe) / len(tets)) ** (1.0 / 3.0)
    # The runs interleaved, so a change of the machine's load falls on every mesher alike.
    runs = {"implicad": [], "hxt": [], "delaunay": []}
    estimated = []
    for _ in range(args.repeat):
        runs["implicad"].append(implicad_mesh(args.size))
        estimated.append(implicad_mesh(args.size, estimate=True)[2:4])
        for algorithm in ("hxt", "delaunay"):
            runs[algorithm].append(gmsh_mesh(gsize, algorithm, args.threads))
    load1 = os.getloadavg()[0]
    median = {k: float(np.median([r[2] for r in v])) for k, v in runs.items()}
    cpu = {k: float(np.median([r[3] for r in v])) for k, v in runs.items()}
    rows = {f"implicad size {args.size:g}": (measures(*runs["implicad"][-1][:2]), median["implicad"])}
    for algorithm in ("hxt", "delaunay"):
        rows[f"gmsh {algorithm} size {gsize:.4g}"] = (measures(*runs[algorithm][-1][:2]), median[algorithm])
    keys = ["tets", "gamma min", "gamma p1", "SICN min", "SICN p1", "slivers <10", "min dih", "vol err %"]
    print(f"benchmark part, median of {args.repeat} interleaved runs, gmsh threads {args.threads}, "
          f"load average {load0:.1f} -> {load1:.1f}")
    print(f"{'mesher':<26}" + "".join(f"{k:>12}" for k in keys) + f"{'time s':>9}{'CPU s':>9}")
    for (name, (m, t)), c in zip(rows.items(), cpu.values()):
        cells = "".join(f"{m[k]:>12d}" if isinstance(m[k], int) else f"{m[k]:>12.4f}" for k in keys)
        print(f"{name:<26}{cells}{t:>9.2f}{c:>9.2f}")
    stages = {k: float(np.median([r[4][k] for r in runs["implicad"]])) for k in runs["implicad"][0][4]}
    print("implicad stages (median s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
    mine = rows[f"implicad size {args.size:g}"]
    hxt = rows[f"gmsh hxt size {gsize:.4g}"]
    print(f"targets: min gamma >= 0.25: {'met' if mine[0]['gamma min'] >= 0.25 else 'MISSED'} "
          f"({mine[0]['gamma min']:.3f}); time within 2x of HXT: "
          f"{'met' if mine[1] <= 2 * hxt[1] else 'MISSED'} ({mine[1] / max(hxt[1], 1e-9):.2f}x wall, "
          f"{cpu['implicad'] / max(cpu['hxt'], 1e-9):.2f}x CPU)")
    wall_e, cpu_e = (float(np.median(col)) for col in zip(*estimated))
    print(f"implicad without a reference volume (the solid's volume measured for the volume check): "
          f"{wall_e:.2f} s wall, {cpu_e:.2f} s CPU: {wall_e / max(hxt[1], 1e-9):.2f}x / "
          f"{cpu_e / max(cpu['hxt'], 1e-9):.2f}x of HXT")
    if args.beam:
        beam(args.repeat, args.threads)


if __name__ == "__main__":
    main()
