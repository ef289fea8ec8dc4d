"""The console script ends without the interpreter's teardown, keeping what the teardown did for the user."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _console(args, cwd, code="from spatial.cli import console; console()"):
    """Run the console script's entry in a fresh interpreter, its output read through pipes."""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=300,
                          cwd=cwd, env=env)


def test_the_mesh_command_ends_with_its_file_whole_and_its_summary_printed(tmp_path):
    out = tmp_path / "part.stl"
    proc = _console(["mesh", os.path.join(ROOT, "examples", "benchmark_part.py"), "-o", str(out),
                     "--resolution", "24"], tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    summary = proc.stdout.strip().splitlines()[-1]
    assert summary.startswith(f"{out}: ") and "watertight yes" in summary
    triangles = int(summary.split(": ")[1].split(" triangles")[0])
    assert out.stat().st_size == 84 + 50 * triangles


def test_the_status_of_a_failed_command_is_the_exit_status(tmp_path):
    proc = _console(["mesh", str(tmp_path / "missing.py"), "-o", str(tmp_path / "part.stl")], tmp_path)
    assert proc.returncode == 2
    assert proc.stderr.startswith("implicad: error: ") and "missing.py" in proc.stderr


def test_a_model_that_leaves_a_file_open_and_an_exit_handler_keeps_both(tmp_path):
    # a model is a Python program: what it writes and registers must reach the disk as a normal exit would
    model = tmp_path / "model.py"
    model.write_text(textwrap.dedent("""
        import atexit, sys
        from implicit import sphere
        sys.model_log = open("log.txt", "w")     # kept open past the model's run (here on the sys module)
        for _ in range(1000):
            sys.model_log.write("measured\\n")    # short writes: the last few kB stay buffered, never closed
        atexit.register(lambda: open("handler.txt", "a").write("ran\\n"))
        solid = sphere(1.0)
    """))
    proc = _console(["info", str(model)], tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert (tmp_path / "log.txt").read_text() == "measured\n" * 1000
    assert (tmp_path / "handler.txt").read_text() == "ran\n"       # run once, not twice


def test_with_another_thread_running_the_process_waits_for_it(tmp_path):
    code = textwrap.dedent("""
        import sys, threading, time
        from spatial.cli._quick_exit import exit_now
        def late():
            time.sleep(0.5)
            open("late.txt", "w").write("done")
        threading.Thread(target=late).start()
        exit_now(3)                              # returns: the thread is alive
        print("returned", flush=True)
        sys.exit(3)
    """)
    proc = _console([], tmp_path, code=code)
    assert proc.returncode == 3
    assert proc.stdout == "returned\n"
    assert (tmp_path / "late.txt").read_text() == "done"


def test_exit_now_ends_the_process_with_the_status(tmp_path):
    code = "from spatial.cli._quick_exit import exit_now; print('before', end=''); exit_now(5); print('after')"
    proc = _console([], tmp_path, code=code)
    assert (proc.returncode, proc.stdout) == (5, "before")


def test_exit_handlers_run_once_when_one_of_them_starts_a_thread(tmp_path):
    code = textwrap.dedent("""
        import atexit, sys, threading, time
        from spatial.cli._quick_exit import exit_now
        def handler():
            open("handler.txt", "a").write("ran\\n")
            threading.Thread(target=time.sleep, args=(0.2,)).start()
        atexit.register(handler)
        exit_now(4)                              # runs the handler, sees its thread, returns
        sys.exit(4)
    """)
    proc = _console([], tmp_path, code=code)
    assert proc.returncode == 4
    assert (tmp_path / "handler.txt").read_text() == "ran\n"


def test_the_flush_at_exit_leaves_modules_bound_lazily_unrun(tmp_path):
    # `isinstance` reads an object's ``__class__``: on a lazily loaded module that read runs the module, so a
    # flush that asked every object would import yaml and importlib.metadata at every exit (80 ms)
    (tmp_path / "lazily_bound.py").write_text("open('ran.txt', 'w').write('ran')\n")
    code = textwrap.dedent("""
        import importlib.util, sys
        from spatial.cli._quick_exit import exit_now
        spec = importlib.util.find_spec("lazily_bound")
        spec.loader = importlib.util.LazyLoader(spec.loader)
        module = importlib.util.module_from_spec(spec)
        sys.modules["lazily_bound"] = module
        spec.loader.exec_module(module)          # bound, not run
        kept = open("kept.txt", "w"); kept.write("flushed")
        exit_now(0)
    """)
    env_path = str(tmp_path)
    proc = _console([], tmp_path, code=f"import sys; sys.path.insert(0, {env_path!r})\n" + code)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert (tmp_path / "kept.txt").read_text() == "flushed"
    assert not (tmp_path / "ran.txt").exists()
