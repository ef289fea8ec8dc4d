"""Files: triangle meshes (STL, PLY, OBJ, VTP, VTK).

Every writer checks the file name's extension before any work and writes
atomically (`spatial.files.atomic_write`), so a failure never leaves half a
file behind.
"""

from __future__ import annotations

import os
import sys

import numpy as np

from .atomic import atomic_write

__all__ = ["MESH_FORMATS", "save_mesh", "load_mesh", "mesh_format"]

#: File extensions of meshes and their descriptions.
MESH_FORMATS = {
    ".stl": "binary STL",
    ".ply": "binary PLY",
    ".obj": "Wavefront OBJ",
    ".vtp": "VTK XML PolyData",
    ".vtk": "legacy VTK",
}


def mesh_format(path) -> str:
    """The extension of `path` if it is a known mesh format, else ValueError listing them."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name, got {type(path).__name__}")
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in MESH_FORMATS:
        known = ", ".join(MESH_FORMATS)
        raise ValueError(f"{os.fspath(path)}: unknown mesh format {ext or '(no extension)'!r}; known: {known}")
    return ext


def save_mesh(mesh, path) -> str:
    """Write a triangle mesh, the format chosen by the extension, atomically.

    Parameters
    ----------
    mesh : pyvista.PolyData or spatial.files.surface.TriangleArrays
        (arrays are written as STL without loading VTK)
    path : str or os.PathLike
        ``.stl`` (binary), ``.ply``, ``.obj``, ``.vtp`` or ``.vtk``.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    ValueError
        Unknown extension (listing the known ones), or an empty mesh, before any work.
    TypeError
        `mesh` is not a pyvista.PolyData.

    Examples
    --------
    >>> import pyvista as pv, tempfile, os
    >>> out = save_mesh(pv.Sphere(), os.path.join(tempfile.mkdtemp(), "ball.stl"))
    """
    ext = mesh_format(path)
    from .surface import TriangleArrays

    if isinstance(mesh, TriangleArrays):
        if ext != ".stl":
            mesh = mesh.to_polydata()
    else:
        import pyvista as pv

        if not isinstance(mesh, pv.PolyData):
            raise TypeError(f"mesh: expected a pyvista.PolyData, got {type(mesh).__name__}")
    if mesh.n_cells == 0:
        raise ValueError("mesh: expected at least one triangle, got an empty mesh (nothing to write; "
                         "a feature thinner than the voxel size may have vanished)")

    def write(tmp):
        if ext == ".stl" and mesh.is_all_triangles:
            _write_binary_stl(mesh, tmp)
        elif ext == ".obj":
            mesh.save(tmp)
        else:
            mesh.save(tmp, binary=True)

    return atomic_write(path, write, ext)


def _write_binary_stl(mesh, path, chunk=1 << 17):
    """Binary STL of a triangle mesh straight from its arrays (unit facet normals from the
    winding): the layout VTK's writer produces, several times faster than going through it.
    The records are filled by one compiled pass per chunk of triangles (`kernels`), so the
    buffer stays small and is reused."""
    points = np.ascontiguousarray(mesh.points, dtype=np.float64)
    tri = mesh.triangles if hasattr(mesh, "triangles") else np.asarray(mesh.faces).reshape(-1, 4)[:, 1:]
    if sys.byteorder != "little":  # the kernel writes native floats; STL's are little-endian
        return _write_binary_stl_numpy(points, tri, path, chunk)
    from .kernels import RECORD, stl_records

    tri = np.ascontiguousarray(tri)
    buffer = np.empty(RECORD * min(chunk, tri.shape[0]), dtype=np.uint8)
    with open(path, "wb") as fh:
        fh.write(b"Binary STL written by implicad".ljust(80, b" "))
        fh.write(np.uint32(tri.shape[0]).tobytes())
        for a in range(0, tri.shape[0], chunk):
            b = min(a + chunk, tri.shape[0])
            stl_records(points, tri, a, b, buffer)
            fh.write(memoryview(buffer)[:RECORD * (b - a)])


def _write_binary_stl_numpy(points, tri, path, chunk=1 << 17):
    """`_write_binary_stl` in numpy array passes: the same bytes (what the compiled pass is tested against)."""
    rec = np.zeros(min(chunk, tri.shape[0]), dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)),
                                                     ("attr", "<u2")])
    with open(path, "wb") as fh:
        fh.write(b"Binary STL written by implicad".ljust(80, b" "))
        fh.write(np.uint32(tri.shape[0]).tobytes())
        for a in range(0, tri.shape[0], chunk):
            corners = points[tri[a:a + chunk]]
            normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            length = np.sqrt(np.einsum("ij,ij->i", normal, normal))
            np.divide(normal, length[:, None], out=normal, where=length[:, None] > 0)
            normal[length == 0] = 0.0
            part = rec[:corners.shape[0]]
            part["normal"] = normal
            part["corners"] = corners
            part.tofile(fh)


def load_mesh(path):
    """Read a triangle mesh written by `save_mesh` (or any format pyvista reads).

    Returns
    -------
    pyvista.PolyData
        Triangulated.
    """
    import pyvista as pv

    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(2, "No such file", path)
    data = pv.read(path)
    if not isinstance(data, pv.PolyData):
        data = data.extract_surface()
    if data.n_cells and not data.is_all_triangles:
        data = data.triangulate()
    return data
