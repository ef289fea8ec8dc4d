"""parametric: curves, surfaces and parametric solids in pure numpy.

Hermite, Bezier, B-spline and NURBS curves; exact conics; Coons, ruled, bicubic
and tensor-product Bezier/B-spline/NURBS surfaces; trivariate volumes with mass
properties; interpolation, least-squares fitting, lofting and closest-point
projection. Nothing here imports the rest of implicad.
"""

from .basis import (bernstein, clamped_knots, periodic_knots, uniform_knots,
                    validate_knots)
from .conics import arc, circle, conic_arc, ellipse, hyperbola, parabola
from .curves import NURBS, Bezier, BSpline, Curve, FunctionCurve, Hermite
from .fitting import (approximate_curve, approximate_surface, fit_curve, fit_periodic_curve,
                      fit_periodic_surface, interpolate_curve, interpolate_surface, loft,
                      make_compatible, parametrize)
from .projection import project_to_curve, project_to_surface
from .surfaces import BicubicPatch, CoonsPatch, RuledSurface, Surface
from .tensor import (BezierSurface, BSplineSurface, NURBSSurface, cylinder, sphere,
                     surface_of_revolution, torus)
from .volumes import BezierVolume, BSplineVolume, NURBSVolume, VolumeProperties

__all__ = [
    "bernstein", "clamped_knots", "periodic_knots", "uniform_knots", "validate_knots",
    "arc", "circle", "conic_arc", "ellipse", "hyperbola", "parabola",
    "Curve", "FunctionCurve", "Hermite", "Bezier", "BSpline", "NURBS",
    "parametrize", "interpolate_curve", "approximate_curve", "fit_periodic_curve", "fit_curve",
    "interpolate_surface", "approximate_surface", "loft", "make_compatible",
    "fit_periodic_surface", "project_to_curve", "project_to_surface",
    "Surface", "CoonsPatch", "RuledSurface", "BicubicPatch",
    "BezierSurface", "BSplineSurface", "NURBSSurface", "surface_of_revolution", "sphere",
    "cylinder", "torus", "VolumeProperties", "BezierVolume", "BSplineVolume", "NURBSVolume",
]
