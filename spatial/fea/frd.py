"""CalculiX results (``.frd``, ASCII) read into pyvista.

The ``.frd`` file is made of fixed-width blocks (CalculiX GraphiX manual,
section "Result Format"): ``2C`` nodes (`` -1`` records: node number, three
coordinates), ``3C`` elements (`` -1`` number and type, `` -2`` node
numbers) and, per result, a ``100C`` block of `` -1`` records (node
number, then the components in 12-character fields, which may run into
each other: ``0.00000E+00-2.12245E-04``).  The last number of a block's
header line gives the width of the numbers: 5 characters (short format)
or 10 (long format).

`read_frd` returns the last increment of every result as point data of a
`pyvista.UnstructuredGrid`: ``DISP`` (n, 3), ``STRESS`` (n, 6 in the order
xx, yy, zz, xy, yz, zx), ``FORC`` ... plus ``von_mises`` from the stresses.

References
----------
G. Dhondt, K. Wittig, CalculiX GraphiX manual 2.20, section 11 (the frd
result format).
"""

from __future__ import annotations

import os

import numpy as np

__all__ = ["read_frd", "von_mises", "FRD_CELL_TYPES"]

#: frd element type -> (VTK cell type, node count); node orders agree for these types.
FRD_CELL_TYPES = {1: (12, 8), 3: (10, 4), 6: (24, 10), 7: (5, 3), 9: (9, 4)}


def von_mises(stress) -> np.ndarray:
    """Von Mises stress of ``(n, 6)`` components xx, yy, zz, xy, yz, zx.

    Examples
    --------
    >>> float(von_mises([[100.0, 0, 0, 0, 0, 0]])[0])
    100.0
    """
    s = np.asarray(stress, dtype=np.float64).reshape(-1, 6)
    xx, yy, zz, xy, yz, zx = s.T
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3.0 * (xy**2 + yz**2 + zx**2))


def _fields(lines, start, width, count):
    """`count` fixed-width numbers from column `start` of equally long byte lines, (n, count)."""
    if not lines:
        return np.zeros((0, count))
    length = start + width * count
    arr = np.array([ln.ljust(length)[:length] for ln in lines], dtype=f"S{length}")
    chars = arr.view(np.uint8).reshape(len(lines), length)
    cols = chars[:, start:].reshape(len(lines), count, width).copy()
    return cols.view(f"S{width}").reshape(len(lines), count).astype(np.float64)


def _ints(lines, start, width, count):
    return _fields(lines, start, width, count).astype(np.int64)


def _blocks(text):
    """The file as a list of (header line, data lines) per block."""
    blocks, head, body = [], None, []
    for line in text.splitlines():
        key = line[:6].strip()
        if key in ("2C", "3C") or line.startswith("  100C"):
            head, body = line, []
        elif line.startswith(" -3") and head is not None:
            blocks.append((head, body))
            head = None
        elif head is not None:
            body.append(line)
    return blocks


def _width(head):
    """Width of integers in a block: the header's last number is 1 (long, 10) or 0 (short, 5)."""
    flag = head.split()[-1]
    return 10 if flag.strip().endswith("1") else 5


def read_frd(path):
    """Nodes, elements and the last increment of each nodal result of a CalculiX ``.frd``.

    Parameters
    ----------
    path : str or os.PathLike
        An ASCII results file (``*NODE FILE`` / ``*EL FILE`` output).

    Returns
    -------
    pyvista.UnstructuredGrid
        Point data ``DISP``, ``STRESS``, ``FORC`` ... as written, and
        ``von_mises`` when stresses are present; ``field_data["node_ids"]``
        holds the solver's node numbers.

    Raises
    ------
    FileNotFoundError
        When `path` does not exist.
    ValueError
        When the file holds no nodes (not a results file) or is binary.

    Examples
    --------
    >>> grid = read_frd("beam.frd")                      # doctest: +SKIP
    >>> float(grid.point_data["DISP"][:, 2].min())      # doctest: +SKIP
    -1.9
    """
    import pyvista as pv

    path = os.fspath(path)
    with open(path, "rb") as fh:
        raw = fh.read()
    try:
        text = raw.decode("ascii")
    except UnicodeDecodeError as exc:
        raise ValueError(f"path: {path!r} is not an ASCII .frd file (write it with CalculiX's default "
                         "ASCII output)") from exc
    blocks = _blocks(text)
    nodes = [b for b in blocks if b[0][:6].strip() == "2C"]
    if not nodes:
        raise ValueError(f"path: {path!r} holds no node block; expected a CalculiX .frd results file")
    head, body = nodes[0]
    w = _width(head)
    rec = [ln for ln in body if ln.startswith(" -1")]
    ids = _ints(rec, 3, w, 1)[:, 0]
    xyz = _fields([ln[3 + w:] for ln in rec], 0, 12, 3)
    index = np.full(ids.max(initial=0) + 1, -1, dtype=np.int64)
    index[ids] = np.arange(ids.size)
    cells, types = [], []
    for head, body in (b for b in blocks if b[0][:6].strip() == "3C"):
        w = _width(head)
        # An element: one " -1" record (number, type, group, material) then " -2" lines of nodes.
        starts = [i for i, ln in enumerate(body) if ln.startswith(" -1")]
        etype = _ints([body[i] for i in starts], 3 + w, 5, 1)[:, 0]
        ends = starts[1:] + [len(body)]
        conn = ["".join(ln[3:] for ln in body[s + 1:e]) for s, e in zip(starts, ends)]
        for t in np.unique(etype):
            if int(t) not in FRD_CELL_TYPES:
                raise ValueError(f"path: element type {int(t)} of {path!r} is not supported "
                                 f"(known: {sorted(FRD_CELL_TYPES)})")
            vtk, k = FRD_CELL_TYPES[int(t)]
            sel = [c for c, e in zip(conn, etype) if e == t]
            nn = _ints(sel, 0, w, k)
            cells.append(np.concatenate([np.full((len(sel), 1), k), index[nn]], axis=1).reshape(-1))
            types.append(np.full(len(sel), vtk, dtype=np.uint8))
    grid = pv.UnstructuredGrid(np.concatenate(cells) if cells else np.zeros(0, np.int64),
                               np.concatenate(types) if types else np.zeros(0, np.uint8), xyz)
    grid.field_data["node_ids"] = ids
    for head, body in (b for b in blocks if b[0].startswith("  100C")):
        w = _width(head)
        name = next((ln[5:13].strip() for ln in body if ln.startswith(" -4")), "")
        comps = [ln for ln in body if ln.startswith(" -5")]
        n_comp = len([c for c in comps if c[5:13].strip() != "ALL"])
        rec = [ln for ln in body if ln.startswith(" -1")]
        if not name or not rec:
            continue
        nid = _ints(rec, 3, w, 1)[:, 0]
        vals = _fields([ln[3 + w:] for ln in rec], 0, 12, n_comp)
        data = np.zeros((ids.size, n_comp))
        data[index[nid]] = vals
        # Later increments overwrite earlier ones: the last one is kept.
        grid.point_data[name] = data[:, 0] if n_comp == 1 else data
    if "STRESS" in grid.point_data:
        grid.point_data["von_mises"] = von_mises(grid.point_data["STRESS"])
    return grid
