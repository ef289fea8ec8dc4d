"""Watertight boundary meshes: marching cubes over the octree's BOUNDARY cells.

`mesh` decomposes a solid into an octree (`spatial.cells.octree`) down to cells of
twice the voxel size, keeps their BOUNDARY cells and meshes only them:

1. the lattice nodes (spacing ``h``) of the boundary cells are considered
   slab by slab along x, in dense arrays of the slab's active blocks only
   (the work follows the surface), in two passes: first the nodes whose sign
   is not already known -- the classification sampled the cells' centres,
   and a node at distance ``d`` from a sampled node ``v`` with ``|v| > L d``,
   or held by a cell found uniform, has that node's sign (``L`` the solid's
   Lipschitz constant) -- then the ends of crossing edges still without a
   value.  Every node is evaluated at most once (a node on a face shared by
   two blocks is merged by its integer id, one on the plane between two
   slabs is handed to the next slab), so the blocks on both sides of a face
   see one value and agree on its sign.  Inferred signs are exact, so the
   mesh is the one full sampling gives (tested) with about 60 % of its
   evaluations (benchmark part at N=512: 9.0 M -> 5.7 M);
2. the cells are grouped into blocks of ``block**3`` voxels; every block is
   meshed independently by scikit-image's Lewiner marching cubes restricted
   (``mask=``) to the voxels of its boundary cells -- a pure function of the
   block's samples, ready to run elsewhere (`mesh_block`); a second thread samples the
   next slab meanwhile (scikit-image holds the GIL, the compiled sampling mostly does not);
3. the blocks' triangles are merged into ONE indexed mesh whose vertices are
   keyed by the lattice edge they lie on (integer id ``3 * node + axis`` of
   the edge's lower node): no floating-point de-duplication (`merge_blocks`);
4. vertices are moved onto the true surface along their edge by a few
   vectorized regula-falsi (Illinois) steps bracketed by the edge's two
   samples, so a vertex never leaves its edge; a vertex whose edge samples
   already prove it within ``REFINE_ACCEPT * h`` of the level (an edge
   crossing a flat face square on) is left where it is, unevaluated.

Cells classified FULL or EMPTY hold samples of one strict sign only (the
classification is conservative), so no triangle is lost by skipping them, and
the mesh is closed, 2-manifold and outward-oriented (scikit-image's
``gradient_direction='descent'`` with negative-inside distances) whenever the
solid lies inside the padded region.

Samples exactly on the level (0.0, or within ``ZERO_NUDGE * h`` of it) are
pushed off it keeping their sign, so a face lying exactly on a sample plane
leaves no hole (scikit-image issue 8116) and no vertex sits on a lattice
node.  A sample at 0 up to rounding (within ``ZERO_TIE * h``) is a tie,
settled by the regularized solid (`arrays._settle_ties`): inside where the
solid's material lies on every side (the face two touching solids share), so
touching solids fuse and flush cuts leave no skin, and outside elsewhere.

References
----------
T. Lewiner, H. Lopes, A. W. Vieira, G. Tavares, "Efficient implementation of
marching cubes' cases with topological guarantees", J. Graphics Tools 8(2),
2003, doi:10.1080/10867651.2003.10487582.
"""

from __future__ import annotations

import warnings

import numpy as np

from .arrays import CLASSIFY_CHUNK, DEFAULT_BLOCK, EVAL_CHUNK, ZERO_NUDGE, ZERO_TIE, _chunks_on_threads, empty_mesh
from .blocks import check_block as _check_block
from .cells import mesh_cells

from ..cells.budget import check_mesh_memory
from ..cells.lattice import CHILD_OFFSETS, descend, make_lattice
from ..cells.thickness import WALL_VOXELS, default_voxel_size, thinnest_wall

__all__ = ["mesh", "boundary_cells_2h"]


def mesh(solid, *, voxel_size=None, resolution=None, bounds=None, refine=True, progress=None,
         block=DEFAULT_BLOCK, features=True):
    """Closed, outward-oriented triangle mesh of a solid's boundary.

    Parameters
    ----------
    solid : Solid
        The solid (bounded, or give `bounds`).
    voxel_size : float, optional
        Edge of the voxels (marching-cubes cells).
    resolution : int, optional
        Voxels across the longest side of the bounds (at most one of
        `voxel_size` / `resolution`).  With neither, the voxel comes from
        the part's size and its thinnest wall
        (`spatial.cells.thickness.default_voxel_size`: four voxels through
        it).  A voxel coarser than half the thinnest wall the CSG tree knows
        gets a warning naming the wall and a voxel size that keeps it.
    bounds : (lo, hi), optional
        Region to mesh; a solid sticking out of it is clipped to it (the mesh
        stays closed).
    refine : bool
        Move vertices onto the true surface (along their lattice edge).
    progress : bool or None
        Progress bar (None: only on a terminal).
    block : int
        Voxels per side of a meshing block (even).
    features : bool
        Rebuild sharp edges and corners (`spatial.meshing.features`; the
        default): a vertex on every edge and corner of the CSG faces, and the
        point data ``feature_rank`` / ``feature_facets`` with the field data
        ``facet_names`` that `feature_edges` reads.  False gives the plain
        marching-cubes mesh, faster, every vertex on a lattice edge (edges
        and corners cut by chamfers up to about a voxel wide).

    Returns
    -------
    pyvista.PolyData
        Triangles; ``field_data`` holds ``voxel_size``, ``evaluations``
        (boxes bounded plus points sampled), ``boundary_cells`` (BOUNDARY
        cells of edge ``2h`` meshed), ``blocks`` and ``seconds``.  Empty (with a warning) when no boundary lies in the
        region.

    Examples
    --------
    >>> from implicit import sphere
    >>> surface = mesh(sphere(1.0), resolution=32)
    >>> surface.is_manifold
    True
    """
    block = _check_block(block)
    if not isinstance(features, (bool, np.bool_)):
        raise TypeError(f"features: expected True or False, got {features!r}")
    if voxel_size is None and resolution is None:
        from implicit import Solid

        if not isinstance(solid, Solid):
            raise TypeError(f"solid: expected an implicit.Solid, got {type(solid).__name__}")
        voxel_size = default_voxel_size(solid, bounds)
    lattice = make_lattice(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds)
    announced = _warn_thin(lattice.solid, lattice.voxel_size, lattice.bounds)
    if lattice.empty:
        warnings.warn("mesh: the solid is empty (its bounds enclose nothing); returning an empty mesh",
                      RuntimeWarning, stacklevel=2)
        return empty_mesh(lattice.voxel_size if voxel_size else 0.0)
    # refuse before allocating (cells.budget)
    check_mesh_memory(lattice.bounds, lattice.voxel_size, features=bool(features))
    found = _boundary_cells_2h(lattice, progress, threads=2)
    # the search for features the lattice may lose reads only the classification: it runs on a thread of
    # its own beside the mesh (whose slab loop leaves a core partly idle), and its warning is given after
    search = _LostFeatureSearch(lattice, found, solid) if found["centres"] is not None else None
    try:
        # popped, so that mesh_cells can release them once used
        out = mesh_cells(lattice.solid, lattice.origin, lattice.voxel_size, found.pop("cells"), cell_size=2,
                         refine=refine, progress=progress, evaluations=found["evaluations"], block=block,
                         centre_values=found.pop("centres"), uniform_cells=found.pop("uniform"),
                         uniform_parents=found.pop("uniform_parents"),
                         node_values=found.pop("nodes"), features=bool(features), slab_threads=2, _stacklevel=3)
    except BaseException:
        if search is not None:
            search.join()  # not left running; the mesh's error is the one raised
        raise
    feature = search.result() if search is not None else None
    if feature is not None:
        from ..cells.specks import warn_feature

        warn_feature(feature, lattice.voxel_size, announced, stacklevel=3)
    return out


class _LostFeatureSearch:
    """`spatial.cells.specks.lost_feature` of a classification, on a thread started at once; `result`
    joins it and returns the feature (or None), raising what the search raised."""

    def __init__(self, lattice, found, name_by):
        import threading

        from ..cells.specks import lost_feature

        args = (lattice.solid, lattice.origin, lattice.voxel_size, found["cells"], found["centres"])
        options = dict(uniform=found.get("uniform"), uniform_parents=found.get("uniform_parents"), name_by=name_by)
        self._out = []

        def run():
            try:
                self._out.append(lost_feature(*args, **options))
            except BaseException as exc:  # raised on the caller's thread by `result`
                self._out.append(exc)

        self._thread = threading.Thread(target=run, name="implicad-lost-features", daemon=True)
        self._thread.start()

    def join(self):
        self._thread.join()

    def result(self):
        self._thread.join()
        out = self._out[0]
        if isinstance(out, BaseException):
            raise out
        return out


def _warn_thin(solid, h, bounds=None):
    """One line when the voxel is coarser than half the thinnest wall (it may be lost): the tree's
    (its primitives' sizes), else the one measured on the field (`spatial.cells.walls`: a wall
    thinned by a Boolean, an offset or a blend), named by its faces' facets and a point on it.
    Returns the voxel size it told to keep the wall, or None."""
    t, what = thinnest_wall(solid)
    if np.isfinite(t) and h > t / 2:
        warnings.warn(f"mesh: voxel size {h:.4g} is coarser than half the thinnest wall ({what}: {t:.4g}); "
                      f"the wall may be lost; voxel_size={t / WALL_VOXELS:.4g} keeps it", RuntimeWarning,
                      stacklevel=3)
        return t / WALL_VOXELS
    from ..cells.walls import thin_wall

    w = thin_wall(solid, bounds=bounds)
    if w is not None and h > w.thickness / 2:
        warnings.warn(f"mesh: voxel size {h:.4g} is coarser than half {w.describe()}; the wall may be "
                      f"lost; voxel_size={w.thickness / WALL_VOXELS:.4g} keeps it", RuntimeWarning,
                      stacklevel=3)
        return w.thickness / WALL_VOXELS
    return None


def _boundary_cells_2h(lattice, progress, start=None, threads=1):
    """BOUNDARY cells of edge ``2h`` (level ``depth - 1``) and what their classification learned.

    Levels down to ``depth - 3`` are classified by `Solid.value_bounds`.  The
    levels of edge ``4h`` and ``2h`` are classified by the Lipschitz test
    (``|f(centre)| > L * half-diagonal``: uniform) on values sampled at the
    cell centres -- which are lattice nodes, so the mesh reuses them instead
    of sampling them again -- and the cells found uniform keep their sign,
    from which the mesh infers the sign of their nodes without sampling them.
    The test is rigorous for any solid with a finite Lipschitz constant ``L``.

    Returns
    -------
    dict
        ``cells`` (m, 3) int; ``centres`` (m,) values at their centres or
        None; ``uniform`` ((k, 3) cells of edge ``2h``, (k,) int8 signs) and
        ``uniform_parents`` (the same for cells of edge ``4h``) or None;
        ``nodes`` ((j, 3) lattice nodes, (j,) values) sampled on the way or
        None; ``evaluations``.

    With ``start=(level, cells)`` only the octree below those cells is
    classified (`descend`): a brick of the lattice, as the whole-lattice
    classification sees it.  The centres are sampled on `threads` threads (the same values).
    """
    solid, depth = lattice.solid, lattice.depth
    lip = float(solid.lipschitz)
    # uniform cells must hold samples of one sign after the nudge, rounding included
    margin = ZERO_NUDGE * lattice.voxel_size
    if not (np.isfinite(lip) and lip > 0) or depth < 3:
        result = descend(lattice, keep_leaves=False, stop_level=depth - 1, progress=progress,
                         chunk=CLASSIFY_CHUNK, margin=margin, start=start)
        return dict(cells=result["boundary"], centres=None, uniform=None, uniform_parents=None, nodes=None,
                    evaluations=result["evaluations"])
    result = descend(lattice, keep_leaves=False, stop_level=depth - 3, progress=progress, chunk=CLASSIFY_CHUNK,
                     margin=margin, start=start)
    evaluations = result["evaluations"]
    h = lattice.voxel_size
    parents = result["boundary"]
    from ..cells import lattice_kernels as K

    uniform, nodes = [], None
    for size in (4, 2):  # cell edge in voxels
        limit = (-(-lattice.shape // size)).astype(np.int32)
        # children beyond the padded region are EMPTY (the solid lies inside its bounds); only the
        # parents on the region's upper edge have such children.  The others' children are read from
        # their parents when needed (`lattice_kernels`), never listed all at once
        inner, edge = K.at_upper_edge(parents, limit)
        at_edge = (2 * parents[edge][:, None, :] + CHILD_OFFSETS).reshape(-1, 3)
        inside = (at_edge < limit).all(axis=1)
        beyond, outer = at_edge[~inside], np.ascontiguousarray(at_edge[inside])
        del edge, at_edge, inside
        values = np.empty(8 * inner.size + outer.shape[0])

        def centres(a, b, size=size, parents=parents, inner=inner, outer=outer, values=values):
            values[a:b] = solid(K.centres(parents, inner, outer, CHILD_OFFSETS, a, b, lattice.origin, size, h))

        # the chunks on `threads` threads (the serial part of the mesh: no slab runs beside it)
        _chunks_on_threads(centres, values.shape[0], EVAL_CHUNK, threads=threads)
        evaluations += int(values.shape[0])
        # the default bound: |f(centre)| <= L * half-diagonal may hold boundary
        # (plus a tie's width: a uniform cell's nodes are never ties, see `_settle_ties`)
        bound = lip * np.sqrt(3.0) * (size // 2) * h * (1 + 1e-12) + 2 * ZERO_TIE * h
        if size == 4:
            # the centre of a cell of 4h is a lattice node
            nodes = (K.centre_nodes(parents, inner, outer, CHILD_OFFSETS, 0, values.shape[0], size), values)
        parents, centres, flat, signs = K.split(parents, inner, outer, CHILD_OFFSETS, values, bound,
                                                np.ascontiguousarray(beyond))
        uniform.append((flat, signs))
        del values, inner, outer, beyond
    return dict(cells=parents, centres=centres,
                uniform=uniform[1], uniform_parents=uniform[0],
                nodes=nodes, evaluations=evaluations)


#: The classification of `mesh`, for callers meshing a part of the lattice (one brick per task).
boundary_cells_2h = _boundary_cells_2h
