"""Which dimensions a view gets, from the CSG tree where it knows them.

* every orthographic view: its overall width (below) and height (right);
* the view that sees holes end-on: one callout per diameter with the count
  (``4x ⌀8``) and the hole positions from the datum corner (the view's
  lower-left corner), ``u`` below and ``v`` on the left;
* bosses (material-adding cylinders) seen end-on: ``⌀D``;
* the front view: edge radii of rounded boxes (``R3``) and spherical
  outlines (``SR10``) where they are on the part's boundary;
* fillets and rounds (cylinders on the boundary only part of the way
  round) seen end-on: ``R5`` at the arc's middle; tori seen from the side:
  the tube radius ``R2`` (both from the tree; arcs measured on sections of
  parts the tree cannot size come in as `arcs`);
* holes whose axis lies along no view direction: in the view nearest their
  axis, ``⌀6, axis 30° from z`` at the centre (ISO 129-1 states the angle).

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

__all__ = ["view_dimensions", "DIAMETER", "pitch_circle"]

#: The diameter sign (U+2300).
DIAMETER = "\u2300"
#: ISO 129-1 / ASME Y14.5 depth symbol of a blind hole's callout.
DEPTH = "\u21a7"

_C45 = np.sqrt(0.5)


def pitch_circle(centres, tol=1e-6):
    """``(centre (2,), radius)`` of the circle three or more hole `centres` lie on evenly
    (a bolt circle), else None."""
    from .measured import fit_circle

    centres = np.asarray(centres, dtype=float)
    if len(centres) < 3:
        return None
    c, r, rms = fit_circle(centres)
    if r <= 0 or rms > tol * max(r, 1.0):
        return None
    ang = np.sort(np.arctan2(centres[:, 1] - c[1], centres[:, 0] - c[0]))
    gaps = np.diff(np.concatenate([ang, ang[:1] + 2 * np.pi]))
    if np.ptp(gaps) > 1e-3:
        return None
    return c, float(r)


def _distinct(values, tol=1e-6):
    values = np.sort(np.asarray(values, dtype=float))
    if values.size == 0:
        return values
    keep = np.concatenate([[True], np.diff(values) > tol])
    return values[keep]


def view_dimensions(name, frame, extent, features, solid, h, arcs=()) -> list:
    """Dimensions of one view (view coordinates, model units).

    `arcs` are measured arcs (`measured.Arc`) whose axis is this view's direction."""
    if name == "iso":
        return []
    umin, vmin, umax, vmax = (float(x) for x in extent)
    d = np.asarray(frame)[2]
    out = []
    end_on = [f for f in features if f.kind == "cylinder" and not f.arc and abs(float(f.axis @ d)) > 1 - 1e-9]
    holes = [f for f in end_on if f.negative]
    bosses = [f for f in end_on if not f.negative]
    on_circle = []   # hole centres placed by a pitch circle rather than by positions
    for group, sign in ((holes, True), (bosses, False)):
        by_d = {}
        for f in group:
            depth = getattr(f, "depth", None)
            by_d.setdefault((round(f.diameter, 6), -1.0 if depth is None else round(depth, 6)), []).append(f)
        for (dia, depth), fs in sorted(by_d.items()):
            centres = np.array([np.asarray(frame)[:2] @ f.centre for f in fs])
            centres = np.unique(np.round(centres, 6), axis=0)
            pick = centres[np.argmax(centres[:, 0] + centres[:, 1])]
            pcd = pitch_circle(centres) if sign else None
            if pcd is not None:
                on_circle.append((centres, pcd))
            # Bosses are met at 20 degrees, holes at 45: a hole's leader in a boss then runs beside the
            # boss's instead of along it.
            anchor = pick + dia / 2 * (np.array([_C45, _C45]) if sign else np.array([0.9397, 0.3420]))
            n = len(centres)
            text = (f"{n}x " if n > 1 else "") + DIAMETER + format_value(dia)
            if depth >= 0:
                text += f" {DEPTH}{format_value(depth)}"
            if pcd is not None:
                text += f" on PCD {DIAMETER}{format_value(2 * pcd[1])}"
            out.append(Note(tuple(anchor), text, dia, kind="hole" if sign else "diameter", count=n,
                            centre=tuple(pick)))
    if holes:
        uv = np.array([np.asarray(frame)[:2] @ f.centre for f in holes])
        if on_circle:
            # Holes on a pitch circle are placed by it: its centre gets the positions instead.
            placed = np.concatenate([c for c, _ in on_circle])
            far = np.min(np.linalg.norm(uv[:, None] - placed[None], axis=2), axis=1) > 1e-6
            uv = np.concatenate([uv[far], np.array([pcd[0] for _, pcd in on_circle])])
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
    out.extend(_arc_radii(frame, features, arcs))
    out.extend(_oblique(frame, features))
    return out


_AXIS_NAMES = "xyz"


def _arc_radii(frame, features, arcs) -> list:
    frame = np.asarray(frame)
    d = frame[2]
    out, seen = [], set()
    for f in features:
        along = abs(float(f.axis @ d))
        if f.arc and along > 1 - 1e-9 and f.mid is not None:
            r, mid = f.diameter / 2, frame[:2] @ f.mid
        elif f.kind == "torus" and along < 1e-9:
            # The tube's outline seen from the side, half way up its outer arc.
            side = frame[:2] @ np.cross(f.axis, d)
            side = side / max(np.linalg.norm(side), 1e-12)
            a2 = frame[:2] @ f.axis
            r = f.length / 2
            mid = frame[:2] @ f.centre + (f.diameter / 2 + r * _C45) * side + r * _C45 * a2
        else:
            continue
        key = round(r, 6)
        if key not in seen:
            seen.add(key)
            out.append(Note(tuple(mid), f"R{format_value(r)}", r, kind="radius"))
    for a in arcs:
        key = round(a.radius, 6)
        if key not in seen:
            seen.add(key)
            out.append(Note(tuple(frame[:2] @ a.mid), f"R{format_value(a.radius)}", a.radius, kind="radius"))
    return out


def _oblique(frame, features) -> list:
    """Callouts of holes along no view direction, in the view nearest their axis."""
    frame = np.asarray(frame)
    d = frame[2]
    out, seen = [], set()
    for f in features:
        if f.kind != "cylinder" or f.arc or not f.negative:
            continue
        cos = np.abs(f.axis)
        if cos.max() > 1 - 1e-9 or int(np.argmax(cos)) != int(np.argmax(np.abs(d))):
            continue
        angle = float(np.degrees(np.arccos(min(1.0, cos.max()))))
        text = f"{DIAMETER}{format_value(f.diameter)}, axis {format_value(angle)}\u00b0 from {_AXIS_NAMES[int(np.argmax(cos))]}"
        key = (text, tuple(np.round(frame[:2] @ f.centre, 6)))
        if key in seen:
            continue
        seen.add(key)
        out.append(Note(tuple(frame[:2] @ f.centre), text, f.diameter, kind="oblique-hole", centre=tuple(frame[:2] @ f.centre)))
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
