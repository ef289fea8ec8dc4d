"""Whole-process figures: a fresh interpreter per run, as a user meets the mesher.

Each run is one child process, timed from the parent: wall seconds around the
child, and the child's own CPU seconds (user + system) and peak resident
memory from ``os.wait4``, which reports the resources of exactly that child
(``RUSAGE_CHILDREN`` would fold in every earlier child's peak).  The child
also prints its in-process meshing time, so both figures come from one run.

The peer is fogleman/sdf (https://github.com/fogleman/sdf), a small numpy
mesher, run from its own Python (``--sdf-python``, e.g. a throw-away venv
where it is installed from its source); nothing of it is vendored here.  It
meshes the same part with its own primitives at the same step ``h = 1.6 / N``
over the same bounds ``[-0.8, 0.8]^3``, with its default two worker threads
and sparse sampling.
"""

from __future__ import annotations

import json
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

#: Whole-process child of implicad: imports and one mesh, nothing warmed beforehand.
IMPLICAD_CHILD = r"""
import json, sys, time
sys.path.insert(0, {root!r})
from implicit import box, cylinder, sphere
from spatial import mesh
part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
t0 = time.perf_counter()
m = mesh(part, resolution={n}, progress=False, features=False)
print(json.dumps(dict(mesh=time.perf_counter() - t0, triangles=int(m.n_cells), volume=float(m.volume))))
"""

#: The same part in fogleman/sdf's own primitives, at the same step and bounds.
SDF_CHILD = r"""
import json, time
import numpy as np
from sdf import X, Y, Z, box, cylinder, sphere
f = sphere(1) & box(1.5)
c = cylinder(0.5)
f -= c.orient(X) | c.orient(Y) | c.orient(Z)
t0 = time.perf_counter()
points = f.generate(step=1.6 / {n}, bounds=((-0.8, -0.8, -0.8), (0.8, 0.8, 0.8)), verbose=False)
seconds = time.perf_counter() - t0
tri = np.asarray(points, dtype=np.float64).reshape(-1, 3, 3)
volume = abs(float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum()) / 6.0)
print(json.dumps(dict(mesh=seconds, triangles=int(tri.shape[0]), volume=volume)))
"""


def run_child(argv, env=None):
    """Run one child; returns its last stdout line as JSON plus ``wall``, ``cpu`` (s) and ``peak`` (MB)."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    # read both pipes to the end (the child may fill either), then reap it ourselves for its rusage
    out, err = _drain(proc)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode:
        raise RuntimeError(f"child {argv[:2]} failed ({proc.returncode}): {err.strip()[-500:]}")
    lines = out.strip().splitlines()
    res = json.loads(lines[-1]) if lines and lines[-1].startswith("{") else {}
    res.update(wall=wall, cpu=usage.ru_utime + usage.ru_stime, peak=usage.ru_maxrss / 1024.0)
    return res


def _drain(proc):
    """Both pipes read to their end without deadlock (stderr in a thread); the child is not reaped."""
    import threading

    chunks = []
    reader = threading.Thread(target=lambda: chunks.append(proc.stderr.read()))
    reader.start()
    out = proc.stdout.read()
    reader.join()
    return out, chunks[0] if chunks else ""


def sdf_usable(python):
    """None when ``python`` can import sdf, else the reason it cannot."""
    if not python:
        return "no --sdf-python given"
    if not os.path.exists(python):
        return f"{python} does not exist"
    res = subprocess.run([python, "-c", "import sdf"], capture_output=True, text=True)
    if res.returncode:
        return f"{python} cannot import sdf ({res.stderr.strip().splitlines()[-1] if res.stderr.strip() else '?'})"
    return None


def implicad_run(python, n):
    return run_child([python, "-c", IMPLICAD_CHILD.format(root=ROOT, n=n)])


def sdf_run(python, n):
    return run_child([python, "-c", SDF_CHILD.format(n=n)])


def command_run(implicad, n, out):
    """``implicad mesh examples/benchmark_part.py -o out --resolution n`` as a whole command."""
    return run_child([implicad, "mesh", os.path.join(ROOT, "examples", "benchmark_part.py"), "-o", out,
                      "--resolution", str(n)])
