"""The model's length unit on a drawing: one source for the title block,
the dimensions and the scale.

A model may declare its unit (``units = "mm"`` in a ``.py`` model, a
``"units"`` field in a ``.json`` tree); ``implicad draw --units`` overrides
it.  A model that declares none is drawn in "units of the model": the
dimensions are its numbers as they are, the title block says so, and the
scale is paper millimetres per model unit.  With a known unit the scale is
the true ISO 5455 ratio (a part in metres at 1:5 is drawn a fifth of its
size).

Examples
--------
>>> unit_label("mm"), unit_label(None)
('mm', 'units of the model')
>>> paper_per_unit("cm"), paper_per_unit(None)
(10.0, 1.0)
"""

from __future__ import annotations

__all__ = ["UNKNOWN", "check_units", "unit_label", "paper_per_unit"]

#: What the title block says of a model that declares no unit.
UNKNOWN = "units of the model"


def check_units(units):
    """`units` if it is None or a unit of `spatial.analysis.UNITS`, else a ValueError naming it."""
    from ..analysis.mass_core import UNITS

    if units is not None and units not in UNITS:
        raise ValueError(f"units: expected one of {', '.join(sorted(UNITS))} or None, got {units!r}")
    return units


def unit_label(units) -> str:
    """The unit as the title block states it."""
    return UNKNOWN if units is None else str(check_units(units))


def paper_per_unit(units) -> float:
    """Millimetres in one model unit (1 when the unit is not known: the scale then counts model units)."""
    from ..analysis.mass_core import UNITS

    if check_units(units) is None:
        return 1.0
    return UNITS[units] / UNITS["mm"]
