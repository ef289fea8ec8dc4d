"""The tetrahedral mesh the FEA room produces: `TetMesh`, its element sides and its meshio form."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from .quality import TetQuality, tet_quality, tet_volumes  # noqa: F401

__all__ = ["TetMesh", "SIDE_NODES", "set_name", "to_meshio"]

#: Corner nodes of each element side, Abaqus / CalculiX numbering S1..S4
#: (outward normals by the right-hand rule for a positive tetrahedron).
SIDE_NODES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]])

# Mid-edge nodes of each side (positions 4..9 in the element), for 10-node elements.
_SIDE_MIDS = np.array([[6, 5, 4], [4, 8, 7], [5, 9, 8], [6, 7, 9]])


def _side_nodes(tets, elem, side):
    corners = tets[elem[:, None], SIDE_NODES[side]]
    if tets.shape[1] == 10:
        return np.concatenate([corners, tets[elem[:, None], _SIDE_MIDS[side]]], axis=1)
    return corners


@dataclass(frozen=True)
class TetMesh:
    """A tetrahedral mesh with named boundary sets.

    Attributes
    ----------
    points : (n, 3) float
        Node coordinates.
    tets : (m, 4) or (m, 10) int
        Elements, VTK / meshio node order (corners, then mid-edge nodes on
        edges 01, 12, 02, 03, 13, 23).
    boundary : (b, 3) int
        Corner nodes of the boundary triangles, outward.
    boundary_element : (b,) int
        The element each boundary triangle belongs to.
    boundary_side : (b,) int
        Its side, 0..3 for Abaqus S1..S4 (see `SIDE_NODES`).
    face_sets : dict of str -> (k,) int
        Indices into `boundary` for each named region; ``"surface"`` holds all.
    node_sets : dict of str -> (k,) int
        Node indices (corner and mid-edge) on each region.
    quality : TetQuality
    surface_deviation : float or None
        Largest ``|f|`` of the solid over the boundary nodes and face centres.
    """

    points: np.ndarray
    tets: np.ndarray
    boundary: np.ndarray
    boundary_element: np.ndarray
    boundary_side: np.ndarray
    face_sets: dict
    node_sets: dict
    quality: TetQuality
    surface_deviation: float | None = None
    info: dict = field(default_factory=dict)

    @property
    def order(self) -> int:
        """1 for 4-node, 2 for 10-node tetrahedra."""
        return 1 if self.tets.shape[1] == 4 else 2

    @property
    def volume(self) -> float:
        """Sum of the element volumes (curved for 10-node elements)."""
        return float(tet_volumes(self.points, self.tets).sum())

    def to_pyvista(self):
        """The mesh as a `pyvista.UnstructuredGrid`."""
        import pyvista as pv

        ctype = pv.CellType.TETRA if self.order == 1 else pv.CellType.QUADRATIC_TETRA
        return pv.UnstructuredGrid({ctype: np.asarray(self.tets)}, np.asarray(self.points))

    def to_meshio(self):
        """The mesh as a `meshio.Mesh` with point, cell and boundary-triangle sets."""
        return to_meshio(self)


def set_name(name: str) -> str:
    """A set name every format accepts: letters, digits and underscores, starting with a letter.

    Examples
    --------
    >>> set_name("box_1.+x"), set_name("cylinder_2.wall")
    ('box_1_px', 'cylinder_2_wall')
    """
    out = name.replace("+", "p").replace("-", "m")
    out = re.sub(r"[^A-Za-z0-9_]", "_", out)
    if not out or not out[0].isalpha():
        out = "s_" + out
    return out


def _cell_type(mesh):
    return "tetra" if mesh.order == 1 else "tetra10"


def _boundary_cells(mesh):
    """Boundary triangles with their mid nodes for 10-node meshes (meshio triangle6 order)."""
    nodes = _side_nodes(mesh.tets, mesh.boundary_element, mesh.boundary_side)
    if mesh.order == 2:
        # Side mids are on edges (c0c1, c1c2, c2c0) in _SIDE_MIDS order: reorder to triangle6.
        return "triangle6", nodes
    return "triangle", nodes


def _region_ids(mesh):
    """Region number (1..) of each boundary face and the names in order."""
    names = [k for k in mesh.face_sets if k != "surface"]
    region = np.zeros(len(mesh.boundary), dtype=np.int64)
    for i, k in enumerate(names):
        region[mesh.face_sets[k]] = i + 1
    return region, names


def to_meshio(mesh, *, with_boundary: bool = True):
    """A `meshio.Mesh` of `mesh`: elements, boundary triangles, node and element sets.

    Parameters
    ----------
    mesh : TetMesh
    with_boundary : bool
        Add the boundary triangles as a second cell block.
    """
    import meshio

    cells = [(_cell_type(mesh), np.asarray(mesh.tets))]
    region, names = _region_ids(mesh)
    cell_sets = {}
    if with_boundary:
        tri_type, tri = _boundary_cells(mesh)
        cells.append((tri_type, tri))
        for i, k in enumerate(names):
            cell_sets[set_name(k)] = [np.zeros(0, dtype=np.int64), np.nonzero(region == i + 1)[0]]
    point_sets = {set_name(k): np.asarray(v) for k, v in mesh.node_sets.items()}
    return meshio.Mesh(np.asarray(mesh.points), cells, point_sets=point_sets, cell_sets=cell_sets)
