"""The clustering behind `surface_for_fea`: a start mesh remeshed to a uniform (or graded) edge length.

The start mesh is cleaned (duplicate points merged, degenerate triangles
dropped), clustered by pyacvd into about ``1.15 area / size^2`` cells (weighted
by a graded size field, `spatial.fea.graded`), turned into the cells' dual
triangle mesh, repaired with MeshFix when that is not closed and manifold, and
oriented outward.

References
----------
S. Valette, J.-M. Chassery, R. Prost, "Generic remeshing of 3D triangular
meshes with metric-dependent discrete Voronoi diagrams", IEEE TVCG 14(2), 2008,
doi:10.1109/TVCG.2007.70430 (the clustering behind pyacvd).
"""

from __future__ import annotations

import warnings

import numpy as np

from .surface_kernels import first_use_order, repeated_points, triangle_areas
from .surface_quality import _is_closed_manifold, _polydata, mesh_faces

__all__ = ["cluster_mesh"]


def cluster_mesh(mesh, size, size_field=None, move_centres=False):
    """`mesh` clustered to edges of about `size`: points and outward triangles, ``(points, faces)``.

    Parameters
    ----------
    mesh : pyvista.PolyData
        A closed triangle surface.
    size : float
        Target edge length.
    size_field : spatial.fea.graded.SizeField, optional
        A size varying over the surface (weights the clusters).
    move_centres : bool
        Let pyacvd move the cluster centres onto the mesh (when they are not projected onto a solid later).

    Examples
    --------
    >>> import pyvista as pv
    >>> pts, faces = cluster_mesh(pv.Sphere(radius=1.0, theta_resolution=40, phi_resolution=40), 0.4)
    >>> bool(abs(len(pts) - 1.1547 * 4 * np.pi / 0.16) < 10), faces.shape[1]
    (True, 3)
    """
    import pyacvd

    pts, faces, area = _clean_input(mesh)
    src = _polydata(pts, faces)
    nclus = max(int(round(1.1547 * area / size**2)), 20)
    with warnings.catch_warnings():
        # pyacvd 0.4 uses a pyvista accessor that pyvista 0.49 deprecates.
        warnings.filterwarnings("ignore", module="pyacvd")
        if size_field is not None and not size_field.uniform:
            from .graded import weighted_clusters  # a size varying over the surface

            clus, nclus = weighted_clusters(src, size, size_field)
        else:
            clus = pyacvd.Clustering(src)
            # Clustering needs many input points per cluster to make good cells.
            nsub = 0
            while src.n_points * 4**nsub < 15 * nclus and nsub < 4:
                nsub += 1
            if nsub:
                clus.subdivide(nsub)
        clus.cluster(nclus)
        # Cluster centres are projected onto a solid later; without one, pyacvd moves them.
        out = clus.create_mesh(moveclus=True) if move_centres else _cells_mesh(clus)
    pts, faces = np.asarray(out.points, dtype=np.float64), mesh_faces(out)
    if not _is_closed_manifold(faces):
        pts, faces = _repair(pts, faces)
    faces = _outward(pts, faces)
    return pts, faces


def _cells_mesh(clus):
    """``clus.create_mesh(moveclus=False)``: the mesh of pyacvd's cells, by pyacvd's own steps.

    Only the triangles whose three corners lie in three different cells make a triangle of the
    result; pyacvd sorts the cells of every triangle to find them (6 ms of the benchmark part's
    77,000).  They are picked here by three comparisons and handed to pyacvd's `create_mesh` alone,
    in their order, with the cells' normals of the whole mesh: its result is the same.
    """
    from pyacvd import clustering

    mesh = clus.mesh
    faces = np.asarray(mesh.face_connectivity).reshape(-1, 3)
    c = clus.clusters[faces]
    spans = (c[:, 0] != c[:, 1]) & (c[:, 1] != c[:, 2]) & (c[:, 0] != c[:, 2])
    part = clustering.polydata_from_faces(mesh.points, faces[spans])
    out = clustering.create_mesh(part, clus.area, clus.clusters, clus.cluster_norm, clus.nclus, False, True)
    return out.clean()


def _needs_cleaning(mesh) -> bool:
    """Whether `mesh` has non-triangles, unused points, or two points at one place."""
    if not mesh.is_all_triangles:
        return True
    pts = np.asarray(mesh.points, dtype=np.float64)
    faces = mesh_faces(mesh)
    if faces.size == 0 or np.count_nonzero(np.bincount(faces.reshape(-1), minlength=pts.shape[0])) != pts.shape[0]:
        return True
    return repeated_points(pts)


def _clean_input(mesh):
    """Merge duplicate points, drop zero-area and repeated triangles: ``(points, faces, area)``, the
    area their sum (VTK's cell sizes took 5 ms more for the benchmark part's 77,000 triangles)."""
    if _needs_cleaning(mesh):
        m = mesh.triangulate().clean(tolerance=0.0, absolute=True)
        pts = np.asarray(m.points, dtype=np.float64)
        faces = mesh_faces(m)
    else:
        # The boundary mesher's surfaces are clean already; VTK's cleaning would only renumber the
        # points in the order the triangles first use them (which the clustering's result depends on).
        pts = np.asarray(mesh.points, dtype=np.float64)
        faces = mesh_faces(mesh)
        order, rank = first_use_order(faces, pts.shape[0])
        pts, faces = pts[order], rank[faces]
    area = triangle_areas(pts, faces)
    keep = area > 1e-14 * max(float(area.max(initial=0.0)), 1e-300)
    keep &= (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    faces = faces[keep]
    return pts, faces, float(area[keep].sum())


def _repair(points, faces):
    """Make a triangle soup closed and manifold with MeshFix, keeping every component."""
    import pymeshfix

    mf = pymeshfix.MeshFix(points, faces.astype(np.int32))
    mf.repair(remove_smallest_components=False)
    return np.asarray(mf.points, dtype=np.float64), np.asarray(mf.faces, dtype=np.int64)


def _outward(points, faces):
    """Flip all triangles when the enclosed signed volume is negative."""
    a, b, c = (points[faces[:, i]] for i in range(3))
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    return faces[:, ::-1].copy() if vol < 0 else faces
