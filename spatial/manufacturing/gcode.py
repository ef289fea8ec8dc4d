"""Tool paths as data, and their G-code (RS-274 / ISO 6983, LinuxCNC dialect).

A `ToolPath` is a list of `Operation` s, each a list of moves
``(g, x, y, z, i, j, feed)``: ``g`` is 0 (rapid), 1 (line), 2 (clockwise arc)
or 3 (counter-clockwise arc) in the XY plane, ``(x, y, z)`` the end point,
``(i, j)`` the arc centre relative to the start (LinuxCNC's default incremental
arc centres, G91.1), ``feed`` in units per minute (None for rapids).

`to_gcode` writes one line per move with its G word repeated (no reliance on
modal motion), units (G21 mm or G20 inch), absolute positions (G90), the XY
plane (G17), feed per minute (G94), spindle speed and direction (S, M3) and
stop (M5), and a comment naming every operation.  `read_gcode` parses such a
program back into moves: the verifier reads programs from any source with it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Operation", "ToolPath", "read_gcode", "arc_points"]


@dataclass(frozen=True)
class Operation:
    """One named operation: its kind, depth and moves."""

    name: str
    kind: str
    depth: float
    moves: list = field(default_factory=list)


@dataclass(frozen=True)
class ToolPath:
    """A 2.5D milling program for a flat end mill approaching from +z.

    Attributes
    ----------
    tool_radius : float
    stock : (lo, hi) of (3,) float
        The stock box the program cuts.
    safe_z : float
        Height of every rapid move across the part.
    depths : list of float
        The cutting depths, top to bottom.
    operations : list of Operation
    units : str
        ``"mm"`` (G21) or ``"inch"`` (G20).
    spindle : float
        Spindle speed (rev/min).
    direction : str
        ``"climb"`` or ``"conventional"``.
    """

    tool_radius: float
    stock: tuple
    safe_z: float
    depths: list
    operations: list
    units: str = "mm"
    spindle: float = 10000.0
    direction: str = "climb"
    title: str = "part"

    @property
    def move_count(self) -> int:
        return sum(1 for op in self.operations for m in op.moves if not isinstance(m[0], str))

    def cutting_length(self) -> float:
        """Length of the feed moves (lines and arcs) in 3D."""
        total = 0.0
        for op in self.operations:
            pts, feeds = path_points(op.moves, self._start(op), step=None)
            d = np.linalg.norm(np.diff(pts, axis=0), axis=1)
            total += float(d[feeds[1:] > 0].sum())
        return total

    def _start(self, op):
        lo, hi = self.stock
        return np.array([lo[0], lo[1], self.safe_z])

    def to_gcode(self) -> str:
        """The program as LinuxCNC G-code text."""
        d = 4 if self.units == "mm" else 5
        lo, hi = (np.asarray(b, dtype=float) for b in self.stock)

        def num(v):
            s = f"{v:.{d}f}".rstrip("0").rstrip(".")
            return "0" if s in ("-0", "") else s

        out = ["%", f"(implicad 2.5D milling: {_clean(self.title)})",
               f"(tool: flat end mill, radius {num(self.tool_radius)}, diameter {num(2 * self.tool_radius)})",
               f"(stock: x {num(lo[0])} .. {num(hi[0])}, y {num(lo[1])} .. {num(hi[1])}, "
               f"z {num(lo[2])} .. {num(hi[2])})",
               f"(milling: {self.direction}, spindle clockwise M3; depths: "
               + ", ".join(num(z) for z in self.depths) + ")",
               "G21" if self.units == "mm" else "G20",
               "G90", "G17", "G94", "G40", "G49", "G91.1",
               f"S{num(self.spindle)} M3",
               f"G0 Z{num(self.safe_z)}"]
        for k, op in enumerate(self.operations, 1):
            out.append(f"(operation {k}: {_clean(op.name)})")
            for g, x, y, z, i, j, f in op.moves:
                if isinstance(g, str):                    # a comment carried with the moves
                    out.append(f"({_clean(g)})")
                    continue
                words = [f"G{g}", f"X{num(x)}", f"Y{num(y)}", f"Z{num(z)}"]
                if g in (2, 3):
                    words += [f"I{num(i)}", f"J{num(j)}"]
                if g != 0:
                    words.append(f"F{num(f)}")
                out.append(" ".join(words))
        out += [f"G0 Z{num(self.safe_z)}", "M5", "M2", "%"]
        return "\n".join(out) + "\n"


def _clean(text: str) -> str:
    """A comment may not hold parentheses."""
    return str(text).replace("(", "[").replace(")", "]").replace("\n", " ")


_WORD = re.compile(r"([A-Za-z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def read_gcode(text: str):
    """Parse RS-274 text into operations of moves.

    Understands G0/G1/G2/G3 (modal, XY plane, incremental I/J centres), G20/G21,
    G90/G91 and F; comments ``( ... )`` that start with ``operation`` open a
    new operation.

    Returns
    -------
    list of (name, moves), start point (3,) and units (``"mm"`` or ``"inch"``).
    """
    if not isinstance(text, str):
        raise TypeError(f"text: expected G-code text, got {type(text).__name__}")
    ops = [("program start", [])]
    pos = np.array([0.0, 0.0, 0.0])
    start = None
    motion, feed, absolute, units = 0, 0.0, True, "mm"
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.split(";", 1)[0]
        for comment in re.findall(r"\(([^)]*)\)", line):
            if comment.strip().lower().startswith("operation"):
                ops.append((comment.strip(), []))
        line = re.sub(r"\([^)]*\)", " ", line).strip()
        if not line or line == "%":
            continue
        words = _WORD.findall(line)
        if not words and line:
            raise ValueError(f"G-code line {lineno}: cannot read {raw.strip()!r}")
        target = {}
        for letter, value in words:
            letter = letter.upper()
            v = float(value)
            if letter == "G":
                if v in (0, 1, 2, 3):
                    motion = int(v)
                elif v == 20:
                    units = "inch"
                elif v == 21:
                    units = "mm"
                elif v == 90:
                    absolute = True
                elif v == 91:
                    absolute = False
            elif letter in "XYZIJF":
                target[letter] = v
        if "F" in target:
            feed = target.pop("F")
        if not any(k in target for k in "XYZ"):
            continue
        new = pos.copy()
        for axis, letter in enumerate("XYZ"):
            if letter in target:
                new[axis] = target[letter] if absolute else pos[axis] + target[letter]
        if start is None:
            # the machine's position before the first move is unknown: start there
            start = new.copy()
            pos = new
            continue
        ops[-1][1].append((motion, new[0], new[1], new[2], target.get("I", 0.0), target.get("J", 0.0),
                           None if motion == 0 else feed))
        pos = new
    ops = [op for op in ops if op[1]]
    return ops, (np.zeros(3) if start is None else start), units


def arc_points(start, end, centre, clockwise, step):
    """Points along an XY arc (z linear), start excluded, end included."""
    a0 = np.arctan2(start[1] - centre[1], start[0] - centre[0])
    a1 = np.arctan2(end[1] - centre[1], end[0] - centre[0])
    if clockwise:
        sweep = -((a0 - a1) % (2 * np.pi))
    else:
        sweep = (a1 - a0) % (2 * np.pi)
    if abs(sweep) < 1e-12:
        sweep = -2 * np.pi if clockwise else 2 * np.pi
    R = float(np.hypot(start[0] - centre[0], start[1] - centre[1]))
    n = max(2, int(np.ceil(abs(sweep) * R / step))) if step else max(8, int(abs(sweep) / 0.1))
    t = np.arange(1, n + 1) / n
    ang = a0 + sweep * t
    pts = np.column_stack([centre[0] + R * np.cos(ang), centre[1] + R * np.sin(ang),
                           start[2] + (end[2] - start[2]) * t])
    pts[-1] = end
    return pts


def path_points(moves, start, step):
    """Every move cut into points at most `step` apart (lines and arcs).

    Returns ``(points (m, 3), feed (m,))``: the feed of the move reaching each
    point (0 for rapids), the start point first.
    """
    pts = [np.asarray(start, dtype=float)[None, :]]
    feeds = [np.zeros(1)]
    cur = np.asarray(start, dtype=float)
    for g, x, y, z, i, j, f in moves:
        if isinstance(g, str):
            continue
        end = np.array([x, y, z], dtype=float)
        if g in (2, 3):
            seg = arc_points(cur, end, cur[:2] + (i, j), g == 2, step)
        else:
            L = float(np.linalg.norm(end - cur))
            n = max(1, int(np.ceil(L / step))) if step else 1
            seg = cur + (end - cur) * (np.arange(1, n + 1) / n)[:, None]
        pts.append(seg)
        feeds.append(np.full(len(seg), 0.0 if g == 0 else float(f or 0.0) or 1.0))
        cur = end
    return np.concatenate(pts), np.concatenate(feeds)
