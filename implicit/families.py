"""Primitive instancing: parameterised part families.

A *family* is a named, parameterised part (a bolt, a flanged pipe, a
bracket) with typed, validated parameters: name, type, default, unit, range
and description.  `instance(name, **params)` checks the values and the
part's geometry (holes must fit in the plate, ...) and returns a
`FamilyInstance`: a node whose single child is the built CSG tree and whose
params hold the family name and every parameter value, so `implicad info`
shows them and the JSON form stores just the family call.

Examples
--------
>>> from implicit.families import instance
>>> plate = instance("hole_plate", length=80, width=40, rows=1, cols=3)
>>> plate.params["family"]
'hole_plate'
>>> instance("hole_plate", hole_diameter=-2)
Traceback (most recent call last):
...
ValueError: hole_plate.hole_diameter: expected a positive number, got -2
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .csg import difference, union
from .polyhedra import prism
from .primitives import box, cylinder
from .solid import Solid

__all__ = ["Parameter", "Family", "FamilyInstance", "families", "family", "instance", "label", "register_family"]


@dataclass(frozen=True)
class Parameter:
    """One typed parameter of a family.

    Attributes
    ----------
    name : str
    type : type
        ``float``, ``int`` or ``bool``.
    default : float, int or bool
    unit : str
        ``"mm"``, ``"count"``, ``""`` ...
    minimum, maximum : float or None
        Allowed range; `exclusive_minimum` makes the lower end open
        (``minimum=0, exclusive_minimum=True`` is "positive").
    description : str
    """

    name: str
    type: type
    default: Any
    unit: str = "mm"
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: bool = False
    description: str = ""

    def range_text(self) -> str:
        """The allowed range as text, e.g. ``> 0`` or ``[1, 20]``."""
        lo, hi = self.minimum, self.maximum
        if lo is None and hi is None:
            return "any"
        if hi is None:
            return f"{'>' if self.exclusive_minimum else '>='} {lo:g}"
        if lo is None:
            return f"<= {hi:g}"
        return f"{'(' if self.exclusive_minimum else '['}{lo:g}, {hi:g}]"

    def _expected(self) -> str:
        if self.type is bool:
            return "true or false"
        noun = "an integer" if self.type is int else "a number"
        if self.minimum == 0 and self.maximum is None:
            if self.exclusive_minimum:
                return "a positive integer" if self.type is int else "a positive number"
            return f"a non-negative {'integer' if self.type is int else 'number'}"
        rng = self.range_text()
        return noun if rng == "any" else f"{noun} {rng}" if rng[0] in "<>" else f"{noun} in {rng}"

    def validate(self, family_name: str, value: Any):
        """Return `value` converted to the parameter's type, or raise naming
        ``family.parameter``."""
        where = f"{family_name}.{self.name}"
        if self.type is bool:
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{where}: expected true or false, got {value!r}")
            return bool(value)
        bad_kind = isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.integer, np.floating))
        if bad_kind:
            raise TypeError(f"{where}: expected {self._expected()}, got {value!r}")
        if self.type is int:
            if float(value) != math.floor(float(value)) or not math.isfinite(float(value)):
                raise ValueError(f"{where}: expected {self._expected()}, got {value!r}")
            out = int(value)
        else:
            out = float(value)
            if not math.isfinite(out):
                raise ValueError(f"{where}: expected {self._expected()}, got {value!r}")
        lo, hi = self.minimum, self.maximum
        if (lo is not None and (out < lo or (self.exclusive_minimum and out == lo))) or (hi is not None and out > hi):
            raise ValueError(f"{where}: expected {self._expected()}, got {value!r}")
        return out

    def describe(self) -> dict:
        """Plain-data description (for listings and JSON)."""
        return {"name": self.name, "type": self.type.__name__, "default": self.default, "unit": self.unit,
                "range": self.range_text(), "description": self.description}


@dataclass(frozen=True)
class Family:
    """A parameterised part: its parameters, a validity check and a builder."""

    name: str
    description: str
    parameters: tuple
    build: Callable[..., Solid]
    check: Callable[..., None] | None = None

    def resolve(self, params: dict) -> dict:
        """Defaults filled in, every value validated, geometry checked."""
        if not isinstance(params, dict):
            raise TypeError(f"{self.name}: expected parameters as a mapping, got {type(params).__name__}")
        known = {p.name: p for p in self.parameters}
        for key in params:
            if key not in known:
                raise ValueError(f"{self.name}: unknown parameter {key!r}; parameters: {', '.join(known)}")
        values = {name: p.validate(self.name, params.get(name, p.default)) for name, p in known.items()}
        if self.check is not None:
            self.check(**values)
        return values

    def describe(self) -> dict:
        return {"name": self.name, "description": self.description,
                "parameters": [p.describe() for p in self.parameters]}


_FAMILIES: dict[str, Family] = {}


def register_family(fam: Family) -> Family:
    """Add `fam` to the registry (its name must be new)."""
    if not isinstance(fam, Family):
        raise TypeError(f"family: expected a Family, got {type(fam).__name__}")
    if fam.name in _FAMILIES:
        raise ValueError(f"family: {fam.name!r} is already registered")
    _FAMILIES[fam.name] = fam
    return fam


def families() -> dict[str, Family]:
    """Every registered family by name, in registration order.

    Examples
    --------
    >>> from implicit.families import families
    >>> "hex_bolt" in families()
    True
    """
    return dict(_FAMILIES)


def family(name: str) -> Family:
    """The family called `name`, or a ValueError listing the known ones."""
    if not isinstance(name, str):
        raise TypeError(f"family: expected a family name, got {name!r}")
    try:
        return _FAMILIES[name]
    except KeyError:
        raise ValueError(f"unknown family {name!r}; known: {', '.join(_FAMILIES)}") from None


#: Labels collected while families build (a stack: a builder may build other families).
_BUILDING: list = []


def label(solid: Solid, name: str, faces: dict | None = None) -> Solid:
    """Name the faces of `solid`, a node a family's builder makes; returns `solid`.

    The faces of the node's leaves (``wall``, ``top``, ``+x`` ... see
    `implicit.facets.FacetField`) are then called ``name.<face>``, or
    ``name.<faces[face]>`` where `faces` renames one (a value with a dot is a
    whole name, for a face shared with another node); a leaf with a single
    face (a sphere) is called `name`.  An inner label wins over an outer one.
    The names belong to the family instance being built: the JSON form keeps
    only the family call, and rebuilding the instance labels its tree again.

    Raises
    ------
    ValueError
        Outside a family's builder, or for an empty or dotted name.

    Examples
    --------
    >>> from implicit.families import instance
    >>> plate = instance("hole_plate", rows=1, cols=2)
    >>> sorted({name for _, name, _ in plate.labels})
    ['hole_1', 'hole_2', 'plate']
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"label: expected a Solid, got {type(solid).__name__}")
    if not isinstance(name, str) or not name or "." in name or name != name.strip():
        raise ValueError(f"label: expected a name without dots or spaces around it, got {name!r}")
    faces = dict(faces or {})
    for key, value in faces.items():
        if not isinstance(key, str) or not isinstance(value, str) or not value.strip(". "):
            raise ValueError(f"label: faces must map face names to names, got {key!r}: {value!r}")
    if not _BUILDING:
        raise ValueError("label: faces are named inside a family's builder (the instance carries the names)")
    _BUILDING[-1].append((solid, name, faces))
    return solid


class FamilyInstance(Solid):
    """One member of a family: the built tree as the single child.

    `params` is ``{"family": name, "params": {every parameter: value}}``;
    the JSON form stores only that (the child is rebuilt on loading).
    `labels` holds the face names the builder gave its nodes (`label`).
    """

    kind = "family"
    serialize_children = False
    __slots__ = ("_labels",)

    def __init__(self, name: str, params: dict | None = None):
        fam = family(name)
        values = fam.resolve({} if params is None else params)
        _BUILDING.append([])
        try:
            built = fam.build(**values)
        finally:
            labels = _BUILDING.pop()
        super().__init__((built,), {"family": fam.name, "params": values}, built.bounds,
                         exact=built.exact, lipschitz=built.lipschitz)
        object.__setattr__(self, "_labels", tuple(labels))

    @property
    def labels(self) -> tuple:
        """``(node, name, faces)`` for every node of the built tree its builder named (`label`)."""
        return self._labels

    @classmethod
    def from_params(cls, children, params):
        """Rebuild from ``{"family": ..., "params": {...}}`` (children ignored)."""
        extra = set(params) - {"family", "params"}
        if extra:
            raise ValueError(f"unexpected keys {sorted(extra)} in a family node; expected 'family' and 'params'")
        return cls(params.get("family"), params.get("params", {}))

    @property
    def family_name(self) -> str:
        return self._params["family"]

    @property
    def values(self) -> dict:
        """The parameter values (a copy)."""
        return dict(self._params["params"])

    def _label(self) -> str:
        args = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v!r}"
                         for k, v in self._params["params"].items())
        return f"family {self._params['family']}({args})"

    def __repr__(self) -> str:
        args = "".join(f", {k}={v!r}" for k, v in self._params["params"].items())
        return f"instance({self._params['family']!r}{args})"

    def _evaluate(self, p):
        return self._children[0]._evaluate(p)

    def _value_bounds(self, lo, hi):
        return self._children[0]._value_bounds(lo, hi)


def instance(name: str, **params) -> Solid:
    """A member of family `name` with `params` (defaults for the rest).

    Raises
    ------
    ValueError, TypeError
        For an unknown family or parameter, a value of the wrong type or out
        of range (``hole_plate.hole_diameter: expected a positive number,
        got -2``), or a geometry that does not fit.

    Examples
    --------
    >>> from implicit.families import instance
    >>> bolt = instance("hex_bolt", diameter=8, length=30)
    >>> round(float(bolt([[0.0, 0.0, -10.0]])[0]), 6)
    -4.0
    """
    return FamilyInstance(name, params)


# ---------------------------------------------------------------------------
# the families
# ---------------------------------------------------------------------------

def _pos(name, default, description, unit="mm"):
    return Parameter(name, float, default, unit, 0.0, None, True, description)


def _count(name, default, description, minimum=1, maximum=64):
    return Parameter(name, int, default, "count", minimum, maximum, False, description)


def _fail(family_name, message):
    raise ValueError(f"{family_name}: {message}")


# hex_bolt -----------------------------------------------------------------

def _hex_bolt_check(diameter, length, head_height, across_flats):
    if across_flats <= diameter:
        _fail("hex_bolt", f"across_flats ({across_flats:g}) must exceed the shank diameter ({diameter:g})")


def _hex_bolt(diameter, length, head_height, across_flats):
    circum = across_flats / math.sqrt(3.0)
    angles = np.radians(np.arange(6) * 60.0)
    hexagon = np.column_stack([circum * np.cos(angles), circum * np.sin(angles)])
    head = label(prism(hexagon, head_height, center=(0.0, 0.0, head_height / 2)), "head")
    shank = label(cylinder(diameter / 2, length, center=(0.0, 0.0, -length / 2)), "shank",
                  {"top": "top", "bottom": "end"})
    return union(head, shank)


register_family(Family(
    "hex_bolt", "Hexagon-head bolt: the head on z >= 0, the plain shank along -z.",
    (_pos("diameter", 10.0, "shank diameter"),
     _pos("length", 40.0, "shank length below the head"),
     _pos("head_height", 7.0, "head height"),
     _pos("across_flats", 17.0, "head width across flats")),
    _hex_bolt, _hex_bolt_check))


# flanged_pipe ------------------------------------------------------------

def _flanged_pipe_check(outer_diameter, wall, length, flange_diameter, flange_thickness, bolt_holes,
                        hole_diameter, bolt_circle):
    name = "flanged_pipe"
    if wall >= outer_diameter / 2:
        _fail(name, f"wall ({wall:g}) must be less than half the outer_diameter ({outer_diameter / 2:g})")
    if flange_diameter <= outer_diameter:
        _fail(name, f"flange_diameter ({flange_diameter:g}) must exceed outer_diameter ({outer_diameter:g})")
    if 2 * flange_thickness > length:
        _fail(name, f"two flanges ({2 * flange_thickness:g}) do not fit in length {length:g}")
    if bolt_holes:
        if bolt_circle / 2 - hole_diameter / 2 <= outer_diameter / 2:
            _fail(name, f"bolt holes (diameter {hole_diameter:g} on bolt_circle {bolt_circle:g}) cut into the pipe")
        if bolt_circle / 2 + hole_diameter / 2 >= flange_diameter / 2:
            _fail(name, f"bolt holes (diameter {hole_diameter:g} on bolt_circle {bolt_circle:g}) do not fit in "
                        f"the flange (diameter {flange_diameter:g})")
        if bolt_holes > 1 and bolt_circle * math.sin(math.pi / bolt_holes) <= hole_diameter:
            _fail(name, f"{bolt_holes} bolt holes of diameter {hole_diameter:g} overlap on bolt_circle {bolt_circle:g}")


def _flanged_pipe(outer_diameter, wall, length, flange_diameter, flange_thickness, bolt_holes,
                  hole_diameter, bolt_circle):
    z_flange = length / 2 - flange_thickness / 2
    body = union(label(cylinder(outer_diameter / 2, length), "pipe", {"wall": "outside", "top": "top_flange.face",
                                                                      "bottom": "bottom_flange.face"}),
                 label(cylinder(flange_diameter / 2, flange_thickness, center=(0, 0, z_flange)), "top_flange",
                       {"wall": "rim", "top": "face", "bottom": "back"}),
                 label(cylinder(flange_diameter / 2, flange_thickness, center=(0, 0, -z_flange)), "bottom_flange",
                       {"wall": "rim", "top": "back", "bottom": "face"}))
    tools = [label(cylinder(outer_diameter / 2 - wall, 2 * length), "pipe", {"wall": "bore"})]
    angles = 2 * np.pi * np.arange(bolt_holes) / max(bolt_holes, 1)
    for i, a in enumerate(angles):  # one tool per hole (a handful of nodes, not points)
        tools.append(label(cylinder(hole_diameter / 2, length * 1.01,
                                    center=(bolt_circle / 2 * math.cos(a), bolt_circle / 2 * math.sin(a), 0.0)),
                           f"hole_{i + 1}"))
    return difference(body, *tools)


register_family(Family(
    "flanged_pipe", "Straight pipe along z with a bolted flange at each end.",
    (_pos("outer_diameter", 60.0, "pipe outer diameter"),
     _pos("wall", 5.0, "pipe wall thickness"),
     _pos("length", 200.0, "overall length"),
     _pos("flange_diameter", 120.0, "flange outer diameter"),
     _pos("flange_thickness", 12.0, "flange thickness"),
     _count("bolt_holes", 4, "bolt holes per flange", minimum=0),
     _pos("hole_diameter", 10.0, "bolt hole diameter"),
     _pos("bolt_circle", 90.0, "bolt circle diameter")),
    _flanged_pipe, _flanged_pipe_check))


# l_bracket ----------------------------------------------------------------

def _leg_holes(span, n):
    """Hole centres along a leg span ``(start, end)``: evenly spaced."""
    start, end = span
    return start + (end - start) * (np.arange(n) + 1) / (n + 1)


def _l_bracket_check(width, leg_a, leg_b, thickness, hole_diameter, holes_per_leg):
    name = "l_bracket"
    if thickness >= min(leg_a, leg_b):
        _fail(name, f"thickness ({thickness:g}) must be less than both legs ({leg_a:g}, {leg_b:g})")
    if holes_per_leg:
        if hole_diameter >= width:
            _fail(name, f"hole_diameter ({hole_diameter:g}) must be less than width ({width:g})")
        for leg, length in (("leg_a", leg_a), ("leg_b", leg_b)):
            pitch = (length - thickness) / (holes_per_leg + 1)
            if pitch <= hole_diameter:
                _fail(name, f"{holes_per_leg} holes of diameter {hole_diameter:g} do not fit on {leg} "
                            f"({length:g} long, hole pitch {pitch:g})")


#: Face names of the bracket's two legs (the base along +x, the upright along +z).
_BRACKET_BASE = {"-z": "base_bottom", "+z": "base_top", "+x": "base_end", "-x": "back", "+y": "side_2",
                 "-y": "side_1"}
_BRACKET_UPRIGHT = {"+z": "upright_top", "+x": "upright_front", "-x": "back", "-z": "base_bottom", "+y": "side_2",
                    "-y": "side_1"}


def _l_bracket(width, leg_a, leg_b, thickness, hole_diameter, holes_per_leg):
    base = label(box((leg_a, width, thickness), center=(leg_a / 2, width / 2, thickness / 2)), "bracket",
                 _BRACKET_BASE)
    upright = label(box((thickness, width, leg_b), center=(thickness / 2, width / 2, leg_b / 2)), "bracket",
                    _BRACKET_UPRIGHT)
    tools = []
    for i, x in enumerate(_leg_holes((thickness, leg_a), holes_per_leg)):
        tools.append(label(cylinder(hole_diameter / 2, 3 * thickness, center=(x, width / 2, thickness / 2)),
                           f"hole_{i + 1}"))
    for i, z in enumerate(_leg_holes((thickness, leg_b), holes_per_leg)):
        tools.append(label(cylinder(hole_diameter / 2, 3 * thickness, center=(thickness / 2, width / 2, z),
                                    axis=(1.0, 0.0, 0.0)), f"hole_{holes_per_leg + i + 1}"))
    body = union(base, upright)
    return difference(body, *tools) if tools else body


register_family(Family(
    "l_bracket", "L-shaped angle bracket: leg_a along +x, leg_b along +z, holes through both legs.",
    (_pos("width", 40.0, "bracket width along y"),
     _pos("leg_a", 60.0, "horizontal leg length (x)"),
     _pos("leg_b", 50.0, "vertical leg length (z)"),
     _pos("thickness", 5.0, "plate thickness"),
     _pos("hole_diameter", 6.0, "hole diameter"),
     _count("holes_per_leg", 2, "holes in each leg", minimum=0, maximum=32)),
    _l_bracket, _l_bracket_check))


# hole_plate ---------------------------------------------------------------

def _hole_centres(length, width, margin, rows, cols):
    xs = np.linspace(-length / 2 + margin, length / 2 - margin, cols) if cols > 1 else np.zeros(1)
    ys = np.linspace(-width / 2 + margin, width / 2 - margin, rows) if rows > 1 else np.zeros(1)
    gx, gy = np.meshgrid(xs, ys, indexing="xy")
    return np.column_stack([gx.ravel(), gy.ravel()])


def _hole_plate_check(length, width, thickness, hole_diameter, rows, cols, margin):
    name = "hole_plate"
    r = hole_diameter / 2
    for size, count, what in ((length, cols, "length"), (width, rows, "width")):
        if count > 1:
            if 2 * margin >= size:
                _fail(name, f"margin ({margin:g}) leaves no room along the {what} ({size:g})")
            pitch = (size - 2 * margin) / (count - 1)
            if pitch <= hole_diameter:
                _fail(name, f"{count} holes of diameter {hole_diameter:g} overlap along the {what} "
                            f"(pitch {pitch:g})")
            if margin <= r:
                _fail(name, f"holes of diameter {hole_diameter:g} at margin {margin:g} break through the edge")
        elif hole_diameter >= size:
            _fail(name, f"hole_diameter ({hole_diameter:g}) does not fit in the {what} ({size:g})")


def _hole_plate(length, width, thickness, hole_diameter, rows, cols, margin):
    plate = label(box((length, width, thickness)), "plate", {"+z": "top", "-z": "bottom"})
    holes = [label(cylinder(hole_diameter / 2, 3 * thickness, center=(x, y, 0.0)), f"hole_{i + 1}")
             for i, (x, y) in enumerate(_hole_centres(length, width, margin, rows, cols))]
    return difference(plate, *holes)


register_family(Family(
    "hole_plate", "Rectangular plate centred on the origin with a rows x cols grid of through holes.",
    (_pos("length", 100.0, "plate length along x"),
     _pos("width", 60.0, "plate width along y"),
     _pos("thickness", 5.0, "plate thickness along z"),
     _pos("hole_diameter", 8.0, "hole diameter"),
     _count("rows", 2, "rows of holes (along y)"),
     _count("cols", 3, "columns of holes (along x)"),
     _pos("margin", 12.0, "distance from the plate edge to the outer hole centres")),
    _hole_plate, _hole_plate_check))
