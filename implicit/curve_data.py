"""Parametric curves as plain JSON values, and the sampling counts and boxes of curve-based nodes."""

from __future__ import annotations

import numbers

import numpy as np

from parametric.curves import NURBS, Bezier, BSpline, Curve, Hermite

from .surface_projection import _from_typed_dict

__all__ = ["curve_to_dict", "curve_from_dict", "MIN_SAMPLES", "SAMPLES_PER_CONTROL"]

#: Default samples per control point (at least `MIN_SAMPLES`).
SAMPLES_PER_CONTROL = 64
MIN_SAMPLES = 1024


def curve_to_dict(curve) -> dict:
    """A parametric curve as plain JSON values.

    Parameters
    ----------
    curve : Bezier, BSpline, NURBS or Hermite

    Returns
    -------
    dict
        ``{"type": "nurbs", "control_points": [[...]], "weights": [...],
        "degree": p, "knots": [...]}`` (B-splines omit the weights, Bezier
        curves store only control points, Hermite curves their end data).

    Examples
    --------
    >>> from parametric.conics import circle
    >>> curve_to_dict(circle(1.0, center=(0, 0)))["type"]
    'nurbs'
    """
    if isinstance(curve, NURBS):
        return {"type": "nurbs", "control_points": np.asarray(curve.control_points).tolist(),
                "weights": np.asarray(curve.weights).tolist(), "degree": int(curve.degree),
                "knots": np.asarray(curve.knots).tolist()}
    if isinstance(curve, BSpline):
        return {"type": "bspline", "control_points": np.asarray(curve.control_points).tolist(),
                "degree": int(curve.degree), "knots": np.asarray(curve.knots).tolist()}
    if isinstance(curve, Bezier):
        return {"type": "bezier", "control_points": np.asarray(curve.control_points).tolist()}
    if isinstance(curve, Hermite):
        g = np.asarray(curve.geometry)
        return {"type": "hermite", "geometry": g.tolist()}
    raise TypeError(f"curve: expected a Bezier, BSpline, NURBS or Hermite curve, got {type(curve).__name__}")


def _hermite_from_dict(data):
    g = np.asarray(data["geometry"], dtype=float)
    return Hermite(g[0], g[1], g[2], g[3])


_CURVE_BUILDERS = {
    "nurbs": lambda d: NURBS(d["control_points"], d["weights"], d["degree"], d["knots"]),
    "bspline": lambda d: BSpline(d["control_points"], d["degree"], d["knots"]),
    "bezier": lambda d: Bezier(d["control_points"]),
    "hermite": _hermite_from_dict,
}


def curve_from_dict(data, name: str = "curve") -> Curve:
    """Rebuild a curve from `curve_to_dict` output (a `Curve` passes through)."""
    if isinstance(data, Curve):
        return data
    if not isinstance(data, dict):
        raise TypeError(f"{name}: expected a parametric curve or its dict, got {type(data).__name__}")
    return _from_typed_dict(data, name, "curve", _CURVE_BUILDERS)


def _hull_box(curve, samples):
    """Conservative box of a curve: control-point hull, else padded samples."""
    if isinstance(curve, (BSpline, Bezier)):
        P = np.asarray(curve.control_points)
        return P.min(axis=0), P.max(axis=0)
    lo, hi = samples.min(axis=0), samples.max(axis=0)
    pad = 0.05 * float(np.max(hi - lo)) + 1e-12
    return lo - pad, hi + pad


def _default_samples(curve) -> int:
    n = np.asarray(curve.control_points).shape[0] if isinstance(curve, (BSpline, Bezier)) else 16
    return max(MIN_SAMPLES, SAMPLES_PER_CONTROL * n)


def _as_samples(samples, curve) -> int:
    if samples is None:
        return _default_samples(curve)
    if isinstance(samples, bool) or not isinstance(samples, (numbers.Integral,)):
        raise TypeError(f"samples: expected an int, got {samples!r}")
    if samples < 16:
        raise ValueError(f"samples: expected at least 16, got {samples}")
    return int(samples)
