"""Pictures and drawings of solids and assemblies.

Shaded, wireframe, mesh and hidden-line pictures, standard views and exploded
views of assemblies, written as PNG off screen (`render`).  Above `fea`,
`analysis`, `meshing`, `cells` and `files`; beside the other application rooms.

Examples
--------
>>> from implicit import sphere
>>> from spatial.meshing import mesh
>>> from spatial.drafting import render
>>> render(mesh(sphere(1.0), resolution=16), "ball.png")   # doctest: +SKIP
'ball.png'
"""

from .render import STYLES, VIEWS, explode_offsets, exploded_view, render, render_views  # noqa: F401

__all__ = ["STYLES", "VIEWS", "render", "render_views", "exploded_view", "explode_offsets"]
