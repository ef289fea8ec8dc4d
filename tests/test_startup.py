"""What a job imports: `import spatial` loads no room, the mesh path no application room and none
of scipy.spatial, matplotlib, dask or meshio, and every lazy public name is the room's own object.

Each import check runs in a fresh interpreter: the test process has imported everything.
"""

from __future__ import annotations

import importlib
import json
import os
import pkgutil
import subprocess
import sys

import pytest

import spatial

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _fresh(code: str) -> dict:
    """Run `code` in a fresh interpreter; it prints a JSON object as its last line."""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


_LOADED = ("import json, sys; print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
           "('spatial', 'scipy', 'pyvista', 'vtkmodules', 'matplotlib', 'dask', 'distributed', 'meshio', 'numba'))))")


def test_import_spatial_loads_no_room_and_no_heavy_library():
    loaded = _fresh("import spatial; " + _LOADED)
    assert set(loaded) <= {"spatial", "spatial.files", "spatial.files.atomic", "spatial.files.lazy",
                           "spatial.files.meshes", "spatial.files.progress", "spatial.files.shutdown",
                           "spatial.files.frozen_imports", "spatial.files.deferred_imports",
                           "spatial.files.vtk_listing", "spatial.files.import_hooks"}, loaded


def test_import_implicit_loads_no_scipy_numba_or_spatial():
    loaded = _fresh("import implicit; " + _LOADED)
    assert loaded == []


@pytest.mark.parametrize("features", [False, None])
def test_the_mesh_path_loads_only_what_meshing_needs(features):
    extra = "" if features is None else f", features={features}"
    job = f"import spatial; from implicit import sphere; spatial.mesh(sphere(1.0), resolution=12{extra}); "
    _fresh(job + _LOADED)  # compiles into numba's cache whatever an edited kernel left stale
    loaded = _fresh(job + _LOADED)
    rooms = {m.split(".")[1] for m in loaded if m.startswith("spatial.")}
    assert rooms <= {"files", "cells", "meshing", "distributed"}, rooms
    # the cluster side of `distributed` stays out: only its warning wrapper and the shared mesh module
    assert "spatial.distributed.mass" not in loaded and "spatial.analysis" not in loaded
    # the plain path needs no scipy; the default (feature) path loads scipy.linalg on the way
    heavies = ("scipy.spatial", "scipy.sparse", "scipy.linalg") if features is False else ()
    for heavy in heavies + ("matplotlib", "dask", "distributed", "meshio"):
        assert heavy not in loaded, heavy


@pytest.mark.parametrize("package", ["spatial", "spatial.distributed"])
def test_every_lazy_name_is_the_rooms_own_object(package):
    module = importlib.import_module(package)
    for name, (where, attribute) in module._LAZY.items():
        source = importlib.import_module(where, package)
        assert getattr(module, name) is (source if attribute is None else getattr(source, attribute)), name
    assert set(module._LAZY) <= set(dir(module))


@pytest.mark.parametrize("package", ["spatial", "spatial.distributed"])
def test_no_lazy_name_is_also_a_submodule(package):
    # importing a submodule binds its name in the package, which would then shadow the lazy name
    module = importlib.import_module(package)
    submodules = {info.name for info in pkgutil.iter_modules(module.__path__)}
    clash = {name for name, (_, attribute) in module._LAZY.items() if attribute is not None} & submodules
    assert clash == set()


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_name"):
        spatial.no_such_name  # noqa: B018


def test_star_import_gives_the_public_names():
    namespace: dict = {}
    exec("from spatial import *", namespace)
    assert {"mesh", "mass_properties", "tet_mesh", "report", "Octree"} <= set(namespace)
    assert "analysis" not in namespace  # rooms stay attributes, not star-imported names


def test_the_mesh_command_reads_no_distribution_metadata(tmp_path):
    # numba's extension loader and `--version` are the only readers, and neither runs for a mesh
    out = str(tmp_path / "part.stl")
    loaded = _fresh("import json, sys; from spatial.cli import main; "
                    f"main(['mesh', 'examples/benchmark_part.py', '-o', {out!r}, '--resolution', '24']); "
                    "print(json.dumps({k: type(sys.modules[k]).__name__ for k in ('importlib.metadata', 'email') "
                    "if k in sys.modules}))")
    assert loaded in ({}, {"importlib.metadata": "_LazyModule"}), loaded
    assert os.path.getsize(out) > 84


def test_version_is_read_when_asked_for():
    from importlib import metadata

    proc = subprocess.run([sys.executable, "-m", "spatial.cli", "--version"], capture_output=True, text=True,
                          timeout=300, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout == f"implicad {metadata.version('implicad')}\n"
