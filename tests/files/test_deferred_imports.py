"""Modules numba and pyvista import but do not use at import time (pooch, yaml) run on first use."""

from __future__ import annotations

import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PROBE = """
import json, sys
import spatial
import numba, pyvista
kinds = {name: type(sys.modules[name]).__name__ for name in ("pooch", "yaml")}
ran_before = "pooch.core" in sys.modules
import pooch
retrieve = callable(pooch.retrieve)          # the first attribute read runs the module
print(json.dumps(dict(kinds=kinds, ran_before=ran_before, ran_after="pooch.core" in sys.modules, retrieve=retrieve,
                      opt=int(numba.core.config.OPT))))
"""


def _probe(cwd, eager=False) -> dict:
    env = dict(os.environ, PYTHONPATH=ROOT)
    env.pop("IMPLICAD_EAGER_IMPORTS", None)
    env = {k: v for k, v in env.items() if k != "NUMBA_OPT"}
    if eager:
        env["IMPLICAD_EAGER_IMPORTS"] = "1"
    code = PROBE
    proc = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_pooch_and_yaml_are_bound_at_import_and_run_at_first_use(tmp_path):
    r = _probe(tmp_path)
    assert r["kinds"] == {"pooch": "_LazyModule", "yaml": "_LazyModule"}
    assert r["ran_before"] is False                                 # pyvista's import ran none of pooch
    assert r["ran_after"] is True and r["retrieve"] is True


def test_numba_still_reads_its_config_file(tmp_path):
    # a .numba_config.yaml in the working folder: numba's configuration reads it through the lazy yaml
    (tmp_path / ".numba_config.yaml").write_text("opt: '2'\n")
    assert _probe(tmp_path)["opt"] == 2
    assert _probe(tmp_path, eager=True)["opt"] == 2


def test_eager_imports_run_them_at_once(tmp_path):
    r = _probe(tmp_path, eager=True)
    assert r["kinds"] == {"pooch": "module", "yaml": "module"} and r["ran_before"] is True
    assert r["opt"] == 3                                            # numba's default without a config file
