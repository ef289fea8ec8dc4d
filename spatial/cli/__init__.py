"""The `implicad` command.

Each sub-command lives in its own module of `spatial.cli` and provides
``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
Bad input prints one line on stderr and exits with status 2 (a traceback only
with ``--debug``).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import json
import os
import sys
from importlib import metadata

from .common import add_common_flags, install_warning_handler

__all__ = ["main", "build_parser", "CommandError", "NoResult"]

#: Sub-command modules, in the order `--help` lists them.
COMMAND_MODULES = (
    "info",
    "families",
    "mesh",
    "mass",
    "check",
    "section",
    "interfere",
    "fea",
    "render",
    "draw",
    "slice",
    "toolpath",
    "inspect",
    "stackup",
    "bom",
    "compare",
    "report",
)


class CommandError(Exception):
    """A user-facing failure: printed as one line, exit status 2."""


class NoResult(Exception):
    """Good input, but no answer to give (a plane that misses the part, a
    tolerance not reached): printed as one line, exit status 1."""


def _version() -> str:
    try:
        return metadata.version("implicad")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a plain checkout
        return "unknown"


def _load_commands():
    commands = []
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(f"spatial.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"spatial.cli.{name}":
                continue
            raise
        commands.append(module)
    return commands


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of `implicad` with every available sub-command."""
    parser = argparse.ArgumentParser(
        prog="implicad",
        description="Volumetric / implicit solid modeler: CSG solids, octree cells, "
        "occupancy grids, boundary meshes, mass properties and FEA meshes.",
        epilog=_EPILOG,
    )
    parser.add_argument("--version", action="version", version=f"implicad {_version()}")
    parser.add_argument("--debug", action="store_true", help="show a traceback on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for module in _load_commands():
        p = sub.add_parser(module.NAME, help=module.HELP, description=getattr(module, "DESCRIPTION", module.HELP),
                           epilog=_EPILOG)
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show a traceback on errors")
        module.add_arguments(p)
        p.set_defaults(_run=module.run, _native_json="--json" in p._option_string_actions, _name=module.NAME)
        add_common_flags(p)
    return parser




def quiet_vtk() -> None:
    """Keep VTK's own error and warning lines off the terminal.

    VTK prints them from C++ (the output window and its logger) besides the
    Python exception pyvista raises; the command reports that exception as its
    one line, so the C++ copies and pyvista's log records are dropped.
    """
    import logging

    try:
        from vtkmodules.vtkCommonCore import vtkLogger, vtkObject, vtkOutputWindow, vtkStringOutputWindow
    except ImportError:  # pragma: no cover - VTK is a dependency
        return
    vtkObject.GlobalWarningDisplayOff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    window = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(window)
    _KEEP.append(window)
    logging.getLogger().addHandler(logging.NullHandler())    # no lastResort "ERROR:root:" lines
    logging.getLogger("pyvista").setLevel(logging.CRITICAL)


_KEEP: list = []
_EPILOG = ("Model files: a .py model is a Python program and runs as such, with your rights (load only "
           "files you trust); a .json model (a CSG tree) never runs code and is the safe format to "
           "exchange.")


def _run(args):
    """Run the command; under ``--json`` a command without its own JSON form is wrapped in one object."""
    if not getattr(args, "json", False) or args._native_json:
        return args._run(args)
    args.progress = False
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        status = args._run(args)
    print(json.dumps({"command": args._name, "status": int(status or 0),
                      "output": buffer.getvalue().splitlines()}, indent=1))
    return status


def main(argv=None) -> int:
    """Run `implicad` with `argv` (default: ``sys.argv[1:]``); return the exit status."""
    install_warning_handler()
    parser = build_parser()
    args = parser.parse_args(argv)
    debug = getattr(args, "debug", False)
    if not debug:
        quiet_vtk()
    try:
        status = _run(args)
    except KeyboardInterrupt:
        print("implicad: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (`implicad families | head`): stop quietly.
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:  # pragma: no cover
            pass
        return 0
    except NoResult as exc:
        if debug:
            raise
        print(f"implicad: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 1
    except (CommandError, ValueError, TypeError, OSError, ImportError, MemoryError, SyntaxError) as exc:
        if debug:
            raise
        message = str(exc) or type(exc).__name__
        if isinstance(exc, OSError) and exc.filename and exc.strerror:
            message = f"{exc.filename}: {exc.strerror}"
        print(f"implicad: error: {message.splitlines()[0] if message else type(exc).__name__}", file=sys.stderr)
        return 2
    return int(status or 0)

