"""A small RS-274 reader written for the tests, independent of spatial.manufacturing.gcode.

It knows only what a 3-axis program needs: G0/G1/G2/G3 (modal), G17 arcs with
incremental I/J centres, G20/G21, G90, F, S, M3/M5/M2 and comments.
"""

import math
import re

import numpy as np

WORD = re.compile(r"([A-Z])([-+]?[0-9]*\.?[0-9]+)")


def parse(text):
    """Moves as dicts {g, start, end, centre, feed, op}; the header words seen."""
    seen = set()
    pos = None
    motion = None
    feed = None
    op = None
    moves = []
    for raw in text.splitlines():
        line = raw.strip()
        comments = re.findall(r"\(([^)]*)\)", line)
        for c in comments:
            if c.startswith("operation"):
                op = c
        line = re.sub(r"\([^)]*\)", "", line).strip().upper()
        if not line or line == "%":
            continue
        words = WORD.findall(line.replace(" ", ""))
        assert "".join(a + b for a, b in words) == line.replace(" ", ""), f"unreadable line {raw!r}"
        vals = {}
        for letter, num in words:
            if letter in "GM":
                seen.add(f"{letter}{float(num):g}")
                if letter == "G" and float(num) in (0, 1, 2, 3):
                    motion = int(float(num))
            else:
                seen.add(letter)
                vals[letter] = float(num)
        if "F" in vals:
            feed = vals["F"]
        if not set(vals) & set("XYZ"):
            continue
        assert "G" in line, f"a move without its G word: {raw!r}"
        new = np.array([vals.get(k, pos[i] if pos is not None else 0.0) for i, k in enumerate("XYZ")])
        if pos is not None:
            centre = None
            if motion in (2, 3):
                centre = pos[:2] + np.array([vals["I"], vals["J"]])
            moves.append({"g": motion, "start": pos, "end": new, "centre": centre, "feed": feed, "op": op})
        pos = new
    return moves, seen


def samples(move, step):
    """Points along a move, at most `step` apart (the start included)."""
    a, b = move["start"], move["end"]
    if move["g"] in (0, 1):
        n = max(2, int(math.ceil(np.linalg.norm(b - a) / step)) + 1)
        return a + (b - a) * np.linspace(0, 1, n)[:, None]
    c = move["centre"]
    r0, r1 = np.hypot(*(a[:2] - c)), np.hypot(*(b[:2] - c))
    assert abs(r0 - r1) < 1e-3, f"arc radii differ: {r0} {r1}"
    t0 = math.atan2(a[1] - c[1], a[0] - c[0])
    t1 = math.atan2(b[1] - c[1], b[0] - c[0])
    sweep = (t1 - t0) % (2 * math.pi) if move["g"] == 3 else -((t0 - t1) % (2 * math.pi))
    n = max(3, int(math.ceil(abs(sweep) * r0 / step)) + 1)
    t = t0 + sweep * np.linspace(0, 1, n)
    z = a[2] + (b[2] - a[2]) * np.linspace(0, 1, n)
    return np.column_stack([c[0] + r0 * np.cos(t), c[1] + r0 * np.sin(t), z])


def tool_body(radius, height, n_ring=16, n_up=6):
    """Offsets of points on a flat end mill's bottom disk and side, bottom at 0."""
    ang = np.linspace(0, 2 * np.pi, n_ring, endpoint=False)
    pts = [np.zeros((1, 3))]
    for rr in (0.5 * radius, radius):
        ring = np.column_stack([rr * np.cos(ang), rr * np.sin(ang), np.zeros(n_ring)])
        pts.append(ring)
    side = np.column_stack([radius * np.cos(ang), radius * np.sin(ang), np.zeros(n_ring)])
    for z in np.linspace(0, height, n_up)[1:]:
        pts.append(side + [0, 0, z])
        pts.append(np.array([[0.0, 0.0, z]]))
    return np.concatenate(pts)
