"""`import implicit` leaves the parametric solids (and scipy) for later; their names and their
kinds in a JSON tree still work in a fresh interpreter, loading them on first use."""

import json
import subprocess
import sys

import numpy as np

from implicit import extrude_curve, sphere, sweep
from implicit.serialize import to_json
from implicit.sweeps import circle
from parametric.conics import circle as nurbs_circle
from parametric.curves import Bezier

CHILD = r"""
import json, sys
import numpy as np
import implicit
before = sorted(m for m in ("implicit.parametric_solids", "implicit.star_solids", "scipy") if m in sys.modules)
solid = implicit.from_json(sys.stdin.read())
values = solid(np.array([[0.05, 0.0, 0.1], [0.0, 0.0, 0.0], [0.95, 0.0, 0.5], [2.0, 2.0, 2.0]])).tolist()
print(json.dumps(dict(before=before, values=values, kinds=sorted({n.kind for n in solid.walk()}),
                      named=implicit.star_solid.__module__)))
"""


def test_a_fresh_interpreter_decodes_parametric_kinds_it_has_not_loaded():
    # a swept rod (curve sweep) and an extruded NURBS circle (curve profile) beside a sphere
    solid = sweep(circle(0.3), Bezier([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])) \
        | extrude_curve(nurbs_circle(0.4, center=(1.0, 0.0)), 1.0, center=(0.0, 0.0, 0.5)) | sphere(0.2)
    text = to_json(solid)
    points = np.array([[0.05, 0.0, 0.1], [0.0, 0.0, 0.0], [0.95, 0.0, 0.5], [2.0, 2.0, 2.0]])
    proc = subprocess.run([sys.executable, "-c", CHILD], input=text, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["before"] == []                      # nothing of them loaded by `import implicit`
    assert {"sweep_curve", "curve_profile"} & set(out["kinds"])
    np.testing.assert_allclose(out["values"], solid(points), rtol=0, atol=1e-12)
    assert out["named"] == "implicit.star_solids"   # a lazy name read after the decode
