"""Representation schemes compared on one part, and the full report (rank 7).

`compare(solid)` builds every scheme that applies -- the CSG tree, the
half-space form, the sweep, the family instance, the trivariate analytical
form, octree cells, occupancy grids, the B-rep with its Euler-Poincare check,
the wireframe, fitted B-spline patches and the OpenVDB level set -- and
measures each on the same part: storage, build time, volume error, time for
point-membership queries, and the questions it answers; the seed's claims
come checked with figures (`claims`).  `brep` groups a closed mesh into faces
by CSG leaf; `half_space_form` expands a polyhedral tree into convex pieces;
`ambiguity` shows three solids that share one wireframe; `report` writes
the full report of a part (Markdown, HTML, JSON and pictures).

Examples
--------
>>> from implicit import box
>>> from spatial.compare import compare
>>> table = compare(box((2, 1, 1)), resolution=16, n_queries=1000, claims=False)
>>> table.row("B-rep (faces by CSG leaf)").details["F"]
6
"""

from .brep import BRep, brep
from .halfspace import HalfSpaceForm, half_space_form
from .leaves import world_leaves
from .schemes import ANSWERS, Representation
from .table import Comparison, compare
from .claims import check_claims, grid_sweep, plot_grid_sweep

__all__ = ["BRep", "brep", "HalfSpaceForm", "half_space_form", "world_leaves", "ANSWERS", "Representation",
           "Comparison", "compare", "check_claims", "grid_sweep", "plot_grid_sweep"]
