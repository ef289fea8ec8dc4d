"""The docstring examples of the parametric package run and hold."""

import doctest
import importlib

import pytest

MODULES = ["basis", "conics", "curve_base", "curves", "fitting", "projection", "coons", "bicubic", "tensor", "volumes"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(f"parametric.{name}")
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
    assert result.attempted > 0


def test_parametric_imports_nothing_of_ours():
    import sys
    import subprocess
    code = ("import sys, parametric; "
            "bad = [m for m in sys.modules if m.split('.')[0] in ('implicit', 'spatial')]; "
            "print(bad); sys.exit(1 if bad else 0)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
