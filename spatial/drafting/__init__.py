"""Drawings and pictures of solids and assemblies.

Engineering drawings (`part_drawing`, `assembly_drawing`, written by
`write_drawing` as SVG, PDF, DXF or PNG): front, top and side views placed
by first-angle (ISO 5456-2) or third-angle (ASME Y14.3) projection and an
isometric view at one standard scale; visible and hidden lines from the
exact feature edges (`surface_edges`: the mesh's edges snapped onto the CSG
faces) and silhouettes, with a depth-buffer visibility test; centre lines;
automatic dimensions from the CSG tree; SECTION A-A with ISO 128-50
hatching; exploded assemblies with balloons and a parts list (CSV too); a
frame and title block.  Raw pictures off screen (`render`): shaded,
wireframe of the feature edges, triangles, hidden-line, standard views,
exploded views and octree cells coloured by class.

Above `fea`, `analysis`, `meshing`, `cells` and `files`; beside the other
application rooms.

Examples
--------
>>> from implicit import box, cylinder
>>> from spatial.drafting import part_drawing, write_drawing
>>> sheet = part_drawing(box((40, 20, 10)) - cylinder(4, 30), name="plate", resolution=48)
>>> sheet.meta["scale"]
'2:1'
>>> write_drawing(sheet, "plate.svg")   # doctest: +SKIP
'plate.svg'
"""

from .render import (STYLES, VIEWS, explode_offsets, exploded_view, feature_lines, render,  # noqa: F401
                     render_cells, render_views)
from .edges import SurfaceEdges, silhouettes, surface_edges  # noqa: F401
from .model import Drawing  # noqa: F401
from .part_sheet import part_drawing  # noqa: F401
from .assembly_sheet import assembly_drawing  # noqa: F401
from .parts_list import PartRow, parts_list, write_csv  # noqa: F401
from .export import FORMATS, write_drawing  # noqa: F401
from .results import draw_results  # noqa: F401
from .measured import fit_circle, measured_holes  # noqa: F401

__all__ = ["STYLES", "VIEWS", "render", "render_views", "render_cells", "feature_lines", "exploded_view",
           "explode_offsets", "SurfaceEdges", "surface_edges", "silhouettes", "Drawing", "part_drawing",
           "assembly_drawing", "PartRow", "parts_list", "write_csv", "FORMATS", "write_drawing", "draw_results",
           "fit_circle", "measured_holes"]
