"""Conversions between representations: grids and solids <-> parametric curves and patches.

Section contours fitted by B-splines, lofted B-spline surfaces, star-shaped
boundaries as closed B-spline surfaces (`fitting`), and curves and surfaces
back to meshes and polylines.  Above `analysis` (it fits the contours of
sections), `meshing`, `cells` and `files`.

Examples
--------
>>> from implicit import sphere
>>> from spatial.convert.fitting import fit_section_curve
>>> fit = fit_section_curve(sphere(1.0), "z=0", n_control=12)   # doctest: +SKIP
"""

from .fitting import (LoftResult, SectionCurve, StarFit, curve_to_polydata, fit_section_curve,  # noqa: F401
                      fit_star_surface, isoparametric_polydata, loft_sections, star_radii, surface_to_mesh)

__all__ = ["SectionCurve", "LoftResult", "StarFit", "fit_section_curve", "loft_sections", "star_radii",
           "fit_star_surface", "surface_to_mesh", "curve_to_polydata", "isoparametric_polydata"]
