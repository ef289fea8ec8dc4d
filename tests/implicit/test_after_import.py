import subprocess
import sys


def test_a_hook_runs_once_right_after_the_import_and_at_once_when_imported():
    code = """
import sys
from implicit.after_import import after_import
seen = []
hook = lambda m: seen.append(m.__name__)
after_import("wave", hook)
after_import("wave", hook)          # the same hook is not registered twice
assert seen == [] and "wave" not in sys.modules
import wave
assert seen == ["wave"], seen
after_import("wave", hook)          # already imported: runs now
assert seen == ["wave", "wave"]
import importlib; importlib.reload(wave)
assert seen == ["wave", "wave"]     # the finder is gone after the first import
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"
