"""Heavy packages imported with the collector paused, then everything alive frozen (a cycle they left included)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# a stand-in for a heavy package: `skimage` is one of PACKAGES, and this folder comes first on the path
FAKE = textwrap.dedent("""
    import gc, weakref

    class Cycle:
        def __init__(self):
            self.me = self

    ENABLED_DURING = gc.isenabled()
    GARBAGE = weakref.ref(Cycle())              # garbage at once, freed only by a collection
    KEPT = [Cycle() for _ in range(2000)]       # alive: frozen
""")

PROBE = textwrap.dedent("""
    import gc, json, sys
    sys.path.insert(0, {fake!r})
    {before}
    import spatial
    frozen_before = gc.get_freeze_count()
    import skimage
    print(json.dumps(dict(before=frozen_before, after=gc.get_freeze_count(), during=skimage.ENABLED_DURING,
                          garbage_alive=skimage.GARBAGE() is not None, enabled=gc.isenabled(),
                          loader=type(skimage.__loader__).__name__,
                          spec_loader=skimage.__spec__.loader is skimage.__loader__)))
""")


def _probe(tmp_path, before="", full=False) -> dict:
    fake = tmp_path / "fake"
    (fake / "skimage").mkdir(parents=True)
    (fake / "skimage" / "__init__.py").write_text(FAKE)
    env = dict(os.environ, PYTHONPATH=ROOT)
    env.pop("IMPLICAD_FULL_GC", None)
    if full:
        env["IMPLICAD_FULL_GC"] = "1"
    proc = subprocess.run([sys.executable, "-c", PROBE.format(fake=str(fake), before=before)], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_heavy_import_runs_without_the_collector_then_its_objects_are_frozen(tmp_path):
    r = _probe(tmp_path)
    assert r["before"] == 0                     # `import spatial` freezes nothing itself
    assert r["during"] is False                 # the package ran with the collector off
    assert r["after"] >= 2000                   # its live objects (and everything older) frozen
    assert r["garbage_alive"] is True           # the price: a cycle it left is frozen, not collected
    assert r["enabled"] is True                 # and the collector is back on
    # the module keeps its own loader: resource readers and get_source work as without the wrapper
    assert r["loader"] == "SourceFileLoader" and r["spec_loader"] is True


def test_a_collector_the_caller_turned_off_stays_off(tmp_path):
    r = _probe(tmp_path, before="gc.disable()")
    assert r["during"] is False and r["enabled"] is False and r["after"] >= 2000


def test_full_gc_leaves_the_collector_alone(tmp_path):
    r = _probe(tmp_path, full=True)
    assert r["during"] is True and r["after"] == 0
    assert r["garbage_alive"] is False          # the collector ran during the import and freed the cycle


@pytest.mark.parametrize("name", ["numba", "pyvista"])
def test_the_real_packages_are_frozen_and_keep_their_loaders(name):
    code = (f"import gc, json, spatial; import {name} as m; "
            "print(json.dumps([gc.get_freeze_count(), type(m.__loader__).__name__, gc.isenabled()]))")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, PYTHONPATH=ROOT))
    assert proc.returncode == 0, proc.stderr[-2000:]
    frozen, loader, enabled = json.loads(proc.stdout.strip().splitlines()[-1])
    assert frozen > 20_000 and loader == "SourceFileLoader" and enabled
