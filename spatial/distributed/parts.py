"""A mesh kept in parts on disk: one .vtp per brick, a .pvtp index over them, merged on demand.

Every part is a closed-off piece of the surface (the triangles of one brick)
whose vertices carry their lattice-edge id (``edge_id``) and whether they lie
in a face between bricks (``shared``).  ParaView opens the .pvtp as one
dataset; `PartitionedMesh.gather` merges the parts into one closed mesh,
fusing the vertices of neighbouring parts by their edge ids (integers: no
floating-point tolerance), when it fits in memory.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import numpy as np

from ..files.atomic import atomic_write
from ..meshing import merge_blocks

__all__ = ["PartitionedMesh", "merge_parts", "write_pvtp"]

_PVTP = """<?xml version="1.0"?>
<VTKFile type="PPolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PPolyData GhostLevel="0">
    <PPointData>
      <PDataArray type="Int64" Name="edge_id"/>
      <PDataArray type="UInt8" Name="shared"/>
    </PPointData>
    <PPoints>
      <PDataArray type="Float64" NumberOfComponents="3"/>
    </PPoints>
{pieces}
  </PPolyData>
</VTKFile>
"""


def write_pvtp(path, sources):
    """Write the .pvtp index of part files `sources` (paths relative to the index's folder)."""
    pieces = "\n".join(f"    <Piece Source={quoteattr(s)}/>" for s in sources)
    text = _PVTP.format(pieces=pieces)

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
    return atomic_write(path, write, ".pvtp")


def merge_parts(parts):
    """One indexed mesh from per-brick arrays; vertices on brick faces fused by lattice-edge id.

    Parameters
    ----------
    parts : list of dict
        ``points`` (v, 3), ``faces`` (f, 3) local indices, ``edges`` (v,)
        int64, ``shared`` (v,) bool.  Emptied as it is merged.

    Returns
    -------
    points : (n, 3) float64
    faces : (m, 3) int
    """
    blocks = []
    while parts:
        p = parts.pop(0)
        if p["faces"].shape[0]:
            blocks.append((p["edges"][p["shared"]], p["shared"], (p["points"],), p["faces"]))
    data, faces = merge_blocks(blocks)
    if data is None:
        return np.empty((0, 3)), faces
    return data[0], faces


@dataclass
class PartitionedMesh:
    """A boundary mesh written as parts (one .vtp per brick) under a .pvtp index.

    Attributes
    ----------
    index : str
        The .pvtp file (ParaView, VTK's ``vtkXMLPPolyDataReader`` and
        ``pyvista.read`` open it as one dataset).
    parts : list of str
        The part files, in brick order.
    triangles : int
        Triangles over all parts (each in exactly one part).
    part_points : int
        Vertices over all parts (those on brick faces counted once per part).
    voxel_size, evaluations, seconds : float, int, float
    bricks : list of dict
        Per brick (task): ``triangles``, ``points``, ``boundary_cells``,
        ``evaluations``, ``seconds`` / ``cpu_seconds`` of the meshing,
        ``write_seconds``, and ``peak_rss`` of the worker after it.
    """

    index: str
    parts: list = field(default_factory=list)
    triangles: int = 0
    part_points: int = 0
    voxel_size: float = 0.0
    evaluations: int = 0
    seconds: float = 0.0
    bricks: list = field(default_factory=list, repr=False)

    def gather(self, *, max_triangles=None):
        """The parts merged into one closed `pyvista.PolyData` (vertices fused by lattice-edge id).

        Parameters
        ----------
        max_triangles : int, optional
            Refuse (ValueError) a mesh larger than this, before reading it.
        """
        import pyvista as pv

        if max_triangles is not None and self.triangles > int(max_triangles):
            raise ValueError(f"max_triangles: the mesh has {self.triangles} triangles, more than {max_triangles}; "
                             f"open {self.index} part by part instead")
        loaded = []
        for path in self.parts:
            part = pv.read(path)
            loaded.append(dict(points=np.asarray(part.points, dtype=np.float64),
                               faces=np.asarray(part.regular_faces), edges=np.asarray(part.point_data["edge_id"]),
                               shared=np.asarray(part.point_data["shared"]).astype(bool)))
        points, faces = merge_parts(loaded)
        out = pv.PolyData.from_regular_faces(points, faces)
        out.field_data["voxel_size"] = np.array([self.voxel_size])
        out.field_data["evaluations"] = np.array([self.evaluations], dtype=np.int64)
        return out

    @property
    def folder(self) -> str:
        return os.path.dirname(os.path.abspath(self.index))
