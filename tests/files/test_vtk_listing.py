"""VTK's extension modules found in one listing of their folder: the files VTK's own globs find."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_the_listing_finds_what_vtks_glob_finds():
    vtkmodules = pytest.importorskip("vtkmodules")
    from spatial.files.vtk_listing import find_lib_path

    original = getattr(vtkmodules.find_lib_path, "__wrapped__", vtkmodules.find_lib_path)
    folder = list(vtkmodules.__path__)
    names = sorted({n.split(".")[0] for n in os.listdir(folder[0]) if n.startswith("vtk")})
    assert len(names) > 50
    # every module name VTK has, a prefix of others (vtkIOXML / vtkIOXMLParser) and names it lacks
    for name in names + ["vtkIOXML", "vtkNoSuchModule", "vtk"]:
        assert find_lib_path(folder, name) == original(folder, name), name
    assert find_lib_path(folder, "vtkCommonCore").endswith(".so")
    assert find_lib_path([os.path.join(folder[0], "missing")], "vtkCommonCore") is None


def test_pyvista_imports_through_the_listing():
    code = ("import json, spatial, pyvista, vtkmodules; "
            "print(json.dumps([hasattr(vtkmodules.find_lib_path, '__wrapped__'), pyvista.Sphere().n_cells]))")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, PYTHONPATH=ROOT))
    assert proc.returncode == 0, proc.stderr[-2000:]
    patched, cells = json.loads(proc.stdout.strip().splitlines()[-1])
    assert patched is True and cells > 0
