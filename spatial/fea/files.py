"""Files for analysts: Gmsh, Abaqus / CalculiX, VTK, Nastran, and boundary STL / PLY.

Every writer works on a `TetMesh` and writes atomically (a temporary file in
the same folder, then ``os.replace``), so a failure never leaves half a file.
Named boundary regions travel as the format allows:

========  =====================  ==============================================
format    node sets              face (element side) sets
========  =====================  ==============================================
.msh      (nodes of the groups)  physical groups of boundary triangles
.inp      ``*NSET``              ``*ELSET`` per side + ``*SURFACE, TYPE=ELEMENT``
.vtu      point data masks       ``region`` cell data on boundary triangles
.bdf      ``SET1`` cards         (none: comments name the sets)
.stl/.ply (none)                 (none: the boundary triangles only)
========  =====================  ==============================================
"""

from __future__ import annotations

import os

import numpy as np

from ..files.atomic import atomic_write as _atomic_write
from .model import TetMesh, _boundary_cells, _cell_type, _region_ids, set_name, to_meshio  # noqa: F401

__all__ = ["FEA_FORMATS", "fea_format", "write_fea", "to_meshio", "set_name"]

#: Extension -> description of the formats `write_fea` knows.
FEA_FORMATS = {
    ".msh": "Gmsh mesh (4.1, or 2.2 with format_version='2.2')",
    ".inp": "Abaqus / CalculiX input",
    ".vtu": "VTK unstructured grid",
    ".bdf": "Nastran bulk data (large-field GRID*, free-field CTETRA)",
    ".nas": "Nastran bulk data (as .bdf)",
    ".stl": "boundary triangles, STL",
    ".ply": "boundary triangles, PLY",
}


def fea_format(path) -> str:
    """The extension of `path` if `write_fea` knows it, else a `ValueError` listing the known ones."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FEA_FORMATS:
        raise ValueError(f"output: unknown extension {ext or '(none)'!r}; expected one of {', '.join(FEA_FORMATS)}")
    return ext


def _write_gmsh(mesh, path, version):
    import meshio

    tri_type, tri = _boundary_cells(mesh)
    region, names = _region_ids(mesh)
    vol_tag = len(names) + 1
    # One cell block per boundary region: Gmsh 4 writes one entity per block.
    cells = [(_cell_type(mesh), np.asarray(mesh.tets))]
    phys = [np.full(len(mesh.tets), vol_tag, dtype=np.int64)]
    geom = [np.ones(len(mesh.tets), dtype=np.int64)]
    for r in np.unique(region):
        sel = tri[region == r]
        cells.append((tri_type, sel))
        phys.append(np.full(len(sel), r, dtype=np.int64))
        geom.append(np.full(len(sel), r, dtype=np.int64))
    field_data = {set_name(k): np.array([i + 1, 2]) for i, k in enumerate(names)}
    field_data["volume"] = np.array([vol_tag, 3])
    point_data = {}
    if version != "2.2":
        # Gmsh 4 classifies every node on an entity: the volume, or the boundary region of one
        # of its faces (meshio then writes the nodes grouped by entity, so their order changes).
        dim_tags = np.tile(np.array([3, 1], dtype=np.int64), (len(mesh.points), 1))
        dim_tags[tri.reshape(-1)] = np.stack([np.full(tri.size, 2), np.repeat(region, tri.shape[1])], axis=1)
        point_data["gmsh:dim_tags"] = dim_tags
    m = meshio.Mesh(np.asarray(mesh.points), cells, cell_data={"gmsh:physical": phys, "gmsh:geometrical": geom},
                    point_data=point_data, field_data=field_data)
    fmt = "gmsh22" if version == "2.2" else "gmsh"
    _atomic_write(path, lambda tmp: meshio.write(tmp, m, file_format=fmt, binary=False))


def _write_inp(mesh, path):
    import meshio

    m = to_meshio(mesh, with_boundary=False)
    # Element sides per region: *ELSET name_S<k> and *SURFACE, TYPE=ELEMENT.
    region, names = _region_ids(mesh)
    lines = []
    for i, k in enumerate(["surface"] + names):
        sel = np.arange(len(region)) if k == "surface" else np.nonzero(region == i)[0]
        nm = set_name(k).upper()
        entries = []
        for s in range(4):
            el = mesh.boundary_element[sel][mesh.boundary_side[sel] == s] + 1
            if el.size == 0:
                continue
            es = f"{nm}_S{s + 1}"
            lines.append(f"*ELSET, ELSET={es}")
            lines.extend(", ".join(str(v) for v in row) for row in np.array_split(el, max(1, -(-el.size // 16))))
            entries.append(f"{es}, S{s + 1}")
        lines.append(f"*SURFACE, NAME={nm}_FACES, TYPE=ELEMENT")
        lines.extend(entries)

    def write(tmp):
        meshio.write(tmp, m, file_format="abaqus")
        with open(tmp, "a", encoding="ascii") as fh:
            fh.write("\n".join(lines) + "\n")

    _atomic_write(path, write)


def _write_vtu(mesh, path):
    import meshio

    tri_type, tri = _boundary_cells(mesh)
    region, names = _region_ids(mesh)
    point_data = {}
    for k, v in mesh.node_sets.items():
        mask = np.zeros(len(mesh.points), dtype=np.uint8)
        mask[v] = 1
        point_data[f"nodeset_{set_name(k)}"] = mask
    m = meshio.Mesh(np.asarray(mesh.points), [(_cell_type(mesh), np.asarray(mesh.tets)), (tri_type, tri)],
                    point_data=point_data, cell_data={"region": [np.zeros(len(mesh.tets), dtype=np.int64), region]})
    _atomic_write(path, lambda tmp: meshio.write(tmp, m, file_format="vtu"))


def _write_bdf(mesh, path):
    """Free-field Nastran: large-field GRID* cards (16-character numbers), CTETRA, SET1."""
    pts = np.asarray(mesh.points, dtype=np.float64)
    ids = np.arange(1, len(pts) + 1)
    out = ["$ implicad tetrahedral mesh", "BEGIN BULK"]
    # Large-field fixed format GRID*: 8-character key, 16-character fields (id, cp, x1, x2),
    # then a continuation line holding x3.  "%16.9e" is exactly 16 characters for |x| < 1e100.
    xs = [np.char.mod("%16.9e", pts[:, i]) for i in range(3)]
    head = np.char.add(np.char.add("GRID*   ", np.char.rjust(ids.astype(str), 16)), " " * 16)
    grid = np.char.add(np.char.add(np.char.add(head, xs[0]), xs[1]), np.char.add("\n*       ", xs[2]))
    out.extend(grid.tolist())
    tets = np.asarray(mesh.tets) + 1
    eids = np.arange(1, len(tets) + 1).astype(str)
    cols = [tets[:, j].astype(str) for j in range(tets.shape[1])]
    head = np.char.add(np.char.add("CTETRA,", eids), ",1")
    for j in range(min(6, tets.shape[1])):
        head = np.char.add(np.char.add(head, ","), cols[j])
    if tets.shape[1] == 10:
        tail = np.char.add("\n+", "")
        for j in range(6, 10):
            tail = np.char.add(np.char.add(tail, ","), cols[j])
        head = np.char.add(head, tail)
    out.extend(head.tolist())
    out.append("PSOLID,1,1")
    for i, (k, v) in enumerate(mesh.node_sets.items()):
        out.append(f"$ node set {i + 1}: {set_name(k)}")
        vals = (np.asarray(v) + 1).astype(str)
        rows = [",".join(vals[j:j + 7]) for j in range(0, len(vals), 7)]
        out.append(f"SET1,{i + 1}," + rows[0])
        out.extend("+," + r for r in rows[1:])
    out.append("ENDDATA")

    def write(tmp):
        with open(tmp, "w", encoding="ascii") as fh:
            fh.write("\n".join(out) + "\n")

    _atomic_write(path, write)


def _write_surface(mesh, path):
    import pyvista as pv

    surf = pv.PolyData.from_regular_faces(np.asarray(mesh.points), np.asarray(mesh.boundary)).clean()
    _atomic_write(path, lambda tmp: surf.save(tmp))


def write_fea(mesh, path, *, format_version: str = "4.1") -> str:
    """Write a `TetMesh` to `path`; the extension picks the format (`FEA_FORMATS`).

    Parameters
    ----------
    mesh : TetMesh
    path : str or os.PathLike
    format_version : {"4.1", "2.2"}
        Gmsh file version (ignored for other formats).

    Returns
    -------
    str
        The path written.

    Raises
    ------
    TypeError
        When `mesh` is not a TetMesh.
    ValueError
        On an unknown extension or Gmsh version (before anything is written).

    Examples
    --------
    >>> write_fea(mesh, "part.inp")                 # doctest: +SKIP
    'part.inp'
    """
    if not isinstance(mesh, TetMesh):
        raise TypeError(f"mesh: expected a TetMesh, got {type(mesh).__name__}")
    ext = fea_format(path)
    if format_version not in ("4.1", "2.2"):
        raise ValueError(f"format_version: expected '4.1' or '2.2', got {format_version!r}")
    if ext == ".msh":
        _write_gmsh(mesh, path, format_version)
    elif ext == ".inp":
        _write_inp(mesh, path)
    elif ext == ".vtu":
        _write_vtu(mesh, path)
    elif ext in (".bdf", ".nas"):
        _write_bdf(mesh, path)
    else:
        _write_surface(mesh, path)
    return os.fspath(path)
