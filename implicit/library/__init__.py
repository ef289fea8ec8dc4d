"""The part library: primitive instancing with standard sizes.

Fourteen families, each registered with `implicit.families` (so
``instance(name, ...)`` and ``implicad families`` know them), with typed,
validated parameters, standard sizes from their tables (`tables`) and named
faces (`named_faces`, `face_names`):

========================  ===================================================
fasteners                 ``iso4014_bolt``, ``iso4032_nut``, ``iso7089_washer``
gears                     ``spur_gear`` (involute: module, teeth, pressure angle,
                          face width, bore, keyway)
pipework                  ``en1092_flange`` (PN 16), ``pipe_tee``, ``pipe_bend``
shafts and housings       ``keyed_shaft`` (DIN 6885), ``bearing_housing``
structural sections       ``angle_section``, ``tee_section``, ``channel_section``,
                          ``i_beam``
springs                   ``helical_spring``
========================  ===================================================

Examples
--------
>>> from implicit.library import iso_bolt, standard_sizes
>>> bolt = iso_bolt("M12", length=60)
>>> bolt.params["family"], bolt.params["params"]["head_height"]
('iso4014_bolt', 7.5)
>>> standard_sizes("en1092_flange")[:3]
['DN15', 'DN20', 'DN25']
"""

from .common import FACES, SIZES, face_names, named_faces, standard_instance
from .fasteners import iso_bolt, iso_nut, iso_washer
from .gears import gear_outline, spur_gear
from .pipes import pipe_bend, pipe_flange, pipe_tee
from .sections import angle_section, channel_section, i_beam, tee_section
from .shafts import bearing_housing, keyed_shaft
from .springs import helical_spring

__all__ = ["LIBRARY_FAMILIES", "standard_sizes", "named_faces", "face_names", "standard_instance",
           "iso_bolt", "iso_nut", "iso_washer", "spur_gear", "gear_outline", "pipe_flange", "pipe_tee",
           "pipe_bend", "angle_section", "tee_section", "channel_section", "i_beam", "keyed_shaft",
           "bearing_housing", "helical_spring"]

#: The library's family names, in the order of the table above.
LIBRARY_FAMILIES = tuple(FACES)


def standard_sizes(family_name: str) -> list:
    """Designations of the standard sizes of `family_name` (empty when it has no table)."""
    if family_name not in FACES:
        raise ValueError(f"family_name: expected a library family ({', '.join(FACES)}), got {family_name!r}")
    return list(SIZES.get(family_name, {}))
