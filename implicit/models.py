"""Model files: solids and assemblies written as Python or JSON.

A model file is either

* a ``.py`` file that defines ``solid`` (a `Solid`) or a function ``model()``
  returning one (``model`` bound to a `Solid` itself is taken as it is), or
* a ``.json`` CSG tree (see `implicit.serialize`).

An assembly file is a ``.py`` file defining ``parts`` (a dict of named,
placed solids) or ``assembly()`` returning one, or a ``.json`` object
``{"parts": {name: tree, ...}}``.

Every failure becomes one clear line naming the file: a missing file is an
`OSError`, anything else (bad JSON, a model that raises, nothing to load) a
`ValueError` or `TypeError`, e.g.
``part.py: model() raised ZeroDivisionError: division by zero``.
A Python model file is the user's own program and runs as such; a JSON file
never executes code.
"""

from __future__ import annotations

import errno
import os
import runpy
import stat
import sys
from pathlib import Path

from .serialize import MAX_CHARS, from_dict, parse_json
from .solid import Solid

__all__ = ["load_model", "load_model_units", "load_assembly", "load_any", "load_materials", "UNIT_NAMES"]

#: Length units a model may declare (``units = "mm"`` in a .py model, a ``units`` field in JSON).
UNIT_NAMES = ("m", "cm", "mm", "in", "ft")


def _check_path(path) -> tuple[Path, str]:
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name, got {type(path).__name__}")
    p = Path(path)
    name = os.fspath(path)
    if not p.exists():
        raise FileNotFoundError(errno.ENOENT, "No such file or directory", name)
    if p.is_dir():
        raise IsADirectoryError(errno.EISDIR, "Is a directory", name)
    if p.suffix.lower() not in (".py", ".json"):
        raise ValueError(f"{name}: expected a .py or .json model file")
    # a device, FIFO or socket (or a link to one: /dev/zero) would be read
    # without end; only regular files are models
    if not stat.S_ISREG(p.stat().st_mode):
        raise ValueError(f"{name}: expected a regular file, got a device, pipe or socket")
    return p, name


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def _run_python(p: Path, name: str) -> dict:
    """Run a model file; its namespace, or ValueError naming the file."""
    folder = str(p.resolve().parent)
    sys.path.insert(0, folder)
    try:
        return runpy.run_path(str(p), run_name="__implicad_model__")
    except SyntaxError as exc:
        raise ValueError(f"{name}: line {exc.lineno}: {exc.msg}") from None
    except (Exception, SystemExit) as exc:  # the file is arbitrary user code
        raise ValueError(f"{name}: raised {_one_line(exc)}") from None
    finally:
        try:
            sys.path.remove(folder)
        except ValueError:  # pragma: no cover - the model removed it itself
            pass


def _call(func, name: str, label: str):
    if not callable(func):
        raise TypeError(f"{name}: {label} is not a function")
    try:
        return func()
    except (Exception, SystemExit) as exc:
        raise ValueError(f"{name}: {label}() raised {_one_line(exc)}") from None


def _read_json(p: Path, name: str):
    size = p.stat().st_size
    if size > MAX_CHARS:
        raise ValueError(f"{name}: the file is larger than {MAX_CHARS} bytes")
    with open(p, "rb") as fh:
        data = fh.read(MAX_CHARS + 1)       # never more, whatever the file claims
    if len(data) > MAX_CHARS:
        raise ValueError(f"{name}: the file is larger than {MAX_CHARS} bytes")
    try:
        return parse_json(data)
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None


def _tree(data, name: str, where: str = "") -> Solid:
    try:
        return from_dict(data)
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        if where and msg.startswith("$"):
            msg = where + msg[1:]
        raise type(exc)(f"{name}: {msg}") from None


def _as_solid(value, name: str, label: str) -> Solid:
    if not isinstance(value, Solid):
        raise TypeError(f"{name}: {label} is a {type(value).__name__}, expected a Solid")
    return value


def load_model(path) -> Solid:
    """Load the solid of a model file (``.py`` or ``.json``).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    Solid

    Raises
    ------
    OSError
        The file is missing or unreadable.
    ValueError, TypeError
        One line naming the file: bad JSON, a model file that raises, no
        ``solid`` or ``model()``, or a value that is not a Solid.

    Examples
    --------
    >>> from implicit.models import load_model
    >>> part = load_model("examples/benchmark_part.py")   # doctest: +SKIP
    """
    return load_model_units(path)[0]


def _declared_units(value, name: str):
    if value is None:
        return None
    if not isinstance(value, str) or value not in UNIT_NAMES:
        raise ValueError(f"{name}: units: expected one of {', '.join(UNIT_NAMES)}, got {value!r}")
    return value


def load_model_units(path) -> tuple:
    """The solid of a model file and the length units it declares (None when it declares none).

    A ``.py`` model declares them with a module-level ``units = "mm"``; a
    ``.json`` tree with a top-level ``"units": "mm"`` field beside ``"kind"``.

    Examples
    --------
    >>> from implicit.models import load_model_units
    >>> solid, units = load_model_units("examples/bracket.py")   # doctest: +SKIP
    """
    p, name = _check_path(path)
    if p.suffix.lower() == ".json":
        data = _read_json(p, name)
        if isinstance(data, dict) and "parts" in data and "kind" not in data:
            raise ValueError(f"{name}: this is an assembly file (it has 'parts'); load it with load_assembly")
        units = None
        if isinstance(data, dict) and "units" in data:
            data = dict(data)
            units = _declared_units(data.pop("units"), name)
        return _tree(data, name), units
    ns = _run_python(p, name)
    return _model_from(ns, name), _declared_units(ns.get("units"), name)


def _model_from(ns: dict, name: str) -> Solid:
    if "solid" in ns:
        return _as_solid(ns["solid"], name, "solid")
    if "model" in ns:
        if isinstance(ns["model"], Solid):  # ``model = box(...)``: a Solid is callable too, but as a field
            return ns["model"]
        return _as_solid(_call(ns["model"], name, "model"), name, "model() result")
    raise ValueError(f"{name}: defines neither 'solid' (a Solid) nor 'model()' returning one")


def _as_parts(value, name: str, label: str) -> dict:
    if not isinstance(value, dict):
        raise TypeError(f"{name}: {label} is a {type(value).__name__}, expected a dict of named solids")
    if not value:
        raise ValueError(f"{name}: {label} is empty")
    out = {}
    for key, solid in value.items():
        if not isinstance(key, str):
            raise TypeError(f"{name}: {label}: part names must be strings, got {key!r}")
        out[key] = _as_solid(solid, name, f"{label}[{key!r}]")
    return out


def load_assembly(path) -> dict[str, Solid]:
    """Load the named parts of an assembly file.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.py`` defining ``parts`` or ``assembly()``, or a ``.json`` object
        ``{"parts": {name: tree}}``.

    Returns
    -------
    dict of str to Solid
        Part name -> placed solid, in file order.
    """
    p, name = _check_path(path)
    if p.suffix.lower() == ".json":
        return _parts_json(_read_json(p, name), name)
    return _parts_from(_run_python(p, name), name)


def _parts_from(ns: dict, name: str) -> dict:
    if "parts" in ns:
        return _as_parts(ns["parts"], name, "parts")
    if "assembly" in ns:
        return _as_parts(_call(ns["assembly"], name, "assembly"), name, "assembly() result")
    raise ValueError(f"{name}: defines neither 'parts' (a dict of solids) nor 'assembly()' returning one")


def _parts_json(data, name: str) -> dict:
    if not isinstance(data, dict) or not isinstance(data.get("parts"), dict):
        raise ValueError(f"{name}: expected an object {{\"parts\": {{name: tree, ...}}}}")
    if not data["parts"]:
        raise ValueError(f"{name}: 'parts' is empty")
    return {str(k): _tree(v, name, f"$.parts[{k!r}]") for k, v in data["parts"].items()}


def load_any(path) -> Solid | dict[str, Solid]:
    """A model's solid, or an assembly's parts when the file is an assembly."""
    p, name = _check_path(path)
    if p.suffix.lower() == ".json":
        data = _read_json(p, name)
        if isinstance(data, dict) and "parts" in data and "kind" not in data:
            return _parts_json(data, name)
        return _tree(data, name)
    ns = _run_python(p, name)
    if "solid" in ns or "model" in ns:
        return _model_from(ns, name)
    if "parts" in ns or "assembly" in ns:
        return _parts_from(ns, name)
    raise ValueError(f"{name}: defines none of 'solid', 'model()', 'parts' or 'assembly()'")


def load_materials(path) -> dict:
    """The materials of an assembly file's parts: part name -> material.

    A ``.py`` assembly may define ``materials`` (a dict: part name -> a
    material name such as ``"steel"``, or ``(name, density in kg/m^3)``); a
    ``.json`` one may carry a ``"materials"`` object.  An empty dict when
    there is none.
    """
    p, name = _check_path(path)
    if p.suffix.lower() == ".json":
        data = _read_json(p, name)
        value = data.get("materials", {}) if isinstance(data, dict) else {}
    else:
        value = _run_python(p, name).get("materials", {})
    if not isinstance(value, dict):
        raise TypeError(f"{name}: materials is a {type(value).__name__}, expected a dict of part name -> material")
    return {str(k): (tuple(v) if isinstance(v, list) else v) for k, v in value.items()}
