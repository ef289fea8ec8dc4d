"""A graded surface refined only where it crosses itself.

A graded size field (`spatial.fea.graded`) can still leave a few triangles of
the clustered surface piercing others (the gear of examples/gear.py at size 5:
at the corners of its tooth tips).  Shrinking the whole field until none is
left meshes the whole part finer; instead the field gets a local cap around
the triangles that cross (`CAP_FACTOR` of the size there, graded away as the
rest of the field) and the surface is clustered again, for at most
`CAP_ROUNDS` rounds.
"""

from __future__ import annotations

import numpy as np

from .surface import surface_for_fea
from .surface_quality import FOLD_COSINE, _normals, mesh_faces

__all__ = ["graded_surface", "crossing_triangles", "surface_info", "poor_element_nodes", "CAP_FACTOR", "CAP_ROUNDS",
           "QUALITY_CAPS"]

#: The size around the triangles that cross, as a fraction of the field's size there (each round).
CAP_FACTOR = 0.8
#: Rounds of local caps before giving up (the size at a crossing goes down to 0.8^4 = 0.41 of the field's).
CAP_ROUNDS = 4


def crossing_triangles(solid, points, faces) -> np.ndarray:
    """Indices of the triangles that pierce another one (pymeshfix's test, as
    `spatial.fea.surface_quality.self_intersections`) or, given `solid`, that face into it
    (as `spatial.fea.surface_quality.folded_triangles`), sorted.

    Examples
    --------
    >>> import pyvista as pv
    >>> from spatial.fea.surface import mesh_faces
    >>> a, b = pv.Cube().triangulate(), pv.Cube(center=(0.5, 0.5, 0.5)).triangulate()
    >>> p = np.concatenate([a.points, b.points]); f = np.concatenate([mesh_faces(a), mesh_faces(b) + a.n_points])
    >>> len(crossing_triangles(None, p, f)) > 0, len(crossing_triangles(None, a.points, mesh_faces(a)))
    (True, 0)
    """
    import pymeshfix

    points = np.ascontiguousarray(points, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return np.zeros(0, dtype=np.int64)
    tm = pymeshfix.PyTMesh()
    tm.set_quiet(True)
    tm.load_array(points, faces.astype(np.int32))
    found = tm.select_intersecting_triangles(justproper=True)
    # pymeshfix 0.17 returns an (m, 3) array whose first m entries are the indices of the m
    # triangles (the rest is not written), in its own order: the input's, reversed.
    ids = np.asarray(found, dtype=np.int64).reshape(-1)[:len(found)]
    ids = ids[(ids >= 0) & (ids < len(faces))]
    out = [len(faces) - 1 - ids]
    if solid is not None:
        n = _normals(points, faces)
        g = solid.gradient(points[faces].mean(axis=1))
        cos = np.einsum("ij,ij->i", n, g) / np.maximum(np.linalg.norm(n, axis=1) * np.linalg.norm(g, axis=1), 1e-300)
        out.append(np.flatnonzero(cos < FOLD_COSINE))
    return np.unique(np.concatenate(out))


def graded_surface(solid, field, *, rounds=CAP_ROUNDS, cap_factor=CAP_FACTOR, start="features"):
    """`surface_for_fea` of `solid` with the graded `field` (a `spatial.fea.graded.SizeField`),
    capped to ``cap_factor`` of its size around the triangles that cross, up to `rounds` times.
    `start` is `surface_for_fea`'s: the feature mesh (every corner of the CSG faces a node;
    `surface_for_fea` takes the plain start itself when that surface crosses itself) or ``"plain"``.

    Returns the surface; ``field_data["local_caps"]`` holds the rounds it took and
    ``field_data["capped_points"]`` the number of crossing triangles' vertices capped.

    Raises
    ------
    ValueError
        When the surface still crosses itself after `rounds` caps (the message says
        "self-intersecting", as `surface_for_fea`'s own).

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.fea.graded import graded_size_field
    >>> part = box((20.0, 4.0, 4.0)) - box((1.0, 6.0, 6.0))
    >>> s = graded_surface(part, graded_size_field(part, 2.0, voxel=0.2))     # doctest: +SKIP
    >>> int(s.field_data["local_caps"][0])                                    # doctest: +SKIP
    0
    """
    capped = 0
    for rnd in range(rounds + 1):
        surface = surface_for_fea(solid, size=field.smallest, size_field=field, split_sides=True,
                                  check_intersections=False, start=start)
        faces = mesh_faces(surface)
        bad = crossing_triangles(solid, surface.points, faces)
        if bad.size == 0:
            surface.field_data["local_caps"] = np.array([rnd])
            surface.field_data["capped_points"] = np.array([capped])
            return surface
        if rnd == rounds:
            break
        where = np.asarray(surface.points, dtype=np.float64)[np.unique(faces[bad])]
        capped += len(where)
        field = field.refined(where, cap_factor * field(where))
    raise ValueError(f"size: the remeshed surface has {bad.size} self-intersecting (or folded) triangles after "
                     f"{rounds} local caps of the size field; use a smaller size")


def surface_info(surface) -> dict:
    """What `tet_mesh` records of the surface it filled: ``surface_start`` (``"features"`` or
    ``"plain"``, `surface_for_fea`'s ``field_data["start"]``), and for a graded surface
    ``local_caps`` and ``capped_points`` (`graded_surface`).

    Examples
    --------
    >>> import pyvista as pv
    >>> s = pv.Sphere()
    >>> s.field_data["start"] = np.array(["features"])
    >>> surface_info(s)
    {'surface_start': 'features'}
    """
    names = {"start": "surface_start", "local_caps": "local_caps", "capped_points": "capped_points"}
    return {new: np.asarray(surface.field_data[old]).reshape(-1)[0].item() for old, new in names.items()
            if old in surface.field_data}


#: Remeshings of a graded part with the field capped around the elements that miss the quality asked.
QUALITY_CAPS = 2


def poor_element_nodes(points, tets, min_dihedral, max_dihedral, radius_edge) -> np.ndarray:
    """Positions ``(k, 3)`` of the corner nodes of the elements whose dihedral angles or radius-edge
    ratio miss the bounds (where `tet_mesh` caps a graded field before meshing again).

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0.01]], dtype=float)
    >>> poor_element_nodes(p, [[0, 1, 2, 3], [0, 1, 2, 4]], 10.0, 165.0, 3.0)[:, 2].round(2).tolist()
    [0.0, 0.0, 0.0, 0.01]
    """
    from .quality import dihedral_angles, radius_edge_ratio

    points = np.asarray(points, dtype=np.float64)
    corners = np.asarray(tets, dtype=np.int64)[:, :4]
    ang = dihedral_angles(points, corners)
    bad = (ang.min(axis=1) < min_dihedral) | (ang.max(axis=1) > max_dihedral)
    bad |= radius_edge_ratio(points, corners) > radius_edge
    return points[np.unique(corners[bad])]
