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

from .common import add_common_flags, install_warning_handler

__all__ = ["main", "console", "build_parser", "CommandError", "NoResult"]

#: Sub-command modules, in the order `--help` lists them, with their one-line help (the module's
#: ``HELP``): a command imports only its own module, the others are listed from this table.
COMMANDS = {
    "info": "show a model's CSG tree, bounds, counts and family parameters",
    "families": "list the part families and their parameters",
    "mesh": "write a watertight boundary mesh (STL, PLY, OBJ, VTP, VTK) of a model",
    "mass": "volume, mass, area, centroid and inertia of a model, with error bounds",
    "check": "check that a model is a valid solid (exit 1 if not)",
    "section": "cut a model by a plane: loops, holes, area and second moments; plot or polylines",
    "interfere": "find interfering and touching parts of an assembly (exit 1 if any interfere)",
    "fea": "tetrahedral mesh, linear-static deck and CalculiX run (.inp .msh .vtu .bdf .med .stl .ply; "
           "--results .frd)",
    "render": "draw a part or an assembly to a PNG picture",
    "draw": "an engineering drawing: views, hidden lines, dimensions, sections, exploded assemblies "
            "(SVG/PDF/DXF/PNG)",
    "slice": "cut a model into layers of closed contours (JSON, SVG or CSV) for additive manufacturing",
    "toolpath": "2.5D milling tool paths as G-code (pockets, profiles, lead-ins), optionally verified by "
                "material removal",
    "inspect": "compare a scanned part (mesh or point cloud) with its design: deviations, pass/fail, pictures",
    "stackup": "tolerance stack-up of a clearance: worst case, RSS, Monte-Carlo, probability of interference",
    "bom": "bill of materials of an assembly: items, families, materials, volumes, masses, counts (CSV, JSON)",
    "compare": "compare every representation scheme of a model: storage, build time, volume error, queries",
    "report": "write the full report of a model (Markdown, HTML, JSON and pictures)",
}
COMMAND_MODULES = tuple(COMMANDS)


class CommandError(Exception):
    """A user-facing failure: printed as one line, exit status 2."""


class NoResult(Exception):
    """Good input, but no answer to give (a plane that misses the part, a
    tolerance not reached): printed as one line, exit status 1."""


def _version() -> str:
    from importlib import metadata  # local: read only for --version (the distributions' metadata, 0.01 s)

    try:
        return metadata.version("implicad")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a plain checkout
        return "unknown"


class _VersionAction(argparse.Action):
    """``--version``: argparse's version action with the version read only when it is asked for."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="show program's version number and exit"):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        parser._print_message(f"implicad {_version()}\n", sys.stdout)
        parser.exit()


def _load_command(name):
    """The module of sub-command `name`, or None when it is not installed."""
    try:
        return importlib.import_module(f"spatial.cli.{name}")
    except ModuleNotFoundError as exc:
        if exc.name == f"spatial.cli.{name}":
            return None
        raise


def command_of(argv) -> str | None:
    """The sub-command `argv` asks for (its first word that is not a flag), or None."""
    for word in argv:
        if not word.startswith("-"):
            return word if word in COMMANDS else None
    return None


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser of `implicad` with every available sub-command.

    With `only`, that sub-command alone is imported and given its arguments;
    the others are listed by name and help (what ``--help`` and an unknown
    command's error show), so a command pays for its own imports only.
    """
    parser = argparse.ArgumentParser(
        prog="implicad",
        description="Volumetric / implicit solid modeler: CSG solids, octree cells, "
        "occupancy grids, boundary meshes, mass properties and FEA meshes.",
        epilog=_EPILOG,
    )
    parser.add_argument("--version", action=_VersionAction)
    parser.add_argument("--debug", action="store_true", help="show a traceback on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name, help_text in COMMANDS.items():
        if only is not None and name != only:
            sub.add_parser(name, help=help_text, add_help=False)
            continue
        module = _load_command(name)
        if module is None:
            continue
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
_VTK = "vtkmodules"


def quiet_vtk_when_loaded() -> None:
    """`quiet_vtk` as soon as VTK is imported, without importing it (0.1 s) for commands that never use it.

    A finder at the head of ``sys.meta_path`` wraps the loader of the ``vtkmodules``
    package, so that VTK is silenced right after the package has run and before
    any of its modules does work.
    """
    from implicit.after_import import after_import

    after_import(_VTK, _quiet_vtk_hook)


def _quiet_vtk_hook(module):
    quiet_vtk()


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
    argv = sys.argv[1:] if argv is None else list(argv)
    # only the chosen command's module; `--help` and errors list the rest by name
    parser = build_parser(only=command_of(argv) or "")
    args = parser.parse_args(argv)
    debug = getattr(args, "debug", False)
    if not debug:
        quiet_vtk_when_loaded()
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



def console() -> None:
    """The `implicad` console script: `main` on ``sys.argv``, then the process ends with its status.

    The process ends without the interpreter's teardown (0.2 s of CPU once
    numba is loaded; `spatial.cli._quick_exit`), after the ``atexit``
    handlers and a flush of every open file; in-process callers use `main`,
    which returns the status.
    """
    status = main()
    from ._quick_exit import exit_now

    exit_now(status)
    sys.exit(status)
