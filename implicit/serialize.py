"""CSG trees <-> JSON.

A node is a JSON object ``{"kind": <kind>, <its params>..., "children": [...]}``:
the parameters sit beside ``kind`` (so an error can name
``$.children[1].radius``) and ``children`` is omitted for leaves and for
nodes whose class sets ``serialize_children = False`` (a family instance
stores only its family call and is rebuilt on loading).

Encoding uses each node's `to_params()` (default: its `params`);
data-backed nodes override `to_params` and `from_params` to store their
data.  Decoding looks the kind up in `Solid.registry` and calls
``cls.from_params(children, params)``.

Loading never executes code (only registered node constructors run),
limits the size of the text, the depth of the tree and the number of nodes,
rejects NaN and Infinity, and reports where a bad node is:
``$.children[1].radius: expected a positive number, got -2``.

Examples
--------
>>> from implicit import sphere, box
>>> from implicit.serialize import to_json, from_json
>>> part = sphere(1.0) & box(1.5)
>>> text = to_json(part)
>>> float(from_json(text)([[0.0, 0.0, 0.0]])[0])
-0.75
"""

from __future__ import annotations

import inspect
import json
from typing import Any

from .solid import Solid, load_all_kinds
from . import primitives, csg, transforms, modifiers, polyhedra, profiles, sweeps, families  # noqa: F401  (register kinds)

__all__ = ["to_dict", "to_json", "from_dict", "from_json", "MAX_DEPTH", "MAX_NODES", "MAX_CHARS", "FORMAT_KEYS"]

#: Deepest tree accepted when loading.
MAX_DEPTH = 500
#: Most nodes accepted when loading.
MAX_NODES = 100_000
#: Longest JSON text accepted when loading (characters).
MAX_CHARS = 32 * 1024 * 1024
#: Keys of a node object that are not parameters.
FORMAT_KEYS = ("kind", "children")

# Exceptions a constructor may raise on bad parameter values.
_BAD_VALUE = (TypeError, ValueError, ArithmeticError, IndexError, KeyError, AttributeError)


def to_dict(solid: Solid) -> dict:
    """The tree as plain data (dicts, lists, numbers, strings).

    Parameters
    ----------
    solid : Solid

    Returns
    -------
    dict
        ``{"kind": ..., <params>, "children": [...]}``.
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    # Iterative post-order: no recursion limit for deep trees.
    out: dict[int, dict] = {}
    stack = [(solid, False)]
    while stack:
        node, ready = stack.pop()
        if not ready:
            stack.append((node, True))
            if getattr(type(node), "serialize_children", True):
                stack.extend((c, False) for c in node.children)
            continue
        if Solid.registry.get(node.kind) is not type(node):
            raise TypeError(f"{type(node).__name__}: kind {node.kind!r} is not registered for JSON")
        params = node.to_params()
        clash = [k for k in FORMAT_KEYS if k in params]
        if clash:
            raise ValueError(f"{node.kind}: parameter names {clash} clash with the JSON format keys")
        item = {"kind": node.kind}
        item.update(params)
        if node.children and getattr(type(node), "serialize_children", True):
            item["children"] = [out[id(c)] for c in node.children]
        out[id(node)] = item
    return out[id(solid)]


def to_json(solid: Solid, *, indent: int | None = None) -> str:
    """The tree as JSON text (no NaN or Infinity).

    Examples
    --------
    >>> from implicit import sphere
    >>> to_json(sphere(2.0))
    '{"kind": "sphere", "radius": 2.0, "center": [0.0, 0.0, 0.0]}'
    """
    data = to_dict(solid)
    try:
        text = json.dumps(data, allow_nan=False)
    except ValueError as exc:
        if "Out of range float" in str(exc):
            raise ValueError("solid: a parameter is NaN or infinite and has no JSON form") from None
        raise
    if indent is None:
        return text
    return _pretty(data, int(indent), 0)


def _pretty(value, indent: int, level: int) -> str:
    """Indented JSON with arrays of plain values kept on one line."""
    pad, inner = " " * (indent * level), " " * (indent * (level + 1))
    if isinstance(value, dict) and value:
        items = [f"{inner}{json.dumps(k)}: {_pretty(v, indent, level + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list) and any(isinstance(v, (list, dict)) for v in value):
        if all(isinstance(v, list) and not any(isinstance(w, (list, dict)) for w in v) for v in value) \
                and sum(len(v) for v in value) <= 12:
            return json.dumps(value)
        items = [inner + _pretty(v, indent, level + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(value)


def _short(path: str, limit: int = 160) -> str:
    """A JSON path cut in the middle when very long (deep trees)."""
    if len(path) <= limit:
        return path
    return f"{path[:60]}...{path[-(limit - 63):]}"


def _reject_constant(name):
    raise ValueError(f"JSON: {name} is not allowed (numbers must be finite)")


def _describe(value) -> str:
    return {dict: "an object", list: "an array", str: "a string", bool: "a boolean",
            int: "a number", float: "a number", type(None): "null"}.get(type(value), type(value).__name__)


def _wrap(exc: Exception, path: str, params: dict) -> ValueError | TypeError:
    msg = str(exc) or type(exc).__name__
    key = msg.split(":", 1)[0].split(".", 1)[0].split("[", 1)[0]
    path = _short(path)
    text = f"{path}.{msg}" if key in params else f"{path}: {msg}"
    return TypeError(text) if isinstance(exc, TypeError) else ValueError(text)


def from_dict(data: Any, *, max_depth: int = MAX_DEPTH, max_nodes: int = MAX_NODES) -> Solid:
    """Rebuild a tree from `to_dict` output.

    Raises
    ------
    ValueError, TypeError
        Naming the JSON path of the first bad node, e.g.
        ``$.children[1].radius: expected a positive number, got -2``.
    """
    order = []
    stack = [(data, "$", 1)]
    while stack:
        node, path, depth = stack.pop()
        if depth > max_depth:
            raise ValueError(f"{_short(path)}: the tree is deeper than {max_depth} levels")
        if len(order) >= max_nodes:
            raise ValueError(f"{_short(path)}: the tree has more than {max_nodes} nodes")
        path_s = _short(path)
        if not isinstance(node, dict):
            raise TypeError(f"{path_s}: expected a node object, got {_describe(node)}")
        kind = node.get("kind")
        if not isinstance(kind, str):
            raise TypeError(f"{path_s}.kind: expected a node kind (a string), got {_describe(kind)}")
        cls = Solid.registry.get(kind)
        if cls is None:
            load_all_kinds()  # the kinds `import implicit` left for later
            cls = Solid.registry.get(kind)
        if cls is None:
            raise ValueError(f"{path_s}.kind: unknown node kind {kind!r}; known: {', '.join(sorted(Solid.registry))}")
        raw = node.get("children", [])
        if not isinstance(raw, list):
            raise TypeError(f"{path_s}.children: expected an array, got {_describe(raw)}")
        if raw and not getattr(cls, "takes_children", True):
            raise ValueError(f"{path_s}.children: a {kind} node is a leaf and takes no children")
        if raw and not getattr(cls, "serialize_children", True):
            raise ValueError(f"{path_s}.children: a {kind} node is rebuilt from its parameters and takes no children")
        params = {k: v for k, v in node.items() if k not in FORMAT_KEYS}
        order.append((cls, params, len(raw), path))
        stack.extend((c, f"{path}.children[{i}]", depth + 1) for i, c in enumerate(raw))
    results: list[Solid] = []
    signatures: dict[type, inspect.Signature] = {}
    for cls, params, n, path in reversed(order):
        children = results[len(results) - n:] if n else []
        if n:
            del results[len(results) - n:]
        if cls.from_params.__func__ is Solid.from_params.__func__:
            sig = signatures.get(cls)
            if sig is None:
                sig = signatures[cls] = inspect.signature(cls)
            try:
                sig.bind(*children, **params)
            except TypeError as exc:
                raise TypeError(f"{_short(path)}: {cls.kind}: {exc}") from None
        try:
            results.append(cls.from_params(tuple(children), params))
        except RecursionError:
            raise ValueError(f"{_short(path)}: the tree is too deep to build") from None
        except _BAD_VALUE as exc:
            raise _wrap(exc, path, params) from None
    return results[0]


def parse_json(text: Any, *, max_chars: int = MAX_CHARS) -> Any:
    """Parse JSON text safely: size limit, no NaN/Infinity, nesting errors as ValueError."""
    if isinstance(text, (bytes, bytearray)):
        if len(text) > max_chars:
            raise ValueError(f"JSON: the text is longer than {max_chars} characters")
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ValueError(f"JSON: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    if not isinstance(text, str):
        raise TypeError(f"JSON: expected text, got {type(text).__name__}")
    if len(text) > max_chars:
        raise ValueError(f"JSON: the text is longer than {max_chars} characters")
    try:
        return json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as exc:
        raise ValueError(f"JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    except RecursionError:
        raise ValueError("JSON: nested too deeply") from None


def from_json(text_or_dict: Any, *, max_depth: int = MAX_DEPTH, max_nodes: int = MAX_NODES,
              max_chars: int = MAX_CHARS) -> Solid:
    """Rebuild a tree from JSON text (or its already-parsed dict).

    Parameters
    ----------
    text_or_dict : str, bytes or dict
        JSON text, or data already parsed from it.
    max_depth, max_nodes, max_chars : int
        Limits on hostile input.

    Examples
    --------
    >>> s = from_json('{"kind": "sphere", "radius": -2}')
    Traceback (most recent call last):
    ...
    ValueError: $.radius: expected a positive number, got -2
    """
    if isinstance(text_or_dict, (str, bytes, bytearray)):
        data = parse_json(text_or_dict, max_chars=max_chars)
    else:
        data = text_or_dict   # already parsed

    return from_dict(data, max_depth=max_depth, max_nodes=max_nodes)
