"""Bill of materials of an assembly: items, families, materials, volumes and masses.

Parts that are the same solid placed differently are one item counted
several times: the key of a part is its CSG tree (the JSON form, where a
family member is just its family and parameter values) with the rigid
motions that place it taken off.  Each item's volume comes from
`mass_properties` (extrapolated meshes, with its error estimate), its mass
from the material's density.  The same rows serve a drawing's parts list.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["MATERIALS", "BomItem", "BillOfMaterials", "bill_of_materials", "part_key"]

#: Densities of common materials, kg / m^3.
MATERIALS = {
    "steel": 7850.0, "stainless steel": 8000.0, "cast iron": 7200.0, "aluminium": 2700.0,
    "brass": 8500.0, "copper": 8960.0, "titanium": 4430.0, "ABS": 1050.0, "PLA": 1240.0,
    "nylon": 1150.0, "polycarbonate": 1200.0,
}


@dataclass(frozen=True)
class BomItem:
    """One row: identical parts counted together.

    `mass` is per part (kg, None without a material); `total_mass` for all of them.
    """

    item: int
    names: list
    family: str
    parameters: dict
    material: str
    density: float | None
    volume: float
    volume_error: float
    mass: float | None
    count: int

    @property
    def total_mass(self) -> float | None:
        return None if self.mass is None else self.mass * self.count

    def to_dict(self) -> dict:
        return {"item": self.item, "parts": self.names, "family": self.family, "parameters": self.parameters,
                "material": self.material, "density": self.density, "volume": self.volume,
                "volume_error": self.volume_error, "mass": self.mass, "count": self.count,
                "total_mass": self.total_mass}


@dataclass(frozen=True)
class BillOfMaterials:
    """The rows of a bill of materials; lengths in `units`, masses in kg."""

    items: list
    units: str

    @property
    def total_mass(self) -> float | None:
        masses = [it.total_mass for it in self.items]
        return None if any(m is None for m in masses) else float(sum(masses))

    @property
    def part_count(self) -> int:
        return sum(it.count for it in self.items)

    def to_dict(self) -> dict:
        return {"units": self.units, "items": [it.to_dict() for it in self.items], "parts": self.part_count,
                "total_mass": self.total_mass}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2)

    def rows(self) -> list:
        """Header and rows of text, as the parts list of a drawing shows them."""
        head = ["item", "part", "family", "parameters", "material", "density kg/m3", f"volume {self.units}3",
                "mass kg", "count", "total mass kg"]
        out = [head]
        for it in self.items:
            params = " ".join(f"{k}={_fmt(v)}" for k, v in it.parameters.items())
            out.append([str(it.item), ", ".join(it.names), it.family, params, it.material,
                        "" if it.density is None else f"{it.density:g}", f"{it.volume:.6g}",
                        "" if it.mass is None else f"{it.mass:.6g}", str(it.count),
                        "" if it.total_mass is None else f"{it.total_mass:.6g}"])
        return out

    def table(self) -> str:
        rows = self.rows()
        widths = [max(len(r[k]) for r in rows) for k in range(len(rows[0]))]
        lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
        lines.insert(1, "  ".join("-" * w for w in widths))
        tm = self.total_mass
        lines.append(f"{self.part_count} parts in {len(self.items)} items"
                     + ("" if tm is None else f"; total mass {tm:.6g} kg"))
        return "\n".join(lines)

    def to_csv(self) -> str:
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(self.rows())
        return buf.getvalue()


def _fmt(v):
    return f"{v:g}" if isinstance(v, float) else str(v)


def _strip_rigid(solid):
    """The solid under the rigid motions (rotations and translations) that place it."""
    from implicit.transforms import Affine

    s = solid
    while isinstance(s, Affine):
        A = s.matrix
        if not (np.allclose(A @ A.T, np.eye(3), atol=1e-9) and np.linalg.det(A) > 0):
            break
        s = s.children[0]
    return s


def part_key(solid) -> str:
    """A text equal for two placements of the same part."""
    from implicit.serialize import to_dict

    return json.dumps(to_dict(_strip_rigid(solid)), sort_keys=True)


def _material(spec, name):
    if spec is None:
        return "", None
    if isinstance(spec, str):
        if spec not in MATERIALS:
            raise ValueError(f"materials[{name!r}]: unknown material {spec!r}; known: {', '.join(MATERIALS)} "
                             f"(or give (name, density in kg/m^3))")
        return spec, MATERIALS[spec]
    if isinstance(spec, (tuple, list)) and len(spec) == 2 and isinstance(spec[0], str):
        rho = spec[1]
        if isinstance(rho, bool) or not isinstance(rho, (int, float)) or not (math.isfinite(rho) and rho > 0):
            raise ValueError(f"materials[{name!r}]: expected a positive density in kg/m^3, got {rho!r}")
        return spec[0], float(rho)
    raise TypeError(f"materials[{name!r}]: expected a material name or (name, density), got {spec!r}")


def bill_of_materials(parts, materials=None, *, default_material=None, units="mm", tolerance=1e-3,
                      resolution=None):
    """Bill of materials of an assembly.

    Parameters
    ----------
    parts : dict of str -> Solid
        Named, placed parts (an assembly file's ``parts``).
    materials : dict of str -> material, optional
        Part name -> a name of `MATERIALS` or ``(name, density kg/m^3)``.
    default_material : material, optional
        For parts missing from `materials` (else they have no mass).
    units : str
        Length unit of the model (see `mass_properties`).
    tolerance : float
        Relative volume error to reach for each distinct part (see
        `mass_properties`; a thin plate needs fine cells).
    resolution : int, optional
        Cells across each distinct part instead of a tolerance.

    Returns
    -------
    BillOfMaterials

    Examples
    --------
    >>> from implicit import box
    >>> parts = {"a": box(10.0), "b": box(10.0).translate((20, 0, 0))}
    >>> bom = bill_of_materials(parts, default_material="aluminium")
    >>> it = bom.items[0]
    >>> it.count, round(it.volume, 6), round(it.mass, 6)            # 1000 mm^3 of aluminium
    (2, 1000.0, 0.0027)
    """
    from implicit import Solid
    from implicit.families import FamilyInstance

    from .mass import UNITS, mass_properties

    if not isinstance(parts, dict) or not parts:
        raise TypeError("parts: expected a non-empty dict of name -> Solid")
    for name, s in parts.items():
        if not isinstance(s, Solid):
            raise TypeError(f"parts[{name!r}]: expected a Solid, got {type(s).__name__}")
    materials = {} if materials is None else materials
    if not isinstance(materials, dict):
        raise TypeError(f"materials: expected a dict of part name -> material, got {type(materials).__name__}")
    unknown = sorted(set(materials) - set(parts))
    if unknown:
        raise ValueError(f"materials: no part named {unknown[0]!r} in the assembly")
    if units not in UNITS:
        raise ValueError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
    specs = {n: _material(materials.get(n, default_material), n) for n in parts}
    groups: dict = {}
    for name, s in parts.items():
        key = (part_key(s), specs[name])
        groups.setdefault(key, []).append(name)
    items = []
    for k, ((_, (mat, rho)), names) in enumerate(groups.items(), 1):
        inner = _strip_rigid(parts[names[0]])
        fam, params = "", {}
        node = inner
        while not isinstance(node, FamilyInstance) and len(node.children) == 1 and node.kind in ("affine",):
            node = node.children[0]
        if isinstance(node, FamilyInstance):
            fam, params = node.family_name, node.values
        else:
            fam = f"{inner.kind} ({inner.count_primitives()} primitives)"
        if resolution is not None:
            props = mass_properties(inner, resolution=resolution, units=units, density=rho or 1.0)
        else:
            props = mass_properties(inner, tolerance=tolerance, units=units, density=rho or 1.0)
        mass = float(props.mass) if rho is not None else None
        items.append(BomItem(k, names, fam, params, mat, rho, float(props.volume), float(props.error.volume),
                             mass, len(names)))
    return BillOfMaterials(items, units)
