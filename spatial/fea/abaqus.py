"""Abaqus / CalculiX input files: the mesh with its named sets.

CalculiX reads at most 20 characters per field, so coordinates are written
with 13 significant digits (``-1.234567890123e+02`` is 19 characters) and
values below ``1e-13`` of the part's size are written as 0.  Every element
goes into the element set of its region (``*ELEMENT, ELSET=...``); each named
boundary face gets a node set, one element set per element side (S1..S4) and
a ``*SURFACE, TYPE=ELEMENT`` made of them.  4-node elements are ``C3D4``,
10-node ones ``C3D10`` (same node order as VTK: corners, then the mid-edge
nodes of edges 12, 23, 31, 14, 24, 34).

References
----------
G. Dhondt, CalculiX CrunchiX user's manual 2.20: ``*NODE``, ``*ELEMENT``,
``*NSET``, ``*ELSET``, ``*SURFACE`` (element face numbering for C3D4 / C3D10:
S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1).
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["abaqus_name", "abaqus_names", "inp_mesh_text", "ELEMENT_SET", "IDS_PER_LINE"]

#: The element set that holds every element.
ELEMENT_SET = "EALL"
#: Numbers per data line of a set (Abaqus allows 16).
IDS_PER_LINE = 16
#: Abaqus names are at most 80 characters.
_MAX_NAME = 80


def abaqus_name(name: str) -> str:
    """A set name Abaqus and CalculiX accept: upper case letters, digits, underscores.

    ``+`` and ``-`` become ``P`` and ``M`` so the six faces of a box stay apart.

    Examples
    --------
    >>> abaqus_name("box_0.-x"), abaqus_name("cylinder_2.wall")
    ('BOX_0_MX', 'CYLINDER_2_WALL')
    """
    out = name.replace("+", "p").replace("-", "m")
    out = re.sub(r"[^A-Za-z0-9_]", "_", out).upper()
    if not out or not out[0].isalpha():
        out = "S_" + out
    return out[:_MAX_NAME - 4]


def abaqus_names(names) -> dict:
    """Distinct Abaqus names for `names` (a suffix ``_2``, ``_3`` ... resolves clashes).

    Examples
    --------
    >>> abaqus_names(["a.b", "a_b"])
    {'a.b': 'A_B', 'a_b': 'A_B_2'}
    """
    out, used = {}, {ELEMENT_SET, "NALL"}
    for n in names:
        base = abaqus_name(n)
        cand, k = base, 1
        while cand in used:
            k += 1
            cand = f"{base}_{k}"
        used.add(cand)
        out[n] = cand
    return out


def _id_lines(ids) -> list:
    """1-based ids, `IDS_PER_LINE` to a line, comma separated."""
    ids = np.asarray(ids, dtype=np.int64).reshape(-1)
    if ids.size == 0:
        return []
    pad = (-ids.size) % IDS_PER_LINE
    table = np.concatenate([ids, np.zeros(pad, dtype=np.int64)]).reshape(-1, IDS_PER_LINE).astype(str)
    lines = [", ".join(row) for row in table[:-1]]
    last = table[-1][: IDS_PER_LINE - pad] if pad else table[-1]
    return lines + [", ".join(last)]


def number_text(values, scale: float = 1.0) -> np.ndarray:
    """Numbers as text that fits a 20-character field (13 significant digits).

    Values smaller than ``1e-13 * scale`` are written as 0 (round-off of
    coordinates that are 0 on the part).

    Examples
    --------
    >>> number_text([2.6400375244011195e-15, -5.0, 1.0 / 3.0], scale=10.0).tolist()
    ['0', '-5', '0.3333333333333']
    """
    v = np.asarray(values, dtype=np.float64)
    v = np.where(np.abs(v) < 1e-13 * scale, 0.0, v)
    return np.char.mod("%.13g", v)


def inp_mesh_text(mesh, names: dict, *, element_set: str = ELEMENT_SET) -> str:
    """The ``*NODE``, ``*ELEMENT`` and set blocks of `mesh` as text.

    Parameters
    ----------
    mesh : TetMesh
    names : dict
        Region name -> Abaqus name (`abaqus_names`) of every face written.
    element_set : str
        The element set of the (single) region.
    """
    pts = np.asarray(mesh.points, dtype=np.float64)
    scale = float(np.abs(pts).max(initial=1.0))
    ids = np.arange(1, len(pts) + 1).astype(str)
    cols = [number_text(pts[:, i], scale) for i in range(3)]
    node_lines = np.char.add(np.char.add(np.char.add(np.char.add(np.char.add(ids, ", "), cols[0]), ", "),
                                         np.char.add(cols[1], ", ")), cols[2])
    tets = np.asarray(mesh.tets, dtype=np.int64) + 1
    etype = "C3D4" if tets.shape[1] == 4 else "C3D10"
    table = np.concatenate([np.arange(1, len(tets) + 1)[:, None], tets], axis=1).astype(str)
    # Abaqus data lines hold at most 16 entries: 11 for C3D10 fit on one line.
    elem_lines = [", ".join(row) for row in table]
    out = ["*NODE, NSET=NALL"]
    out.extend(node_lines.tolist())
    out.append(f"*ELEMENT, TYPE={etype}, ELSET={element_set}")
    out.extend(elem_lines)
    for region, nm in names.items():
        out.append(f"*NSET, NSET={nm}")
        out.extend(_id_lines(np.asarray(mesh.node_sets[region]) + 1))
    for region, nm in names.items():
        sel = np.asarray(mesh.face_sets[region])
        entries = []
        for s in range(4):
            el = np.sort(np.asarray(mesh.boundary_element)[sel][np.asarray(mesh.boundary_side)[sel] == s]) + 1
            if el.size == 0:
                continue
            es = f"{nm}_S{s + 1}"
            out.append(f"*ELSET, ELSET={es}")
            out.extend(_id_lines(el))
            entries.append(f"{es}, S{s + 1}")
        out.append(f"*SURFACE, NAME={surface_name(nm)}, TYPE=ELEMENT")
        out.extend(entries)
    return "\n".join(out) + "\n"


def surface_name(set_name: str) -> str:
    """The ``*SURFACE`` name of the face whose node set is `set_name`.

    Examples
    --------
    >>> surface_name("BOX_0_MX")
    'BOX_0_MX_F'
    """
    return f"{set_name}_F"
