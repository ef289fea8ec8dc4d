"""Nastran bulk data (``.bdf`` / ``.nas``) of a tetrahedral mesh.

The file is a complete input deck: executive control (``SOL 101``), a case
control section, one ``BEGIN BULK``, and the bulk data ``GRID*`` (large
field: 16-character numbers, so coordinates keep 10 significant digits),
``CTETRA`` (4 or 10 nodes, small field, the 10-node card continued on a
second line, both marked ``+``), ``PSOLID`` pointing to a ``MAT1*`` of the given material, and
one ``SET1`` per named face (7 ids on the first line, 8 on each
continuation, as the card's fields allow, continuations marked ``+``), each preceded by a comment naming
the face.

References
----------
MSC Nastran Quick Reference Guide: GRID, CTETRA, PSOLID, MAT1, SET1 bulk data
entries; small (8-character) and large (16-character) field formats.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bdf_text", "nastran_set_ids"]


def _field8(values) -> np.ndarray:
    """Integers right-aligned in 8-character fields."""
    return np.char.rjust(np.asarray(values, dtype=np.int64).astype(str), 8)


def _real16(values) -> np.ndarray:
    """Reals in 16 characters with a decimal point and exponent (``-1.234567890e+01``)."""
    return np.char.rjust(np.char.mod("%.9e", np.asarray(values, dtype=np.float64)), 16)


def nastran_set_ids(names) -> dict:
    """SET1 identification numbers of the named faces: 1, 2, ... in order.

    Examples
    --------
    >>> nastran_set_ids(["box_0.+x", "box_0.-x"])
    {'box_0.+x': 1, 'box_0.-x': 2}
    """
    return {n: i + 1 for i, n in enumerate(names)}


def _set1_lines(sid, ids) -> list:
    """A SET1 card: the id and 7 numbers on the first line, 8 on each continuation line.

    Every line but the last ends with ``+`` in field 10 and each continuation
    starts with ``+`` in field 1 (the marked form every reader accepts).
    """
    ids = np.asarray(ids, dtype=np.int64)
    first, rest = ids[:7], ids[7:]
    lines = ["SET1    " + f"{sid:>8d}" + "".join(_field8(first))]
    if rest.size:
        pad = (-rest.size) % 8
        table = _field8(np.concatenate([rest, np.zeros(pad, dtype=np.int64)])).reshape(-1, 8)
        rows = ["".join(r) for r in table]
        if pad:
            rows[-1] = rows[-1][: 8 * (8 - pad)]
        lines[0] = lines[0].ljust(72) + "+"
        cont = ["+       " + r for r in rows]
        cont = [c.ljust(72) + "+" for c in cont[:-1]] + cont[-1:]
        lines.extend(cont)
    return lines


def bdf_text(mesh, *, material=None, title="implicad tetrahedral mesh") -> tuple:
    """The Nastran deck of `mesh` and the SET1 number of each named face.

    Parameters
    ----------
    mesh : TetMesh
    material : Material or str, optional
        The ``MAT1`` written (default steel, in mm, N, MPa, t/mm^3).
    title : str

    Returns
    -------
    text : str
    sets : dict
        Face name -> SET1 identification number.
    """
    from .deck import parse_material

    mat = parse_material("steel" if material is None else material)
    pts = np.asarray(mesh.points, dtype=np.float64)
    scale = float(np.abs(pts).max(initial=1.0))
    pts = np.where(np.abs(pts) < 1e-13 * scale, 0.0, pts)
    n = len(pts)
    out = ["$ " + title, "SOL 101", "CEND", f"TITLE = {title}", "ECHO = NONE", "BEGIN BULK"]
    ids16 = np.char.rjust(np.arange(1, n + 1).astype(str), 16)
    x = [_real16(pts[:, i]) for i in range(3)]
    line1 = np.char.add(np.char.add(np.char.add("GRID*   ", ids16), " " * 16), np.char.add(x[0], x[1]))
    grid = np.char.add(np.char.add(line1, "\n*       "), x[2])
    out.extend(grid.tolist())
    tets = np.asarray(mesh.tets, dtype=np.int64) + 1
    m = len(tets)
    head = np.char.add(np.char.add("CTETRA  ", _field8(np.arange(1, m + 1))), _field8(np.ones(m)))
    cols = [_field8(tets[:, j]) for j in range(tets.shape[1])]
    for j in range(min(6, tets.shape[1])):
        head = np.char.add(head, cols[j])
    if tets.shape[1] == 10:
        # Field 10 of the first line and field 1 of the second mark the continuation.
        tail = np.char.add(np.char.add(np.char.add(np.char.add("+\n+       ", cols[6]), cols[7]), cols[8]), cols[9])
        head = np.char.add(np.char.ljust(head, 72), tail)
    out.extend(head.tolist())
    out.append("PSOLID  " + f"{1:>8d}{1:>8d}")
    e, nu, rho = _real16([mat.E, mat.nu, mat.rho])
    out.append(f"MAT1*   {1:>16d}{e}{'':16}{nu}\n*       {rho}")
    names = [k for k in mesh.face_sets if k != "surface"]
    sets = nastran_set_ids(names)
    for name, sid in sets.items():
        out.append(f"$ SET1 {sid}: nodes of face {name}")
        out.extend(_set1_lines(sid, np.asarray(mesh.node_sets[name]) + 1))
    out.append("ENDDATA")
    return "\n".join(out) + "\n", sets
