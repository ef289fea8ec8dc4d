"""Partial auxiliary views of oblique holes (ISO 128-3 / ASME Y14.3): the hole
seen along its own axis, where its rim is a circle of the true diameter.

The view the axis lies flat in (its direction square to the axis: the axis in
true length) gets an arrow along the axis with the view's letter; the partial
view, labelled ``VIEW B``, is drawn at the sheet's scale in a free place of
the drawing area, with centre lines and the hole's diameter callout.
"""

from __future__ import annotations

import numpy as np

from .auto_dims import DIAMETER
from .dimensions import Linear, Note, format_value

__all__ = ["oblique_holes", "draw_auxiliary_views"]

_LETTERS = "BCDEFGHJK"   # A is the section's letter


def oblique_holes(features) -> list:
    """Hole cylinders whose axis is along no coordinate direction, one per axis line."""
    out = []
    for f in features:
        if f.kind != "cylinder" or f.arc or not f.negative or np.abs(f.axis).max() > 1 - 1e-9:
            continue
        if not any(np.allclose(f.axis, g.axis) and np.allclose(f.centre, g.centre) for g in out):
            out.append(f)
    return out


def _free_spot(boxes, area, w, h):
    x0, y0, x1, y1 = area
    for y in np.arange(y0, y1 - h, 2.0):
        for x in np.arange(x1 - w, x0, -2.0):   # a handful of trial spots, right to left
            b = (x, y, x + w, y + h)
            if not any(b[0] < c[2] and c[0] < b[2] and b[1] < c[3] and c[1] < b[3] for c in boxes):
                return b
    return None


def _mouth(frame, extent, f):
    """Where the axis of `f` leaves the view's extent on its ``+axis`` side (view coordinates):
    the hole's mouth on the face it leaves."""
    c, a = frame[:2] @ f.centre, frame[:2] @ f.axis
    lo, hi = np.asarray(extent[:2], dtype=float), np.asarray(extent[2:], dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(np.abs(a) > 1e-12, np.where(a > 0, hi - c, lo - c) / a, np.inf)
    return c + float(np.min(t)) * a


def draw_auxiliary_views(drawing, views, places, holes, placer, area, scale) -> list:
    """Draw one partial auxiliary view per hole of `holes`; returns their letters.

    A hole with no view square to its axis, or no room left on the sheet, gets none."""
    letters = []
    for k, f in enumerate(holes[:len(_LETTERS)]):
        true_view = next((v for v, vl in views.items() if v != "iso" and abs(float(vl.frame[2] @ f.axis)) < 1e-6), None)
        if true_view is None:
            continue
        r = 0.5 * f.diameter * scale
        side = 2 * r + 30.0
        letter = _LETTERS[k]
        # The arrow in the true-length view: along the axis, pointing at the hole's mouth.
        frame = np.asarray(views[true_view].frame)
        a = frame[:2] @ f.axis
        a = a / np.linalg.norm(a)
        top = _mouth(frame, views[true_view].extent, f)
        place = places[true_view]
        tip = place.to_sheet(top + a * 0.5 * f.diameter)
        d = np.array([a[0], -a[1]])   # sheet y points down
        tail = tip + 12.0 * d
        # The view lies on the line of sight from the arrow (projected along the axis), where it is free.
        spot = None
        for t in np.arange(side / 2 + 16.0, 400.0, 2.0):   # trial distances along one line
            c = tip + t * d
            b = (c[0] - side / 2, c[1] - side / 2, c[0] + side / 2, c[1] + side / 2 + 10.0)
            inside = b[0] >= area[0] and b[1] >= area[1] and b[2] <= area[2] and b[3] <= area[3]
            if inside and not any(b[0] < o[2] and o[0] < b[2] and b[1] < o[3] and o[1] < b[3] for o in placer.boxes):
                spot = b
                break
        spot = spot or _free_spot(placer.boxes, area, side, side + 10.0)
        if spot is None:
            continue
        # The mouth's position along the face it leaves, from that face's left (or lower) end.
        ext_ = views[true_view].extent
        tv = drawing.find(f"view-{true_view}")
        umin, vmin, umax, vmax = (float(e) for e in ext_)
        if abs(top[1] - vmax) < 1e-6 or abs(top[1] - vmin) < 1e-6:
            v_face = top[1]
            dim = Linear((umin, v_face), (float(top[0]), v_face), "h", "above" if v_face == vmax else "below",
                         float(top[0]) - umin, kind="position")
        else:
            u_face = top[0]
            dim = Linear((u_face, vmin), (u_face, float(top[1])), "v", "right" if u_face == umax else "left",
                         float(top[1]) - vmin, kind="position")
        pg = (tv or drawing).group(f"aux-position-{letter}", "dimensions")
        placer.place(pg, dim, place.to_sheet, place.box())
        g = drawing.group(f"arrow-{letter}", "view-arrow", letter=letter)
        g.line([tail, tip], "dimension")
        n = np.array([-d[1], d[0]])
        g.polygon([tip, tip + 3.0 * d + 1.0 * n, tip + 3.0 * d - 1.0 * n], "dimension")
        g.text(*(tail + 3.5 * d), letter, size=5.0, cls="view-label", bold=True)
        placer.boxes.append(g.bbox())
        # The partial view: the rim as a circle of true size, centre lines past it.
        cx, cy = 0.5 * (spot[0] + spot[2]), spot[1] + 0.5 * side
        v = drawing.group(f"view-{letter}", "view", name=f"aux-{letter}", scale=f"{scale:g}")
        v.circle(cx, cy, r, "visible")
        ext = r + 3.0
        # Centre lines along and across the line of sight's trace, as the view is projected.
        n_ = np.array([-d[1], d[0]])
        c0 = np.array([cx, cy])
        v.line([c0 - ext * d, c0 + ext * d], "center")
        v.line([c0 - ext * n_, c0 + ext * n_], "center")
        v.text(cx, cy + r + 10.0, f"VIEW {letter}", size=5.0, cls="view-label", bold=True)
        placer.boxes.append(v.bbox())
        dg = v.group(None, "dimensions")

        def to_sheet(uv, cx=cx, cy=cy):
            uv = np.asarray(uv, dtype=float)
            return np.stack([cx + scale * uv[..., 0], cy - scale * uv[..., 1]], axis=-1)

        anchor = 0.5 * f.diameter * np.array([0.7071, 0.7071])
        note = Note(tuple(anchor), DIAMETER + format_value(f.diameter), f.diameter, kind="hole", count=1,
                    centre=(0.0, 0.0))
        box = (cx - r, cy - r, cx + r, cy + r)
        placer.place(dg, note, to_sheet, box)
        letters.append(letter)
    return letters
