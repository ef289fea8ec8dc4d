"""Input the command must survive: devices as models, killed writes, VTK's own error lines."""

import os
import subprocess
import sys
import time

import pytest

from spatial.cli import build_parser, main
from spatial.files.atomic import STALE_SECONDS, atomic_write, clean_stale_temporaries


def test_json_model_must_be_a_regular_file(tmp_path, capsys):
    link = tmp_path / "zero.json"
    os.symlink("/dev/zero", link)
    t0 = time.perf_counter()
    assert main(["info", str(link)]) == 2
    assert time.perf_counter() - t0 < 10
    err = capsys.readouterr().err
    assert "expected a regular file" in err and err.count("\n") == 1
    from implicit.models import load_model

    with pytest.raises(ValueError, match="regular file"):
        load_model(link)
    py = tmp_path / "zero.py"
    os.symlink("/dev/zero", py)
    with pytest.raises(ValueError, match="regular file"):
        load_model(py)


def test_help_says_py_runs_code_and_json_is_safe():
    text = build_parser().format_help()
    assert ".py model is a Python program" in " ".join(text.split())
    assert ".json model" in text and "safe format" in " ".join(text.split())


def test_stale_temporaries_are_cleaned_at_the_next_write(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    dead_pid = int(dead.stdout)
    killed = tmp_path / f".part.stl.{dead_pid}-{'a' * 32}.tmp.stl"
    killed.write_bytes(b"half a file")
    live = tmp_path / f".part.stl.{os.getppid()}-{'b' * 32}.tmp.stl"     # a live writer: kept
    live.write_bytes(b"being written")
    old = tmp_path / f".part.stl.{'c' * 32}.tmp.stl"                     # no pid, old: removed
    old.write_bytes(b"old")
    past = time.time() - STALE_SECONDS - 60
    os.utime(old, (past, past))
    young = tmp_path / f".part.stl.{'d' * 32}.tmp.stl"                   # no pid, young: kept
    young.write_bytes(b"young")
    other = tmp_path / ".hidden.txt"
    other.write_text("not ours")
    atomic_write(tmp_path / "part.txt", lambda p: open(p, "w").write("done"))
    assert (tmp_path / "part.txt").read_text() == "done"
    assert not killed.exists() and not old.exists()
    assert live.exists() and young.exists() and other.exists()
    assert clean_stale_temporaries(tmp_path) == []


def test_temporary_name_carries_the_pid(tmp_path):
    seen = []
    atomic_write(tmp_path / "a.stl", lambda p: (seen.append(os.path.basename(p)), open(p, "w").close()))
    assert seen[0].startswith(f".a.stl.{os.getpid()}-") and seen[0].endswith(".tmp.stl")


def test_vtk_error_lines_never_reach_the_terminal():
    code = ("from spatial.cli import quiet_vtk; quiet_vtk()\n"
            "from vtkmodules.vtkIOGeometry import vtkSTLWriter\n"
            "w = vtkSTLWriter(); w.SetFileName('/nonexistent/dir/x.stl'); w.Write()\n"
            "print('done')\n")
    loud = subprocess.run([sys.executable, "-c", code.replace("quiet_vtk()", "None")],
                          capture_output=True, text=True, timeout=120)
    assert "ERR" in loud.stderr or "rror" in loud.stderr       # VTK does print without the guard
    quiet = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert quiet.stdout.strip() == "done" and quiet.stderr == ""


def test_empty_mesh_is_not_written(tmp_path):
    import pyvista as pv

    from spatial.files.meshes import save_mesh

    with pytest.raises(ValueError, match="empty mesh"):
        save_mesh(pv.PolyData(), tmp_path / "x.stl")
    assert list(tmp_path.iterdir()) == []
