"""Tetrahedral meshes of the benchmark part: implicad against gmsh at a similar tet count.

Run: ``.venv/bin/python bench/bench_fea.py [--repeat N] [--size H] [--threads T] [--beam]
[--tree NAME=PATH ...]``.

The part is ``(sphere(1) & box(1.5)) - cylinder(0.5, 4)`` along x, y and z (volume
0.988789504774).  implicad meshes it with `tet_mesh` (surface remeshing, TetGen, sliver
smoothing and flips); gmsh meshes the same CSG built with its OpenCASCADE kernel, with
its HXT and Delaunay 3D algorithms, at a mesh size chosen to give about the same number
of tetrahedra.  Both meshes are then measured by gmsh itself (element qualities
``gamma`` and ``minSICN``) and by implicad's dihedral angles (slivers: elements with a
dihedral angle under 10 degrees).  Times are wall-clock (and CPU) medians of the runs, interleaved
(implicad: the whole `tet_mesh` from the CSG tree: surface, TetGen, smoothing and checks; gmsh:
`generate(3)` of the OCC model, 1D, 2D, 3D and its optimisation; both exclude building the model).

gmsh's size is searched so that HXT's tet count matches implicad's within `MATCH` (the cube-root
rule from probes): the time target is read at the matched count.  HXT is also run at the size one
probe gives (the rule the earlier figures used: 17,244 tets against 19,070), printed beside it.
With ``--tree NAME=PATH`` (repeatable) implicad runs in one child process per tree, each with
that tree's ``.venv`` and code, the trees' runs and gmsh's interleaved run by run.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings

import numpy as np

if "--worker" in sys.argv:  # a child process for one tree (`--tree`): that tree's code first
    sys.path.insert(0, os.path.abspath(sys.argv[sys.argv.index("--worker") + 1]))
else:
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


#: Largest relative difference of HXT's tet count from implicad's at the matched size.
MATCH = 0.01


def matched_size(size, target, threads, probes=5):
    """gmsh's size whose HXT mesh has `target` tets within `MATCH` (cube-root rule from each probe):
    (the one-probe size, the matched size, its count)."""
    gsize = size
    first = None
    for _ in range(probes):
        count = len(gmsh_mesh(gsize, "hxt", threads)[1])
        if first is None:
            first = gsize * (count / target) ** (1.0 / 3.0)
        if abs(count - target) <= MATCH * target:
            break
        gsize *= (count / target) ** (1.0 / 3.0)
    return first, gsize, count


def worker():
    """Child process of one tree: JSON requests on stdin, one JSON answer a line on stdout."""
    import hashlib
    import json

    warnings.simplefilter("ignore")
    sys.stdout.flush()
    out = os.fdopen(os.dup(1), "w")  # only the answers on the pipe: whatever else prints goes to stderr
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    for line in sys.stdin:
        req = json.loads(line)
        pts, tets, wall, cpu, stages = implicad_mesh(req["size"], allow_poor=req.get("allow_poor", False),
                                                     estimate=req.get("estimate", False))
        digest = hashlib.sha256(np.ascontiguousarray(pts).tobytes() + np.ascontiguousarray(tets).tobytes())
        if req.get("save"):
            np.savez(req["save"], points=pts, tets=tets)
        out.write(json.dumps({"wall": wall, "cpu": cpu, "stages": stages, "tets": int(len(tets)),
                              "sha": digest.hexdigest()[:16]}) + "\n")
        out.flush()


class Tree:
    """implicad of another tree, in a child process with that tree's environment (`worker`)."""

    def __init__(self, root):
        import subprocess

        root = os.path.abspath(root)
        python = os.path.join(root, ".venv", "bin", "python")
        self.proc = subprocess.Popen([python, os.path.abspath(__file__), "--worker", root], cwd=root,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        self.tmp = tempfile.mkdtemp(prefix="bench-fea-")

    def mesh(self, size, allow_poor=False, estimate=False, keep=False):
        """As `implicad_mesh` (the points and tets only with `keep`, else None), and the mesh's SHA-256."""
        import json

        save = os.path.join(self.tmp, "m.npz") if keep else None
        self.proc.stdin.write(json.dumps({"size": size, "allow_poor": allow_poor, "estimate": estimate,
                                          "save": save}) + "\n")
        self.proc.stdin.flush()
        r = json.loads(self.proc.stdout.readline())
        pts = tets = None
        if keep:
            with np.load(save) as z:
                pts, tets = z["points"], z["tets"]
        return pts, tets, r["wall"], r["cpu"], r["stages"], r["sha"]

    def close(self):
        self.proc.stdin.close()
        self.proc.wait()


class Here(Tree):
    """implicad of this tree, in this process."""

    def __init__(self):
        pass

    def mesh(self, size, allow_poor=False, estimate=False, keep=False):
        import hashlib

        pts, tets, wall, cpu, stages = implicad_mesh(size, allow_poor=allow_poor, estimate=estimate)
        digest = hashlib.sha256(np.ascontiguousarray(pts).tobytes() + np.ascontiguousarray(tets).tobytes())
        return pts, tets, wall, cpu, stages, digest.hexdigest()[:16]

    def close(self):
        pass


def main(argv=None):
    warnings.simplefilter("ignore")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--size", type=float, default=0.08, help="implicad target edge length")
    ap.add_argument("--threads", type=int, default=1, help="gmsh threads (1: the same as implicad)")
    ap.add_argument("--beam", action="store_true", help="also the beam 100 x 10 x 10 at sizes 10 and 5")
    ap.add_argument("--tree", action="append", metavar="NAME=PATH",
                    help="implicad of the tree at PATH (its .venv) in a child process; repeatable")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()[0]
    trees = {"implicad": Here()} if not args.tree else {n: Tree(p) for n, p in (t.split("=", 1) for t in args.tree)}
    first = next(iter(trees.values()))
    for tree in trees.values():
        tree.mesh(0.2, allow_poor=True)  # warm-up: compiling the field evaluator and kernels
    pts, tets, *_ = first.mesh(args.size, keep=True)
    # gmsh's size for the same tet count (the probes are also its warm-up)
    gprobe, gsize, gcount = matched_size(args.size, len(tets), args.threads)
    # The runs interleaved, so a change of the machine's load falls on every mesher alike.
    mine = {n: {"ref": [], "est": []} for n in trees}
    runs = {"hxt": [], "hxt one probe": [], "delaunay": []}
    for k in range(args.repeat):
        last = k == args.repeat - 1
        for name, tree in trees.items():
            mine[name]["ref"].append(tree.mesh(args.size, keep=last))
            mine[name]["est"].append(tree.mesh(args.size, estimate=True))
        runs["hxt"].append(gmsh_mesh(gsize, "hxt", args.threads))
        runs["hxt one probe"].append(gmsh_mesh(gprobe, "hxt", args.threads))
        runs["delaunay"].append(gmsh_mesh(gsize, "delaunay", args.threads))
    load1 = os.getloadavg()[0]
    med = lambda rows, i: float(np.median([r[i] for r in rows]))  # noqa: E731
    rows = {}
    for name in trees:
        r = mine[name]["ref"]
        rows[f"{name} size {args.size:g}"] = (measures(*r[-1][:2]), med(r, 2), med(r, 3))
    sizes = {"hxt": gsize, "hxt one probe": gprobe, "delaunay": gsize}
    for algorithm, r in runs.items():
        label = f"gmsh {algorithm.split()[0]} size {sizes[algorithm]:.4g}"
        rows[label] = (measures(*r[-1][:2]), med(r, 2), med(r, 3))
    keys = ["tets", "gamma min", "gamma p1", "SICN min", "SICN p1", "slivers <10", "min dih", "vol err %"]
    print(f"benchmark part, median of {args.repeat} interleaved runs, gmsh threads {args.threads}, "
          f"load average {load0:.1f} -> {load1:.1f}")
    print(f"{'mesher':<26}" + "".join(f"{k:>12}" for k in keys) + f"{'time s':>9}{'CPU s':>9}")
    for name, (m, t, c) in rows.items():
        cells = "".join(f"{m[k]:>12d}" if isinstance(m[k], int) else f"{m[k]:>12.4f}" for k in keys)
        print(f"{name:<26}{cells}{t:>9.2f}{c:>9.2f}")
    hxt = (med(runs["hxt"], 2), med(runs["hxt"], 3))
    probe = (med(runs["hxt one probe"], 2), med(runs["hxt one probe"], 3))
    print(f"HXT at the matched count: {len(runs['hxt'][-1][1])} tets (implicad {len(tets)}, within {MATCH:.0%}: "
          f"{'yes' if abs(len(runs['hxt'][-1][1]) - len(tets)) <= MATCH * len(tets) else 'NO'}); at the one-probe "
          f"size {gprobe:.4g}: {len(runs['hxt one probe'][-1][1])} tets")
    for name in trees:
        ref, est = mine[name]["ref"], mine[name]["est"]
        stages = {k: float(np.median([r[4][k] for r in ref])) for k in ref[0][4]}
        print(f"{name} stages (median s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items())
              + f"; mesh SHA-256 {ref[-1][5]} (without a reference volume {est[-1][5]})")
        gamma = rows[f"{name} size {args.size:g}"][0]["gamma min"]
        for line, r in (("with the reference volume", ref),
                        ("without it (the solid's volume measured for the check, as a user calls it)", est)):
            w, c = med(r, 2), med(r, 3)
            print(f"  {line}: {w:.3f} s wall, {c:.3f} s CPU; to HXT at the matched count "
                  f"{w / max(hxt[0], 1e-9):.2f}x wall, {c / max(hxt[1], 1e-9):.2f}x CPU (target 2x: "
                  f"{'met' if w <= 2 * hxt[0] else 'MISSED'}); at the one-probe size {w / max(probe[0], 1e-9):.2f}x / "
                  f"{c / max(probe[1], 1e-9):.2f}x")
        print(f"  min gamma >= 0.25: {'met' if gamma >= 0.25 else 'MISSED'} ({gamma:.4f})")
    for tree in trees.values():
        tree.close()
    if args.beam:
        beam(args.repeat, args.threads)


if __name__ == "__main__":
    if "--worker" in sys.argv:
        worker()
    else:
        main()
