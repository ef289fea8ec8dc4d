"""Inspection: produced parts against their design, and tolerance stack-up of assemblies.

`inspect` aligns a scan (mesh or point cloud: `load_scan` reads STL, PLY,
OBJ, XYZ...) to the design by best fit (`icp`: point-to-point ICP on a
cKDTree, then point-to-plane on the solid's field) or on three datum planes
(`datum_align`), and gives each point's signed deviation from the design
surface with statistics, pass/fail and the alignment transform
(`deviation`, `align`); `deviation_picture` and `histogram_picture` draw it
(`pictures`).  `stackup` propagates tolerances of family parameters and
placements to a clearance of an assembly, worst case and Monte-Carlo, with
sensitivities (`stackup`, pictures in `stackup_pictures`).  Rank 6: imports
`analysis`, `meshing` and `files` below it.

Examples
--------
>>> from implicit import sphere
>>> from spatial.meshing import mesh
>>> from spatial.inspection import inspect
>>> r = inspect(sphere(1.0), mesh(sphere(1.01), resolution=24).points, tolerance=0.02)
>>> round(r.max_deviation, 4), r.passed
(0.01, True)
"""

from .align import apply, datum_align, icp, rigid_fit, vertex_areas  # noqa: F401
from .deviation import SCAN_FORMATS, Inspection, inspect, load_scan  # noqa: F401
from .pictures import deviation_picture, histogram_picture  # noqa: F401
from .stackup import StackUp, Tolerance, signed_gap, stackup  # noqa: F401
from .stackup_pictures import stackup_picture  # noqa: F401

__all__ = ["apply", "datum_align", "icp", "rigid_fit", "vertex_areas", "SCAN_FORMATS", "Inspection", "inspect",
           "load_scan", "deviation_picture", "histogram_picture", "StackUp", "Tolerance", "signed_gap", "stackup",
           "stackup_picture"]
