"""Topology and validity of boundary meshes and solids.

`topology` counts the boundary's vertices, edges, faces and shells, the
Euler characteristic and genus of every shell, and checks the
Euler-Poincare law ``F - E + V - L = 2 (B - G)``; it finds open edges,
non-manifold edges and vertices, and inconsistent orientation.  `check`
turns a solid or mesh into a `ValidityReport`: finite, bounded, closed,
manifold, oriented, free of degenerate and duplicate triangles and of
vertices at one position (`triangle_defects`), its bodies, shells and
genus, and flags for what is wrong; several bodies are valid only when the
caller checks an assembly-like solid.

For a triangle mesh every face is bounded by exactly one loop, so the count
of inner loops (rings) ``L`` of the Euler-Poincare law is 0 and the law
reads ``F - E + V = 2 (B - G)`` over closed shells; `Topology` reports each
term.  Here ``B`` counts shells (connected boundary components: an outer
skin and each internal void) and ``G`` is the sum of their genera.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Topology", "ValidityReport", "topology", "triangle_defects", "check"]


@dataclass(frozen=True)
class Topology:
    """Combinatorial topology of a triangle mesh.

    Attributes
    ----------
    vertices, edges, faces : int
        ``V``, ``E``, ``F`` (vertices used by at least one face).
    loops : int
        Inner loops (rings) ``L`` of the faces: 0 for triangles.
    shells : int
        Connected components of the surface, ``B``.
    euler : int
        ``V - E + F`` of the whole mesh.
    shell_euler, shell_genus : tuple of int
        Euler characteristic and genus of each shell (genus ``(2 - chi) / 2``
        of a closed shell; -1 for an open one).
    shell_volume : tuple of float
        Signed volume enclosed by each shell (negative for a void).
    genus : int
        ``G``: sum of the shells' genera.
    open_edges, nonmanifold_edges, nonmanifold_vertices : int
        Edges in one face; edges in more than two; vertices whose faces form
        more than one fan.
    oriented : bool
        Every interior edge is used once in each direction.
    signed_volume : float
        Volume enclosed, positive for an outward-oriented mesh.
    """

    vertices: int
    edges: int
    faces: int
    loops: int
    shells: int
    euler: int
    shell_euler: tuple
    shell_genus: tuple
    shell_volume: tuple
    genus: int
    open_edges: int
    nonmanifold_edges: int
    nonmanifold_vertices: int
    oriented: bool
    signed_volume: float

    @property
    def closed(self) -> bool:
        """No open edge."""
        return self.open_edges == 0

    @property
    def manifold(self) -> bool:
        """No non-manifold edge or vertex."""
        return self.nonmanifold_edges == 0 and self.nonmanifold_vertices == 0

    @property
    def bodies(self) -> int:
        """Shells enclosing positive volume (outer skins; voids excluded)."""
        return int(sum(1 for v in self.shell_volume if v > 0))

    @property
    def euler_poincare(self) -> tuple[int, int]:
        """Both sides of ``F - E + V - L = 2 (B - G)``."""
        return self.faces - self.edges + self.vertices - self.loops, 2 * (self.shells - self.genus)

    @property
    def euler_poincare_holds(self) -> bool:
        """True when both sides agree (always, for closed 2-manifold shells)."""
        lhs, rhs = self.euler_poincare
        return lhs == rhs

    def to_dict(self) -> dict:
        """Plain-Python form for JSON."""
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out = {k: list(v) if isinstance(v, tuple) else v for k, v in out.items()}
        out.update(closed=self.closed, manifold=self.manifold, bodies=self.bodies,
                   euler_poincare=list(self.euler_poincare), euler_poincare_holds=self.euler_poincare_holds)
        return out


def _triangles(mesh) -> tuple[np.ndarray, np.ndarray]:
    from ..meshing.arrays import faces_array as _faces_array

    return _faces_array(mesh)


def topology(mesh) -> Topology:
    """Shells, Euler characteristic, genus and defects of a triangle mesh.

    Parameters
    ----------
    mesh : pyvista.PolyData
        Triangles; points shared between faces by index (weld first).

    Returns
    -------
    Topology

    Examples
    --------
    >>> import pyvista as pv
    >>> t = topology(pv.Sphere().triangulate().clean())
    >>> t.shells, t.genus, t.euler, t.closed, t.oriented
    (1, 0, 2, True, True)
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    points, tri = _triangles(mesh)
    n_pts = points.shape[0]
    F = tri.shape[0]
    a = tri.ravel()
    b = np.roll(tri, -1, axis=1).ravel()
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    ukey = lo * n_pts + hi
    edges, edge_of, counts = np.unique(ukey, return_inverse=True, return_counts=True)
    E = edges.size
    used = np.unique(tri)
    V = used.size
    open_edges = int((counts == 1).sum())
    nm_edges = int((counts > 2).sum())
    # orientation: a directed half-edge used twice, or a two-face edge whose
    # two uses run the same way
    dkey = a * n_pts + b
    _, dcounts = np.unique(dkey, return_counts=True)
    oriented = bool(np.all(dcounts == 1))

    # shells: faces joined through shared edges (face-edge bipartite graph)
    face_of = np.repeat(np.arange(F), 3)
    graph = coo_matrix((np.ones(3 * F), (face_of, F + edge_of)), shape=(F + E, F + E))
    _, labels = connected_components(graph, directed=False)
    face_label = labels[:F]
    shell_ids, face_label = np.unique(face_label, return_inverse=True)
    B = shell_ids.size
    # per-shell V, E, F
    f_s = np.bincount(face_label, minlength=B)
    edge_shell = np.empty(E, dtype=np.int64)
    edge_shell[edge_of] = face_label[face_of]
    e_s = np.bincount(edge_shell, minlength=B)
    vkeys = np.unique(tri.ravel() * B + np.repeat(face_label, 3))
    v_s = np.bincount(vkeys % B, minlength=B)
    chi_s = v_s - e_s + f_s
    open_s = np.bincount(edge_shell[counts == 1], minlength=B)
    genus_s = np.where(open_s == 0, (2 - chi_s) // 2, -1)
    # signed volume per shell
    c0 = 0.5 * (points[used].min(axis=0) + points[used].max(axis=0))
    p = points - c0
    det = np.einsum("ij,ij->i", p[tri[:, 0]], np.cross(p[tri[:, 1]], p[tri[:, 2]])) / 6.0
    vol_s = np.bincount(face_label, weights=det, minlength=B)

    # non-manifold vertices: the faces around a vertex must form one fan.
    # Corners (vertex, face) are joined when the two faces share an edge at
    # that vertex; a vertex with corners in more than one group is pinched.
    corner = np.arange(3 * F)                        # corner k: vertex tri.ravel()[k] in face k // 3
    nxt = 3 * (corner // 3) + (corner % 3 + 1) % 3   # corner of the edge's other end in the same face
    order = np.argsort(edge_of, kind="stable")
    se = edge_of[order]
    same = se[1:] == se[:-1]
    i1, i2 = order[:-1][same], order[1:][same]       # half-edge pairs sharing an edge
    # half-edge k runs from corner k to corner nxt[k]; join the corners of
    # the two half-edges that sit at the same vertex
    rows = np.concatenate([i1, nxt[i1]])
    cols = np.concatenate([np.where(a[i2] == a[i1], i2, nxt[i2]), np.where(a[i2] == b[i1], i2, nxt[i2])])
    cg = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(3 * F, 3 * F))
    _, clabels = connected_components(cg, directed=False)
    fans = np.unique(a * (3 * F) + clabels)
    fans_per_vertex = np.bincount(fans // (3 * F), minlength=n_pts)
    nm_vertices = int((fans_per_vertex > 1).sum())

    return Topology(
        vertices=int(V), edges=int(E), faces=int(F), loops=0, shells=int(B), euler=int(V - E + F),
        shell_euler=tuple(int(x) for x in chi_s), shell_genus=tuple(int(x) for x in genus_s),
        shell_volume=tuple(float(x) for x in vol_s), genus=int(genus_s[genus_s > 0].sum()),
        open_edges=open_edges, nonmanifold_edges=nm_edges, nonmanifold_vertices=nm_vertices,
        oriented=oriented, signed_volume=float(det.sum()),
    )


@dataclass(frozen=True)
class ValidityReport:
    """Whether a solid (or mesh) is a valid solid, and why not.

    Attributes
    ----------
    valid : bool
        Finite, bounded, non-empty, closed, manifold, oriented outward, no
        degenerate or duplicate triangles, no two vertices at one position,
        and one body (or any number of bodies when `assembly`).
    finite, bounded, closed, manifold, oriented : bool
    bodies : int
        Connected solids (shells enclosing positive volume; a cavity is not a
        body).
    genus : int
        Through-holes (sum over shells).
    volume : float
        Signed volume of the boundary mesh.
    topology : Topology or None
        Full counts (None when the solid could not be meshed).
    flags : tuple of str
        One line per problem (``'isolated parts'``, ``'open shell'``,
        ``'infinite extent'``, ...).
    shells : int
        Boundary components: a body with a cavity has 2.
    degenerate_triangles : int
        Triangles of zero area or with a repeated vertex index.
    duplicate_triangles : int
        Triangles on the same three vertices as another.
    duplicate_vertices : int
        Vertices used by triangles at the position of another such vertex.
    nonfinite_vertices : int
        Vertices with a NaN or infinite coordinate.
    assembly : bool
        Checked as an assembly-like solid: several bodies are allowed.
    """

    valid: bool
    finite: bool
    bounded: bool
    closed: bool
    manifold: bool
    oriented: bool
    bodies: int
    genus: int
    volume: float
    topology: Topology | None = None
    flags: tuple = field(default_factory=tuple)
    shells: int = 0
    degenerate_triangles: int = 0
    duplicate_triangles: int = 0
    duplicate_vertices: int = 0
    nonfinite_vertices: int = 0
    assembly: bool = False

    def to_dict(self) -> dict:
        """Plain-Python form for JSON."""
        out = {k: getattr(self, k) for k in self.__dataclass_fields__ if k != "topology"}
        out["flags"] = list(self.flags)
        out["topology"] = None if self.topology is None else self.topology.to_dict()
        return out

    def summary(self) -> str:
        """A short multi-line text report."""
        t = self.topology
        lines = [f"valid:     {'yes' if self.valid else 'NO'}{' (as an assembly)' if self.assembly else ''}",
                 f"finite:    {self.finite}", f"bounded:   {self.bounded}", f"closed:    {self.closed}",
                 f"manifold:  {self.manifold}", f"oriented:  {self.oriented}", f"bodies:    {self.bodies}",
                 f"shells:    {self.shells}", f"genus:     {self.genus}", f"volume:    {self.volume:.6g}",
                 f"triangles: {self.degenerate_triangles} degenerate, {self.duplicate_triangles} duplicate; "
                 f"vertices: {self.duplicate_vertices} at the same position, {self.nonfinite_vertices} not finite"]
        if t is not None:
            lhs, rhs = t.euler_poincare
            lines += [f"V, E, F:   {t.vertices}, {t.edges}, {t.faces}  (L = {t.loops} inner loops)",
                      f"Euler:     {t.euler} (per shell {list(t.shell_euler)}; genus per shell {list(t.shell_genus)})",
                      f"Euler-Poincare F - E + V - L = {lhs}, 2(B - G) = {rhs}: "
                      f"{'holds' if t.euler_poincare_holds else 'FAILS'}"]
        lines += [f"problem:   {f}" for f in self.flags]
        return "\n".join(lines)


def triangle_defects(mesh) -> dict:
    """Degenerate and duplicate triangles, vertices at one position and non-finite vertices of a mesh.

    Returns
    -------
    dict
        ``degenerate`` (zero area -- below 1e-12 of the squared size of the
        mesh -- or a repeated vertex index), ``duplicate`` (the same three
        vertices as another triangle), ``duplicate_vertices`` (used vertices
        at the position of another used vertex), ``nonfinite`` (vertices).

    Examples
    --------
    >>> import pyvista as pv
    >>> triangle_defects(pv.Sphere().triangulate().clean())["degenerate"]
    0
    """
    points, tri = _triangles(mesh)
    nonfinite = int(np.count_nonzero(~np.isfinite(points).all(axis=1)))
    repeated = (tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 0] == tri[:, 2])
    with np.errstate(invalid="ignore", over="ignore"):
        cross = np.cross(points[tri[:, 1]] - points[tri[:, 0]], points[tri[:, 2]] - points[tri[:, 0]])
        area2 = np.sqrt((cross * cross).sum(axis=1))
        used = np.unique(tri)
        span = points[used]
        span = span[np.isfinite(span).all(axis=1)]
        size = float(np.max(span.max(axis=0) - span.min(axis=0))) if span.shape[0] else 0.0
    zero = ~(area2 > 1e-12 * size * size)
    duplicate = tri.shape[0] - np.unique(np.sort(tri, axis=1), axis=0).shape[0]
    dup_vertices = used.size - np.unique(points[used], axis=0).shape[0]
    return {"degenerate": int(np.count_nonzero(repeated | zero)), "duplicate": int(duplicate),
            "duplicate_vertices": int(dup_vertices), "nonfinite": nonfinite}


def check(obj, *, resolution=None, mesher=None, assembly=False) -> ValidityReport:
    """Check that a solid or a mesh is a valid solid, and say what is wrong.

    A valid solid is finite (its field has no NaN or infinity), bounded,
    non-empty, and its boundary is a closed, 2-manifold, outward-oriented
    surface without degenerate or duplicate triangles or two vertices at one
    position, of exactly one body (no isolated parts) -- or of any number of
    bodies when `assembly` is set (an assembly-like solid).

    Parameters
    ----------
    obj : Solid or pyvista.PolyData
    resolution : int, optional
        Cells across a solid's bounds for its boundary mesh (default: the
        mesher's default voxel, from the part's size and its thinnest wall).
    mesher : callable, optional
        ``mesher(solid, h) -> PolyData``; default `spatial.meshing.mesh`.
    assembly : bool
        Several bodies are valid (they are reported all the same).

    Returns
    -------
    ValidityReport

    Examples
    --------
    >>> import pyvista as pv
    >>> check(pv.Sphere().triangulate().clean()).valid
    True
    >>> two = pv.Sphere().triangulate().clean() + pv.Sphere(center=(3, 0, 0)).triangulate().clean()
    >>> check(two).valid, check(two, assembly=True).valid
    (False, True)
    """
    from implicit import Solid

    if resolution is not None and (isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer))
                                   or resolution < 4):
        raise ValueError(f"resolution: expected an integer of at least 4, got {resolution!r}")
    assembly = bool(assembly)
    flags = []
    finite = bounded = True
    if isinstance(obj, Solid):
        lo, hi = obj.bounds
        if obj.is_empty_bounds:
            return ValidityReport(False, True, True, False, False, False, 0, 0, 0.0, None, ("empty solid",),
                                  assembly=assembly)
        bounded = obj.is_bounded
        if not bounded:
            flags.append("infinite extent: the solid's bounds are not finite (intersect it with a box)")
            lo_f = np.where(np.isfinite(lo), lo, -1.0)
            hi_f = np.where(np.isfinite(hi), hi, 1.0)
        else:
            lo_f, hi_f = lo, hi
        probe = lo_f + (hi_f - lo_f) * np.random.default_rng(0).random((512, 3))
        with np.errstate(all="ignore"):
            vals = obj(probe)
        finite = bool(np.all(np.isfinite(vals)))
        if not finite:
            flags.append("not finite: the field is NaN or infinite at some points")
        if not (bounded and finite):
            return ValidityReport(False, finite, bounded, False, False, False, 0, 0, float("nan"), None, tuple(flags),
                                  assembly=assembly)
        if mesher is None:
            from .mass import _default_mesher

            mesher = _default_mesher()
        if resolution is None:
            from ..cells.thickness import default_voxel_size

            h = default_voxel_size(obj)
        else:
            h = float(np.max(hi - lo)) / resolution
        mesh = mesher(obj, h)
        if mesh.n_cells == 0:
            return ValidityReport(False, True, True, False, False, False, 0, 0, 0.0, None, ("empty solid",),
                                  assembly=assembly)
    else:
        mesh = obj
    defects = triangle_defects(mesh)
    if defects["nonfinite"]:
        flags.append(f"not finite: {defects['nonfinite']} vertices have NaN or infinite coordinates")
        return ValidityReport(False, False, False, False, False, False, 0, 0, float("nan"), None, tuple(flags),
                              nonfinite_vertices=defects["nonfinite"], assembly=assembly)
    t = topology(mesh)
    if not t.closed:
        flags.append(f"open shell: {t.open_edges} edges bound only one face")
    if not t.manifold:
        flags.append(f"not manifold: {t.nonmanifold_edges} edges in more than two faces, "
                     f"{t.nonmanifold_vertices} pinched vertices")
    if not t.oriented:
        flags.append("inconsistent orientation: some edges are used twice in the same direction")
    if t.signed_volume <= 0:
        flags.append("inside out: the enclosed volume is not positive")
    if defects["degenerate"]:
        flags.append(f"degenerate triangles: {defects['degenerate']} of zero area or with a repeated vertex")
    if defects["duplicate"]:
        flags.append(f"duplicate triangles: {defects['duplicate']} on the same vertices as another")
    if defects["duplicate_vertices"]:
        flags.append(f"duplicate vertices: {defects['duplicate_vertices']} at the position of another")
    if t.bodies > 1 and not assembly:
        flags.append(f"isolated parts: {t.bodies} separate bodies (check as an assembly to allow them)")
    clean = not (defects["degenerate"] or defects["duplicate"] or defects["duplicate_vertices"])
    one = t.bodies == 1 or (assembly and t.bodies >= 1)
    valid = finite and bounded and t.closed and t.manifold and t.oriented and t.signed_volume > 0 and clean and one
    return ValidityReport(bool(valid), finite, bounded, t.closed, t.manifold, t.oriented, t.bodies,
                          t.genus, t.signed_volume, t, tuple(flags), shells=t.shells,
                          degenerate_triangles=defects["degenerate"], duplicate_triangles=defects["duplicate"],
                          duplicate_vertices=defects["duplicate_vertices"], nonfinite_vertices=0,
                          assembly=assembly)
