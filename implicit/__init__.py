"""implicad's function representation: solids as CSG trees of signed distances.

Examples
--------
>>> from implicit import sphere, box, cylinder
>>> part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0))
>>> part.count_primitives()
3
"""

from .solid import Solid, INFINITE_BOUNDS, register_kind_loader as _register_kind_loader
from .primitives import (
    halfspace, sphere, box, rounded_box, cylinder, cone, frustum, torus, ellipsoid, capsule,
)
from .polyhedra import convex_polyhedron, pyramid, wedge, prism
from .csg import (
    union, intersection, difference, complement,
    smooth_union, smooth_intersection, smooth_difference,
)
from .transforms import translate, rotate, scale, mirror, affine, rotation_matrix
from .modifiers import offset, shell
from .sweeps import Profile, circle, rectangle, polygon, extrude, revolve
from .families import families, instance
from .serialize import to_json, from_json
from .models import load_model, load_assembly
from . import library  # noqa: F401  (registers the part library's families with `families`)

__all__ = [
    "Solid", "INFINITE_BOUNDS",
    "halfspace", "sphere", "box", "rounded_box", "cylinder", "cone", "frustum", "torus",
    "ellipsoid", "capsule", "convex_polyhedron", "pyramid", "wedge", "prism",
    "Profile", "circle", "rectangle", "polygon", "extrude", "revolve",
    "families", "instance", "to_json", "from_json", "load_model", "load_assembly",
    "union", "intersection", "difference", "complement",
    "smooth_union", "smooth_intersection", "smooth_difference",
    "translate", "rotate", "scale", "mirror", "affine", "rotation_matrix",
    "offset", "shell",
    "curve_profile", "revolve_curve", "extrude_curve", "sweep", "thicken", "surface_solid", "volume_solid",
    "star_solid", "fit_radial_function",
]

# Solids from parametric curves, surfaces and volumes (and scipy, which they need) load when one
# of their names is first read here, or when a decoded tree holds one of their kinds.
_LAZY = {
    "curve_profile": "parametric_solids", "revolve_curve": "parametric_solids",
    "extrude_curve": "parametric_solids", "sweep": "parametric_solids", "thicken": "parametric_solids",
    "surface_solid": "parametric_solids", "volume_solid": "parametric_solids",
    "star_solid": "star_solids", "fit_radial_function": "star_solids",
}


def _load_later_kinds():
    from . import parametric_solids, star_solids  # noqa: F401  (their classes register their kinds)


def __getattr__(name):
    if name not in _LAZY:
        raise AttributeError(f"module 'implicit' has no attribute {name!r}")
    _load_later_kinds()
    from . import parametric_solids, star_solids

    value = getattr(parametric_solids if _LAZY[name] == "parametric_solids" else star_solids, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


_register_kind_loader(_load_later_kinds)

# Last: the compiled evaluator registers itself with the nodes (it needs numba).
try:
    from . import evaluate as _evaluate  # noqa: E402,F401
except ImportError as _exc:  # pragma: no cover - numba missing: numpy evaluation only
    if getattr(_exc, "name", None) not in ("numba", "llvmlite"):
        raise
