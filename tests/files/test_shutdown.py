"""The exit handler `import spatial` installs: garbage collected once with the modules intact, then frozen."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

SCRIPT = textwrap.dedent("""
    import atexit, gc, sys
    # registered before spatial's handler, so it runs after it: what the teardown will find
    atexit.register(lambda: open("frozen.txt", "w").write(str(gc.get_freeze_count())))
    import spatial


    class Node:
        def __init__(self):
            self.me = self                        # a reference cycle: only a collection frees it

        def __del__(self):
            # runs while the modules are intact: `open` and `str` are still there
            with open("finalized.txt", "a") as fh:
                fh.write("node\\n")


    gc.disable()                                  # the cycle is still garbage when the process ends
    Node()
""")


@pytest.mark.parametrize("full", [False, True], ids=["collect then freeze", "interpreter's teardown"])
def test_cycles_are_finalized_and_the_survivors_frozen(tmp_path, full):
    env = dict(os.environ, PYTHONPATH=ROOT)
    env.pop("IMPLICAD_FULL_TEARDOWN", None)
    if full:
        env["IMPLICAD_FULL_TEARDOWN"] = "1"
    proc = subprocess.run([sys.executable, "-c", SCRIPT], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    frozen = int((tmp_path / "frozen.txt").read_text())
    if full:
        assert frozen == 0                        # the handler stood aside
    else:
        assert frozen > 1000                      # every module's objects, out of the teardown's walks
        # the cycle was finalized by the handler's collection (the interpreter's own teardown reaches
        # it only once `open` is gone, and the write fails silently)
        assert (tmp_path / "finalized.txt").read_text() == "node\n"
