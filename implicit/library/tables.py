"""Standard sizes of the library's part families, taken from their tables.

Each table maps a designation (``"M10"``, ``"DN50"``, ``"IPE200"``, ...) to
the dimensions of that size in millimetres.  Root radii, fillets, tapers and
thread forms are left out: the parts are the envelopes the standards give
(the volumes of the tests are those of these envelopes).

Sources: ISO 4014 (hexagon head bolts, product grades A and B), ISO 4032
(hexagon nuts, style 1), ISO 7089 (plain washers, normal series), EN 1092-1
(circular flanges, PN 16, type 01 plate flange), DIN 6885-1 (parallel keys,
form A), EN 10056-1 (equal-leg angles), EN 10055 (equal-flange T sections),
DIN 1026-1 (UPN channels, flanges drawn parallel), EN 10365 (IPE beams).
"""

from __future__ import annotations

__all__ = ["ISO4014_BOLTS", "ISO4032_NUTS", "ISO7089_WASHERS", "EN1092_PN16", "DIN6885_KEYS",
           "EN10056_ANGLES", "EN10055_TEES", "UPN_CHANNELS", "IPE_BEAMS", "key_for_shaft", "lookup"]

#: ISO 4014: nominal diameter d, head height k, width across flats s.
ISO4014_BOLTS = {
    "M3": dict(diameter=3.0, head_height=2.0, across_flats=5.5),
    "M4": dict(diameter=4.0, head_height=2.8, across_flats=7.0),
    "M5": dict(diameter=5.0, head_height=3.5, across_flats=8.0),
    "M6": dict(diameter=6.0, head_height=4.0, across_flats=10.0),
    "M8": dict(diameter=8.0, head_height=5.3, across_flats=13.0),
    "M10": dict(diameter=10.0, head_height=6.4, across_flats=16.0),
    "M12": dict(diameter=12.0, head_height=7.5, across_flats=18.0),
    "M16": dict(diameter=16.0, head_height=10.0, across_flats=24.0),
    "M20": dict(diameter=20.0, head_height=12.5, across_flats=30.0),
    "M24": dict(diameter=24.0, head_height=15.0, across_flats=36.0),
    "M30": dict(diameter=30.0, head_height=18.7, across_flats=46.0),
    "M36": dict(diameter=36.0, head_height=22.5, across_flats=55.0),
}

#: ISO 4032: nominal diameter d, nut height m, width across flats s.
ISO4032_NUTS = {
    "M3": dict(diameter=3.0, height=2.4, across_flats=5.5),
    "M4": dict(diameter=4.0, height=3.2, across_flats=7.0),
    "M5": dict(diameter=5.0, height=4.7, across_flats=8.0),
    "M6": dict(diameter=6.0, height=5.2, across_flats=10.0),
    "M8": dict(diameter=8.0, height=6.8, across_flats=13.0),
    "M10": dict(diameter=10.0, height=8.4, across_flats=16.0),
    "M12": dict(diameter=12.0, height=10.8, across_flats=18.0),
    "M16": dict(diameter=16.0, height=14.8, across_flats=24.0),
    "M20": dict(diameter=20.0, height=18.0, across_flats=30.0),
    "M24": dict(diameter=24.0, height=21.5, across_flats=36.0),
    "M30": dict(diameter=30.0, height=25.6, across_flats=46.0),
    "M36": dict(diameter=36.0, height=31.0, across_flats=55.0),
}

#: ISO 7089: inner diameter d1, outer diameter d2, thickness h.
ISO7089_WASHERS = {
    "M3": dict(inner_diameter=3.2, outer_diameter=7.0, thickness=0.5),
    "M4": dict(inner_diameter=4.3, outer_diameter=9.0, thickness=0.8),
    "M5": dict(inner_diameter=5.3, outer_diameter=10.0, thickness=1.0),
    "M6": dict(inner_diameter=6.4, outer_diameter=12.0, thickness=1.6),
    "M8": dict(inner_diameter=8.4, outer_diameter=16.0, thickness=1.6),
    "M10": dict(inner_diameter=10.5, outer_diameter=20.0, thickness=2.0),
    "M12": dict(inner_diameter=13.0, outer_diameter=24.0, thickness=2.5),
    "M16": dict(inner_diameter=17.0, outer_diameter=30.0, thickness=3.0),
    "M20": dict(inner_diameter=21.0, outer_diameter=37.0, thickness=3.0),
    "M24": dict(inner_diameter=25.0, outer_diameter=44.0, thickness=4.0),
    "M30": dict(inner_diameter=31.0, outer_diameter=56.0, thickness=4.0),
    "M36": dict(inner_diameter=37.0, outer_diameter=66.0, thickness=5.0),
}

#: EN 1092-1 PN 16, type 01: flange diameter D, bolt circle K, hole diameter L,
#: bolt count, thickness C, bore B1 (pipe outside diameter + clearance).
EN1092_PN16 = {
    "DN15": dict(flange_diameter=95.0, bolt_circle=65.0, hole_diameter=14.0, bolt_holes=4, thickness=14.0, bore=22.0),
    "DN20": dict(flange_diameter=105.0, bolt_circle=75.0, hole_diameter=14.0, bolt_holes=4, thickness=16.0, bore=27.6),
    "DN25": dict(flange_diameter=115.0, bolt_circle=85.0, hole_diameter=14.0, bolt_holes=4, thickness=16.0, bore=34.4),
    "DN32": dict(flange_diameter=140.0, bolt_circle=100.0, hole_diameter=18.0, bolt_holes=4, thickness=18.0, bore=43.1),
    "DN40": dict(flange_diameter=150.0, bolt_circle=110.0, hole_diameter=18.0, bolt_holes=4, thickness=18.0, bore=49.0),
    "DN50": dict(flange_diameter=165.0, bolt_circle=125.0, hole_diameter=18.0, bolt_holes=4, thickness=20.0, bore=61.1),
    "DN65": dict(flange_diameter=185.0, bolt_circle=145.0, hole_diameter=18.0, bolt_holes=8, thickness=20.0, bore=77.1),
    "DN80": dict(flange_diameter=200.0, bolt_circle=160.0, hole_diameter=18.0, bolt_holes=8, thickness=20.0, bore=90.3),
    "DN100": dict(flange_diameter=220.0, bolt_circle=180.0, hole_diameter=18.0, bolt_holes=8, thickness=22.0, bore=115.9),
    "DN125": dict(flange_diameter=250.0, bolt_circle=210.0, hole_diameter=18.0, bolt_holes=8, thickness=22.0, bore=141.6),
    "DN150": dict(flange_diameter=285.0, bolt_circle=240.0, hole_diameter=22.0, bolt_holes=8, thickness=24.0, bore=170.5),
    "DN200": dict(flange_diameter=340.0, bolt_circle=295.0, hole_diameter=22.0, bolt_holes=12, thickness=26.0, bore=221.8),
}

#: DIN 6885-1: (shaft diameter above, up to) -> key width b, key height h, shaft keyway depth t1.
DIN6885_KEYS = [
    ((6.0, 8.0), dict(key_width=2.0, key_height=2.0, keyway_depth=1.2)),
    ((8.0, 10.0), dict(key_width=3.0, key_height=3.0, keyway_depth=1.8)),
    ((10.0, 12.0), dict(key_width=4.0, key_height=4.0, keyway_depth=2.5)),
    ((12.0, 17.0), dict(key_width=5.0, key_height=5.0, keyway_depth=3.0)),
    ((17.0, 22.0), dict(key_width=6.0, key_height=6.0, keyway_depth=3.5)),
    ((22.0, 30.0), dict(key_width=8.0, key_height=7.0, keyway_depth=4.0)),
    ((30.0, 38.0), dict(key_width=10.0, key_height=8.0, keyway_depth=5.0)),
    ((38.0, 44.0), dict(key_width=12.0, key_height=8.0, keyway_depth=5.0)),
    ((44.0, 50.0), dict(key_width=14.0, key_height=9.0, keyway_depth=5.5)),
    ((50.0, 58.0), dict(key_width=16.0, key_height=10.0, keyway_depth=6.0)),
    ((58.0, 65.0), dict(key_width=18.0, key_height=11.0, keyway_depth=7.0)),
    ((65.0, 75.0), dict(key_width=20.0, key_height=12.0, keyway_depth=7.5)),
    ((75.0, 85.0), dict(key_width=22.0, key_height=14.0, keyway_depth=9.0)),
    ((85.0, 95.0), dict(key_width=25.0, key_height=14.0, keyway_depth=9.0)),
]

#: EN 10056-1 equal-leg angles: leg a, thickness t.
EN10056_ANGLES = {f"L{a}x{t}": dict(leg=float(a), thickness=float(t)) for a, t in
                  ((20, 3), (25, 3), (30, 3), (40, 4), (50, 5), (60, 6), (70, 7), (80, 8), (100, 10), (120, 12))}

#: EN 10055 equal-flange tees: width b = height h, thickness t (flange and stem).
EN10055_TEES = {f"T{b}": dict(width=float(b), height=float(b), thickness=float(t)) for b, t in
                ((30, 4), (40, 5), (50, 6), (60, 7), (70, 8), (80, 9), (100, 11), (120, 13))}

#: DIN 1026-1 UPN channels: height h, flange width b, web tw, flange tf.
UPN_CHANNELS = {f"UPN{h}": dict(height=float(h), width=float(b), web=tw, flange=tf) for h, b, tw, tf in
                ((80, 45, 6.0, 8.0), (100, 50, 6.0, 8.5), (120, 55, 7.0, 9.0), (140, 60, 7.0, 10.0),
                 (160, 65, 7.5, 10.5), (180, 70, 8.0, 11.0), (200, 75, 8.5, 11.5), (220, 80, 9.0, 12.5),
                 (240, 85, 9.5, 13.0), (260, 90, 10.0, 14.0))}

#: EN 10365 IPE beams: height h, flange width b, web tw, flange tf.
IPE_BEAMS = {f"IPE{h}": dict(height=float(h), width=float(b), web=tw, flange=tf) for h, b, tw, tf in
             ((80, 46, 3.8, 5.2), (100, 55, 4.1, 5.7), (120, 64, 4.4, 6.3), (140, 73, 4.7, 6.9),
              (160, 82, 5.0, 7.4), (180, 91, 5.3, 8.0), (200, 100, 5.6, 8.5), (220, 110, 5.9, 9.2),
              (240, 120, 6.2, 9.8), (270, 135, 6.6, 10.2), (300, 150, 7.1, 10.7))}


def key_for_shaft(diameter: float) -> dict:
    """The DIN 6885-1 key and keyway depth for a shaft of `diameter` (mm).

    Examples
    --------
    >>> key_for_shaft(25)["key_width"]
    8.0
    """
    d = float(diameter)
    for (lo, hi), key in DIN6885_KEYS:
        if lo < d <= hi:
            return dict(key)
    raise ValueError(f"diameter: DIN 6885-1 covers shafts above 6 up to 95 mm, got {diameter!r}")


def lookup(table: dict, designation: str, what: str) -> dict:
    """One row of `table`, or a ValueError listing the designations."""
    if not isinstance(designation, str):
        raise TypeError(f"{what}: expected a designation such as {next(iter(table))!r}, got {designation!r}")
    key = designation.strip().upper().replace("X", "x")
    for name, row in table.items():
        if name.upper() == key.upper():
            return dict(row)
    raise ValueError(f"{what}: unknown size {designation!r}; sizes: {', '.join(table)}")
