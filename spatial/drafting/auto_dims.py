"""Which dimensions a view gets, from the CSG tree where it knows them.

* every orthographic view: its overall width (below) and height (right);
* the view that sees holes end-on: one callout per diameter with the count
  (``4x ⌀8``) and the hole positions from the datum corner (the view's
  lower-left corner), ``u`` below and ``v`` on the left;
* bosses (material-adding cylinders) seen end-on: ``⌀D``;
* the front view: edge radii of rounded boxes (``R3``) and spherical
  outlines (``SR10``) where they are on the part's boundary.

Examples
--------
>>> from implicit import box, cylinder
>>> from spatial.drafting.csg_features import axial_features
>>> from spatial.drafting.views import view_frame
>>> part = box((40, 20, 10)) - cylinder(4, 30, center=(10, 0, 0))
>>> dims = view_dimensions("top", view_frame("top"), (-20, -10, 20, 10), axial_features(part), part, 0.3)
>>> sorted(d.text for d in dims if hasattr(d, "text"))
['⌀8']
"""

from __future__ import annotations

import numpy as np

from .csg_features import rounded_radii, sphere_radii
from .dimensions import Linear, Note, format_value

__all__ = ["view_dimensions", "DIAMETER"]

#: The diameter sign (U+2300).
DIAMETER = "\u2300"

_C45 = np.sqrt(0.5)


def _distinct(values, tol=1e-6):
    values = np.sort(np.asarray(values, dtype=float))
    if values.size == 0:
        return values
    keep = np.concatenate([[True], np.diff(values) > tol])
    return values[keep]


def view_dimensions(name, frame, extent, features, solid, h) -> list:
    """Dimensions of one view (view coordinates, model units)."""
    if name == "iso":
        return []
    umin, vmin, umax, vmax = (float(x) for x in extent)
    d = np.asarray(frame)[2]
    out = []
    end_on = [f for f in features if f.kind == "cylinder" and abs(float(f.axis @ d)) > 1 - 1e-9]
    holes = [f for f in end_on if f.negative]
    bosses = [f for f in end_on if not f.negative]
    for group, sign in ((holes, True), (bosses, False)):
        by_d = {}
        for f in group:
            by_d.setdefault(round(f.diameter, 6), []).append(f)
        for dia, fs in sorted(by_d.items()):
            centres = np.array([np.asarray(frame)[:2] @ f.centre for f in fs])
            centres = np.unique(np.round(centres, 6), axis=0)
            pick = centres[np.argmax(centres[:, 0] + centres[:, 1])]
            anchor = pick + dia / 2 * np.array([_C45, _C45])
            n = len(centres)
            text = (f"{n}x " if n > 1 else "") + DIAMETER + format_value(dia)
            out.append(Note(tuple(anchor), text, dia, kind="hole" if sign else "diameter", count=n,
                            centre=tuple(pick)))
    if holes:
        uv = np.array([np.asarray(frame)[:2] @ f.centre for f in holes])
        for u in _distinct(uv[:, 0]):
            if u - umin > 1e-6:
                out.append(Linear((umin, vmin), (u, vmin), "h", "below", u - umin, kind="position"))
        for v in _distinct(uv[:, 1]):
            if v - vmin > 1e-6:
                out.append(Linear((umin, vmin), (umin, v), "v", "left", v - vmin, kind="position"))
    out.append(Linear((umin, vmin), (umax, vmin), "h", "below", umax - umin, kind="overall"))
    out.append(Linear((umax, vmin), (umax, vmax), "v", "right", vmax - vmin, kind="overall"))
    if name == "front":
        out.extend(_radii(frame, extent, solid, h))
    return out


def _radii(frame, extent, solid, h) -> list:
    frame = np.asarray(frame)
    umin, vmin, umax, vmax = extent
    out = []
    for centre, half, r in rounded_radii(solid)[:1]:
        # The arc at the box's upper right corner, half way round.
        c2, h2 = frame[:2] @ centre, np.abs(frame[:2]) @ half
        corner = c2 + h2 - r + r * _C45
        p3 = centre + (corner[0] - c2[0]) * frame[0] + (corner[1] - c2[1]) * frame[1]
        if abs(float(solid(p3[None])[0])) < 2 * h:
            out.append(Note(tuple(corner), f"R{format_value(r)}", r, kind="radius"))
    for centre, r in sphere_radii(solid)[:2]:
        c2 = frame[:2] @ centre
        p3 = centre + r * (_C45 * frame[0] + _C45 * frame[1])
        if abs(float(solid(p3[None])[0])) < 2 * h:
            out.append(Note(tuple(c2 + r * np.array([_C45, _C45])), f"SR{format_value(r)}", r, kind="radius"))
    return out
