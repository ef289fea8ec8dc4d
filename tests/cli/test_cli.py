"""The `implicad` command as a whole: help, version, exit statuses, pipes."""

import sys

import pytest

from spatial.cli import COMMAND_MODULES, build_parser, main


def test_every_command_is_available_and_has_help(capsys):
    parser = build_parser()
    choices = parser._subparsers._group_actions[0].choices
    assert sorted(choices) == sorted(COMMAND_MODULES)
    for name in COMMAND_MODULES:
        with pytest.raises(SystemExit) as exc:
            main([name, "--help"])
        assert exc.value.code == 0
        out = capsys.readouterr().out
        assert out.startswith(f"usage: implicad {name}")


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.startswith("implicad ")


def test_unknown_command_exits_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
    assert "invalid choice: 'frobnicate'" in capsys.readouterr().err


def test_missing_model_is_one_line_and_status_2(capsys, tmp_path):
    status = main(["info", str(tmp_path / "nope.py")])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith("implicad: error: ")
    assert err.count("\n") == 1
    assert "Traceback" not in err


def test_closed_pipe_ends_quietly(monkeypatch):
    class ClosedPipe:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert main(["families"]) == 0


def test_the_help_table_is_each_commands_own_help():
    import importlib

    from spatial.cli import COMMANDS

    for name, help_text in COMMANDS.items():
        module = importlib.import_module(f"spatial.cli.{name}")
        assert module.NAME == name and module.HELP == help_text, name


def test_a_command_imports_its_own_module_only_and_vtk_is_still_quiet():
    import json
    import subprocess

    code = ("import json, sys; from spatial.cli import main, _KEEP; status = main(['families']); "
            "before = sorted(m for m in sys.modules if m.startswith('spatial.cli.') or m == 'vtkmodules'); "
            "import pyvista; print(json.dumps(dict(status=status, before=before, kept=len(_KEEP))))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["status"] == 0
    assert out["before"] == ["spatial.cli.common", "spatial.cli.families"]
    assert out["kept"] == 1  # VTK, imported after the command started, was silenced when it loaded


def test_options_before_the_command_still_find_it(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--debug", "mesh", "--help"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.startswith("usage: implicad mesh")
