"""B-spline algorithms on raw arrays (knots, degree, control array).

The control array has the control index on axis 0 and any trailing shape, so the
same routines serve curves (``(n+1, dim)``), homogeneous NURBS control points
(``(n+1, dim+1)``) and the rows of surfaces and volumes (``(n+1, m, dim)``).
References are to The NURBS Book (Piegl and Tiller, 2nd ed.).
"""

from __future__ import annotations

from ._ops_core import *  # noqa: F401,F403
from ._ops_core import _span_and_mult  # noqa: F401
from ._ops_removal import (bezier_elevate, bezier_product, elevate, elevate_by_decomposition,  # noqa: F401
                           rational_derivative, remove_knot)
