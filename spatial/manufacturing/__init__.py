"""Manufacturing: layer slices, 2.5D milling tool paths, G-code and their verification.

`slice` cuts a part into layers of closed contours (outer loops
counter-clockwise, holes clockwise) for additive manufacturing (`slicing`).
`toolpath` plans pocketing and profile passes of a flat end mill from +z
on the solid's exact offsets (`toolpath`, over `contours`), a `ToolPath`
writes LinuxCNC G-code and `read_gcode` reads it back (`gcode`).  `verify`
simulates a program by dexel material removal and compares the result with
the design: gouge, excess and a table per operation (`verify`);
`toolpath_picture` and `removal_picture` draw them (`pictures`).  Rank 6:
imports `analysis`, `meshing` and `files` below it.

Examples
--------
>>> from implicit import box, cylinder
>>> from spatial.manufacturing import slice, toolpath, verify
>>> part = box((4.0, 3.0, 1.0)) - cylinder(0.8, 4)
>>> round(slice(part, layer=0.25).volume, 4)
9.9894
>>> program = toolpath(part, 0.25, resolution=48)
>>> verify(part, program, resolution=64).gouge_volume
0.0
"""

from .slicing import Layer, Slices, slice  # noqa: F401,A001
from .gcode import Operation, ToolPath, read_gcode  # noqa: F401
from .toolpath import part_floors, toolpath  # noqa: F401
from .verify import Verification, removal_deviation, verify  # noqa: F401
from .pictures import removal_picture, toolpath_picture  # noqa: F401

__all__ = ["Layer", "Slices", "slice", "Operation", "ToolPath", "read_gcode", "part_floors", "toolpath",
           "Verification", "removal_deviation", "verify", "removal_picture", "toolpath_picture"]
