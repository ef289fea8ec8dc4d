"""`implicad mass MODEL`: volume, mass, area, centroid and inertia with error bounds.

A model file (``.py`` / ``.json``) is meshed and integrated at levels chosen for
the tolerance (meshes with sharp edges rebuilt), or at ``--resolution`` /
``--voxel-size`` with Richardson extrapolation (see `spatial.analysis.mass`); a
mesh file (``.stl``, ``.ply``, ``.obj``, ``.vtp``, ``.vtk``) is integrated exactly.  ``--json`` prints one object with
``volume``, ``mass``, ``area``, ``centroid``, ``inertia``, ``inertia_origin``,
``principal_moments``, ``principal_axes``, ``error`` (same keys, absolute
bounds), ``voxel_size``, ``units`` and ``density``.
"""

from __future__ import annotations

import json
import os

NAME = "mass"
HELP = "volume, mass, area, centroid and inertia of a model, with error bounds"
DESCRIPTION = (
    "Compute mass properties: volume, mass (density x volume), boundary area, centroid, "
    "inertia tensor about the centroid and about the origin, principal moments and axes, "
    "each with an absolute error bound. Lengths are in --units; --density is in kg/m^3, "
    "so the mass is in kg and inertia in kg*units^2."
)

MESH_SUFFIXES = (".stl", ".ply", ".obj", ".vtp", ".vtk")


def add_arguments(parser) -> None:
    from ..analysis.mass import UNITS

    parser.add_argument("model", metavar="MODEL", help="model file (.py or .json) or mesh file (.stl, .ply, ...)")
    parser.add_argument("--density", type=float, default=1.0, help="density in kg/m^3 (default 1)")
    parser.add_argument("--units", default=None, choices=sorted(UNITS),
                        help="length unit of the model (default: the units the model declares; m when it declares none, "
                             "said on the first line)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--voxel-size", type=float, metavar="H", help="finest cell size")
    group.add_argument("--resolution", type=int, metavar="N", help="finest cells across the model")
    group.add_argument("--tolerance", type=float, metavar="T",
                       help="relative volume error to reach (default 1e-4)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def load_target(path):
    """A mesh for mesh files, else the model's solid."""
    from .common import load_target as _load

    return _load(path)


def load_target_units(path):
    """``(mesh or solid, declared units or None)``."""
    from .common import is_mesh_file, load_target as _load

    if is_mesh_file(path):
        return _load(path), None
    from implicit.models import load_model_units

    return load_model_units(path)


def _fmt(v) -> str:
    return f"{v:.9g}"


def table(props) -> str:
    """The properties as an aligned text table with their error bounds."""
    u = props.units
    e = props.error
    rows = [
        ("volume", _fmt(props.volume), f"{e.volume:.2g}", f"{u}^3"),
        ("mass", _fmt(props.mass), f"{e.mass:.2g}", "kg"),
        ("area", _fmt(props.area), f"{e.area:.2g}", f"{u}^2"),
    ]
    for i, axis in enumerate("xyz"):
        rows.append((f"centroid {axis}", _fmt(props.centroid[i]), f"{e.centroid[i]:.2g}", u))
    names = ["xx", "yy", "zz", "xy", "yz", "xz"]
    idx = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)]
    for n, (i, j) in zip(names, idx):
        rows.append((f"I{n} (centroid)", _fmt(props.inertia[i, j]), f"{e.inertia[i, j]:.2g}", props.inertia_unit))
    for n, (i, j) in zip(names, idx):
        rows.append((f"I{n} (origin)", _fmt(props.inertia_origin[i, j]), f"{e.inertia_origin[i, j]:.2g}",
                     props.inertia_unit))
    for k in range(3):
        ax = props.principal_axes[k]
        rows.append((f"principal I{k + 1}", _fmt(props.principal_moments[k]), f"{e.principal_moments[k]:.2g}",
                     f"{props.inertia_unit}  axis ({ax[0]:+.6f}, {ax[1]:+.6f}, {ax[2]:+.6f})"))
    w0 = max(len(r[0]) for r in rows)
    w1 = max(len(r[1]) for r in rows)
    w2 = max(len(r[2]) for r in rows)
    lines = [f"{'quantity':<{w0}}  {'value':>{w1}}  {'+/-':>{w2}}  unit"]
    lines += [f"{a:<{w0}}  {b:>{w1}}  {c:>{w2}}  {d}" for a, b, c, d in rows]
    lines.append(f"density {props.density:g} kg/m^3, units {u}, voxel size {props.voxel_size:.4g} ({props.method})")
    return "\n".join(lines)


def run(args) -> int:
    from implicit import Solid

    from ..analysis.mass import mass_properties

    target, declared = load_target_units(args.model)
    units, assumed = (args.units, False) if args.units else ((declared, False) if declared else ("m", True))
    kw = {}
    if isinstance(target, Solid):
        kw = {"voxel_size": args.voxel_size, "resolution": args.resolution, "tolerance": args.tolerance}
        kw = {k: v for k, v in kw.items() if v is not None}
    elif any(v is not None for v in (args.voxel_size, args.resolution, args.tolerance)):
        raise ValueError(f"{args.model}: a mesh file is integrated exactly; --voxel-size, --resolution and "
                         "--tolerance apply to model files only")
    if isinstance(target, Solid):
        from .common import progress_of

        kw["progress"] = progress_of(args)       # the meshers mass_properties picks (sharp edges or plain)
    from ..analysis.mass import ToleranceError

    try:
        props = mass_properties(target, density=args.density, units=units, **kw)
    except ToleranceError as exc:
        from . import NoResult

        raise NoResult(str(exc)) from None
    source = ("solid volume (extrapolated mesh integrals)" if isinstance(target, Solid)
              else "mesh volume (exact integral over its triangles)")
    if args.json:
        d = props.to_dict()
        keys = ["volume", "mass", "area", "centroid", "inertia", "inertia_origin", "principal_moments",
                "principal_axes", "error", "voxel_size", "units", "density", "mass_unit", "inertia_unit", "method"]
        out = {k: d[k] for k in keys}
        out["units_assumed"] = assumed
        out["volume_of"] = "solid" if isinstance(target, Solid) else "mesh"
        print(json.dumps(out, indent=2))
    else:
        if assumed:
            print(f"units: m assumed (the model declares none; pass --units or write units = \"mm\" in the model)")
        else:
            print(f"units: {units} ({'given with --units' if args.units else 'declared by the model'})")
        print(f"what:  {source}")
        print(table(props))
    return 0
