"""Files for analysts: Gmsh, Abaqus / CalculiX, VTK, Nastran, and boundary STL / PLY.

Every writer works on a `TetMesh` and writes atomically (a temporary file in
the same folder, then ``os.replace``), so a failure never leaves half a file.
Named boundary regions travel as the format allows:

========  =====================  ==============================================
format    node sets              face (element side) sets
========  =====================  ==============================================
.msh      (nodes of the groups)  physical groups of boundary triangles
.inp      ``*NSET``              ``*ELSET`` per side + ``*SURFACE, TYPE=ELEMENT``
.vtu      point data masks       ``region`` cell data, names in field data
.bdf      ``SET1`` cards         (none: comments name the sets)
.med      node families/groups   element families/groups (faces; ``volume``)
.stl/.ply (none)                 (none: the boundary triangles only)
========  =====================  ==============================================
"""

from __future__ import annotations

import os

import numpy as np

from ..files.atomic import atomic_write as _atomic_write
from .model import TetMesh, _boundary_cells, _cell_type, _region_ids, set_name, to_meshio  # noqa: F401

__all__ = ["FEA_FORMATS", "fea_format", "write_fea", "to_meshio", "set_name", "set_names"]

#: Extension -> description of the formats `write_fea` knows.
FEA_FORMATS = {
    ".msh": "Gmsh mesh (4.1, or 2.2 with format_version='2.2')",
    ".inp": "Abaqus / CalculiX input (C3D4 / C3D10, NSET and SURFACE per face)",
    ".vtu": "VTK unstructured grid",
    ".bdf": "Nastran input (SOL 101, GRID*, CTETRA, PSOLID, MAT1, SET1 per face)",
    ".nas": "Nastran bulk data (as .bdf)",
    ".med": "MED / HDF5 (Salome, Code_Aster): node and element groups per face, the elements in 'volume'",
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
    # Physical names are quoted strings in both versions: the face names go in unchanged.
    field_data = {k: np.array([i + 1, 2]) for i, k in enumerate(names)}
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


#: VTK / meshio corner and mid-edge order -> MED's (Salome's connectivity: corners 0 2 1 3,
#: then the mid nodes of the edges 02, 21, 10, 03, 23, 13 of that order).
_MED_ORDER = {4: [0, 2, 1, 3], 10: [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]}


def _write_med(mesh, path):
    """MED 3.0 through meshio: each face set a group of boundary triangles (and of their
    nodes), the elements the group ``volume``; entities take MED families (negative numbers
    for elements, positive for nodes), one per combination of groups."""
    import meshio

    tri_type, tri = _boundary_cells(mesh)
    region, names = _region_ids(mesh)
    tets = np.asarray(mesh.tets)[:, _MED_ORDER[mesh.tets.shape[1]]]
    cell_tags = {-1: ["volume"], -2: ["surface"]}
    for i, k in enumerate(names):
        cell_tags[-(i + 3)] = [set_name(k), "surface"]
    tri_family = np.where(region > 0, -(region + 2), -2)
    sets = list(mesh.node_sets)
    member = np.zeros((len(mesh.points), len(sets)), dtype=bool)
    for j, k in enumerate(sets):
        member[np.asarray(mesh.node_sets[k]), j] = True
    rows, family = np.unique(member, axis=0, return_inverse=True)
    family = family.reshape(-1) + 1
    point_tags = {}
    for f, row in enumerate(rows, start=1):
        groups = [set_name(sets[j]) for j in np.nonzero(row)[0]]
        if groups:
            point_tags[f] = groups
        else:
            family[family == f] = 0  # MED's family 0: no group
    m = meshio.Mesh(np.asarray(mesh.points, dtype=np.float64), [(_cell_type(mesh), tets), (tri_type, tri)],
                    point_data={"point_tags": family.astype(np.int64)},
                    cell_data={"cell_tags": [np.full(len(tets), -1, dtype=np.int64), tri_family.astype(np.int64)]})
    m.point_tags = point_tags
    m.cell_tags = cell_tags
    _atomic_write(path, lambda tmp: (meshio.write(tmp, m, file_format="med"), _short_family_names(tmp)))


#: Longest MED family name (MED_NAME_SIZE).
_MED_NAME_SIZE = 64


def _short_family_names(path):
    """Rename families whose name (meshio joins their groups into it) is over MED's 64 characters."""
    import h5py

    with h5py.File(path, "r+") as f:
        for kind in ("NOEUD", "ELEME"):
            where = f.get(f"FAS/mesh/{kind}")
            if where is None:
                continue
            for name in list(where):
                if len(name) > _MED_NAME_SIZE:
                    where.move(name, f"FAM_{int(where[name].attrs['NUM'])}")


def _write_inp(mesh, path):
    from .abaqus import abaqus_names, inp_mesh_text

    names = abaqus_names(_face_names(mesh))
    text = "*HEADING\nimplicad tetrahedral mesh\n" + inp_mesh_text(mesh, names)
    _atomic_write(path, lambda tmp: _write_text(tmp, text))


def _write_text(tmp, text):
    with open(tmp, "w", encoding="ascii") as fh:
        fh.write(text)


def _face_names(mesh):
    return [k for k in mesh.face_sets if k != "surface"]


def _write_vtu(mesh, path):
    import pyvista as pv

    tri_type, tri = _boundary_cells(mesh)
    region, names = _region_ids(mesh)
    quadratic = mesh.order == 2
    cells = {pv.CellType.QUADRATIC_TETRA if quadratic else pv.CellType.TETRA: np.asarray(mesh.tets),
             pv.CellType.QUADRATIC_TRIANGLE if quadratic else pv.CellType.TRIANGLE: np.asarray(tri)}
    grid = pv.UnstructuredGrid(cells, np.asarray(mesh.points, dtype=np.float64))
    # pyvista orders the blocks by cell type: tetrahedra (10, 24) come after triangles (5, 22).
    is_tet = np.isin(np.asarray(grid.celltypes), [pv.CellType.TETRA, pv.CellType.QUADRATIC_TETRA])
    cell_region = np.zeros(grid.n_cells, dtype=np.int64)
    cell_region[~is_tet] = region
    grid.cell_data["region"] = cell_region
    for k, v in mesh.node_sets.items():
        mask = np.zeros(len(mesh.points), dtype=np.uint8)
        mask[v] = 1
        grid.point_data[f"nodeset_{set_name(k)}"] = mask
    # Region names travel as field data (meshio's writer drops it, so pyvista writes the file):
    # one array per name holding its number in the `region` cell data; 0 is the volume.
    for i, k in enumerate(names):
        grid.field_data[k] = np.array([i + 1], dtype=np.int64)
    grid.field_data["volume"] = np.array([0], dtype=np.int64)
    _atomic_write(path, lambda tmp: grid.save(tmp, binary=True))


def _write_bdf(mesh, path, material=None):
    from .nastran import bdf_text

    text, _ = bdf_text(mesh, material=material)
    _atomic_write(path, lambda tmp: _write_text(tmp, text))


def set_names(mesh, path) -> dict:
    """How each named face of `mesh` is called in the file `path` (by its extension).

    ``.inp``: the node set (the surface is that name plus ``_F``); ``.bdf``:
    the SET1 number; ``.msh`` / ``.vtu``: the face name itself (a physical
    group / field-data name); ``.med``: the group (of triangles and of nodes);
    ``.stl`` / ``.ply`` carry no sets (empty).

    Examples
    --------
    >>> set_names(mesh, "beam.inp")["box_0.-x"]             # doctest: +SKIP
    'BOX_0_MX'
    """
    ext = fea_format(path)
    faces = _face_names(mesh)
    if ext == ".inp":
        from .abaqus import abaqus_names

        return abaqus_names(faces)
    if ext in (".bdf", ".nas"):
        from .nastran import nastran_set_ids

        return {k: f"SET1 {v}" for k, v in nastran_set_ids(faces).items()}
    if ext in (".msh", ".vtu"):
        return {k: k for k in faces}
    if ext == ".med":
        return {k: f"group {set_name(k)}" for k in faces}
    return {}


def _write_surface(mesh, path):
    import pyvista as pv

    surf = pv.PolyData.from_regular_faces(np.asarray(mesh.points), np.asarray(mesh.boundary)).clean()
    _atomic_write(path, lambda tmp: surf.save(tmp))


def write_fea(mesh, path, *, format_version: str = "4.1", material=None) -> str:
    """Write a `TetMesh` to `path`; the extension picks the format (`FEA_FORMATS`).

    Parameters
    ----------
    mesh : TetMesh
    path : str or os.PathLike
    format_version : {"4.1", "2.2"}
        Gmsh file version (ignored for other formats).
    material : Material or str, optional
        The Nastran ``MAT1`` (default steel; see `spatial.fea.deck.parse_material`).

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
        _write_bdf(mesh, path, material)
    elif ext == ".med":
        _write_med(mesh, path)
    else:
        _write_surface(mesh, path)
    return os.fspath(path)
