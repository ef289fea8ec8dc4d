"""Element sizes that vary over a part: fine in its narrow gaps and thin walls, graded to the size asked.

A surface of edge length `size` cannot follow a gap narrower than `size`
(the space between two gear teeth).  Instead of a surface that is fine
everywhere, the target size becomes a field: at each point of the surface
``h = min(size, GAP_FRACTION * local width)`` (the width of the gap or wall
there, `spatial.fea.narrow_widths`; `WALL_FRACTION` of a wall's), then graded so that it grows by at most `GROWTH`
per unit length (``h(x) <= h(y) + GROWTH * |x - y|``: neighbouring elements
differ by a ratio of at most ``1 + GROWTH``).  The field drives the surface
clustering (pyacvd, each input point weighted by ``(size / h)^2`` so that
clusters come out of area ``~h^2``) and TetGen's volume refinement (a
background mesh carrying the field, TetGen's ``-m``).

References
----------
P.-O. Persson, "Mesh size functions for implicit geometries and PDE-based
gradient limiting", Engineering with Computers 22, 2006,
doi:10.1007/s00366-006-0014-1 (the size function ``min(h_i + g |x - x_i|)``).
"""

from __future__ import annotations

import numpy as np

from .size_field import GAP_FRACTION, SMALLEST_FRACTION, _trace

__all__ = ["SizeField", "graded_size_field", "GROWTH", "BAND_RATIO"]

#: Element edge over the width of a wall (a gear's tooth) where the size is graded: elements
#: across a tooth one at a time leave slivers with all four nodes on its faces (the gear at size 5:
#: 14 elements under 10 degrees with 0.8 of the tooth's width, none with 0.6).
WALL_FRACTION = 0.4
#: Largest angle (radians) an edge may turn through on a curved face (a cylinder's, a sphere's):
#: ``h <= CURVE_ANGLE * radius`` (0.35 rad, 20 degrees: the chords of a bore of radius 6 in the gear at size 5
#: cut 0.3 percent of its volume, 1.7 percent at edges of 5).
CURVE_ANGLE = 0.35
#: Leaves whose faces are curved (the names `implicit.facets.FacetField` gives their facets start so);
#: of cylinders and cones, the wall only.
_CURVED = ("sphere", "capsule", "torus")
_CURVED_WALL = ("cylinder", "cone")


def _is_curved(name):
    kind, _, face = name.partition(".")
    kind = kind.rsplit("_", 1)[0]
    return kind in _CURVED or (kind in _CURVED_WALL and face == "wall")
#: Largest growth of the size per unit length: two neighbouring elements differ by at most 1 + GROWTH.
GROWTH = 0.3
#: Sources are grouped in bands of sizes within this ratio; each band counts at its smallest size
#: (the field errs finer, by at most this ratio, never coarser).
BAND_RATIO = 1.1
#: Groups of points by how far a band's sources may lie and still lower their size (halving reaches).
_REACH_GROUPS = 4



def _bands_of(size, points, sizes):
    """The sources under `size`, grouped in bands of sizes within `BAND_RATIO` of each other: the
    smallest source size (`size` when there is none) and ``[(band's smallest size, KD-tree), ...]``."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    h = np.asarray(sizes, dtype=np.float64).reshape(-1)
    if p.shape[0] != h.shape[0]:
        raise ValueError(f"sizes: expected one size per point ({p.shape[0]}), got {h.shape[0]}")
    keep = np.isfinite(h) & (h < size)
    p, h = p[keep], h[keep]
    smallest = float(h.min(initial=size))
    bands = []
    if h.size:
        from scipy.spatial import cKDTree

        level = np.floor(np.log(h / smallest) / np.log(BAND_RATIO) + 1e-9).astype(np.int64)
        for lv in np.unique(level):
            sel = level == lv
            bands.append((float(h[sel].min()), cKDTree(p[sel])))
    return smallest, bands

class SizeField:
    """A graded target size: ``min(size, min_i(h_i + growth * |x - p_i|))`` over sources ``(p_i, h_i)``.

    Parameters
    ----------
    size : float
        The size asked: the field never exceeds it.
    points : (m, 3) array_like
        Points where the size must be smaller.
    sizes : (m,) array_like
        The size wanted at each point.
    growth : float
        Largest growth of the size per unit length.

    Examples
    --------
    >>> f = SizeField(5.0, [[0.0, 0.0, 0.0]], [1.0])
    >>> f([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [100.0, 0.0, 0.0]]).round(3).tolist()
    [1.0, 4.0, 5.0]
    """

    def __init__(self, size, points=(), sizes=(), growth=GROWTH):
        self.size = float(size)
        self.growth = float(growth)
        self.smallest, self._bands = _bands_of(self.size, points, sizes)

    def scaled(self, factor) -> "SizeField":
        """The field times `factor` (the size asked and every source's size)."""
        out = SizeField(self.size * factor, growth=self.growth)
        out.smallest = self.smallest * factor
        out._bands = [(h * factor, tree) for h, tree in self._bands]
        return out

    def capped(self, size) -> "SizeField":
        """The field at most `size` everywhere."""
        out = self.scaled(1.0)
        out.size = min(self.size, float(size))
        out.smallest = min(self.smallest, out.size)
        out._bands = [(h, tree) for h, tree in self._bands if h < out.size]
        return out

    def refined(self, points, sizes) -> "SizeField":
        """The field with more sources: at most ``sizes[i] + growth * |x - points[i]|`` near each of `points`.

        Examples
        --------
        >>> f = SizeField(5.0).refined([[0.0, 0.0, 0.0]], [2.0])
        >>> f.smallest, f([[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [50.0, 0.0, 0.0]]).round(3).tolist()
        (2.0, [2.0, 3.5, 5.0])
        """
        smallest, bands = _bands_of(self.size, points, sizes)
        out = self.scaled(1.0)
        out.smallest = min(self.smallest, smallest)
        # New bands of their own: a query takes the least over all bands, whichever they are.
        out._bands.extend(bands)
        return out

    @property
    def uniform(self) -> bool:
        """Whether the field is the size asked everywhere."""
        return not self._bands

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=np.float64).reshape(-1, 3)
        out = np.full(x.shape[0], self.size)
        # Finest bands first: a source of band h can lower the size at a point only within
        # (size there so far - h) / growth of it, so each band asks the points it can still lower, in
        # groups of such reach (halving), and the trees search that far only.  The least over all
        # bands is the same as every band over every point (the reach is widened by a relative 1e-9
        # against rounding).
        for h, tree in sorted(self._bands, key=lambda band: band[0]):
            reach = (out - h) / self.growth
            live = np.flatnonzero(reach > 0.0)
            if live.size == 0:
                continue
            top = float(reach[live].max())
            group = np.minimum(np.floor(np.log2(top / np.maximum(reach[live], 1e-300 * top))), _REACH_GROUPS - 1)
            for g in range(_REACH_GROUPS):
                idx = live[group == g]
                if idx.size == 0:
                    continue
                bound = float(reach[idx].max()) * (1.0 + 1e-9)
                d, _ = tree.query(x[idx], k=1, distance_upper_bound=bound)
                out[idx] = np.minimum(out[idx], h + self.growth * d)
        return out


def graded_size_field(solid, size, *, voxel=None, growth=GROWTH, curve_angle=CURVE_ANGLE) -> SizeField:
    """The `SizeField` of `solid` for elements of `size`: ``GAP_FRACTION`` of the local gap's
    width, ``WALL_FRACTION`` of the wall's (rays along the normals as in `narrow_widths`, measured at the vertices of a mesh of voxel `voxel`), at least
    ``SMALLEST_FRACTION * size``, and at most ``curve_angle`` times the radius of a curved face
    (`curvatures`; None: no such bound), graded by `growth`.

    `voxel` defaults to ``size / 4``; give a quarter of the smallest size expected (a mesh
    coarser than a gap closes it: `spatial.fea.resolve.resolving_field` does so).

    Examples
    --------
    >>> from implicit import box
    >>> slot = box((20.0, 4.0, 4.0)) - box((1.0, 6.0, 6.0))       # a cut 1 wide across a bar
    >>> f = graded_size_field(slot, 2.0, voxel=0.2)
    >>> round(f.smallest, 2), f([[9.9, 0, 0]]).round(2).tolist()
    (0.8, [2.0])
    """
    from ..meshing.boundary import mesh

    size = float(size)
    voxel = size / 4.0 if voxel is None else float(voxel)
    m = mesh(solid, voxel_size=voxel, progress=False, features=False)
    if m.n_points == 0:
        return SizeField(size, growth=growth)
    pts = np.asarray(m.points, dtype=np.float64)
    g = solid.gradient(pts)
    nrm = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    reach = size / min(GAP_FRACTION, WALL_FRACTION)
    gap = _trace(solid, pts, nrm, 1.0, reach, size)
    wall = _trace(solid, pts, -nrm, -1.0, reach, size)
    h = np.minimum(GAP_FRACTION * gap, WALL_FRACTION * wall)
    if curve_angle is not None:
        h = np.minimum(h, curve_angle / np.maximum(curvatures(solid, pts, 1e-3 * size), 1e-300))
    h = np.clip(h, SMALLEST_FRACTION * size, size)
    return SizeField(size, pts, h, growth=growth)


def curvatures(solid, points, step):
    """Largest principal curvature ``(n,)`` of the face deciding each of `points` (on the surface),
    0 on faces that are not curved (planes, polygon sides).

    The Hessian of that face's own field (the leaf's, smooth across the solid's sharp edges,
    `implicit.facets.FacetField`) by central differences of step `step`, projected on the
    tangent plane over the gradient's length.

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> curvatures(box(10.0) - cylinder(2.0, 20.0), [[2.0, 0, 0], [5.0, 0, 0]], 1e-3).round(4).tolist()
    [0.5, 0.0]
    """
    from implicit.facets import FacetField as TreeFacets

    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    ff = TreeFacets(solid)
    curved = np.array([_is_curved(name) for name in ff.names], dtype=bool)
    out = np.zeros(len(p))
    if not curved.any() or len(p) == 0:
        return out
    _, dec, _ = ff(p)
    idx = np.nonzero(curved[dec])[0]
    if idx.size == 0:
        return out
    q, d = p[idx], dec[idx]
    e = np.eye(3) * step
    pairs = [(i, j) for i in range(3) for j in range(i + 1, 3)]
    offs = [np.zeros(3)] + [s * e[i] for i in range(3) for s in (1, -1)]
    offs += [a * e[i] + b * e[j] for i, j in pairs for a in (1, -1) for b in (1, -1)]
    probe = (q[None] + np.array(offs)[:, None]).reshape(-1, 3)
    _, _, fv = ff(probe)
    f = fv.reshape(len(ff.names), len(offs), len(q))[d, :, np.arange(len(q))]       # (m, 19)
    grad = np.stack([(f[:, 1 + 2 * i] - f[:, 2 + 2 * i]) / (2 * step) for i in range(3)], axis=1)
    hess = np.empty((len(q), 3, 3))
    for i in range(3):
        hess[:, i, i] = (f[:, 1 + 2 * i] - 2 * f[:, 0] + f[:, 2 + 2 * i]) / step**2
    for k, (i, j) in enumerate(pairs):
        pp, pm, mp, mm = f[:, 7 + 4 * k:11 + 4 * k].T
        hess[:, i, j] = hess[:, j, i] = (pp - pm - mp + mm) / (4 * step**2)
    gn = np.linalg.norm(grad, axis=1)
    nrm = grad / np.maximum(gn, 1e-300)[:, None]
    proj = np.eye(3)[None] - nrm[:, :, None] * nrm[:, None, :]
    shape = proj @ hess @ proj / np.maximum(gn, 1e-300)[:, None, None]
    out[idx] = np.where(gn > 0.5, np.abs(np.linalg.eigvalsh(shape)).max(axis=1), 0.0)
    return out


def weighted_clusters(src, size, field):
    """A pyacvd clustering of surface `src` whose clusters have edges ~ ``field(x)`` and the
    number of clusters for it: ``(clustering, nclus)``.

    Each input point counts ``(size / h)^2`` times its area.  pyacvd's own `weights` scale
    only the points' weighted positions, not their areas (pyacvd 0.4: the clusters' centroids
    come out scaled and the clustering non-manifold), so both are set here.  The surface is
    subdivided first until the smallest clusters hold about 15 input points.
    """
    import pyacvd
    from pyacvd.clustering import _subdivide

    tri_area = src.compute_cell_sizes(length=False, area=True, volume=False)["Area"]
    area = float(np.sum(tri_area))
    faces = np.asarray(src.faces).reshape(-1, 4)[:, 1:]
    h_face = field(np.asarray(src.points, dtype=np.float64))[faces].mean(axis=1)
    # A triangulation of edge h has sqrt(3)/4 h^2 per triangle, 1.1547 / h^2 vertices per unit area.
    nclus = max(int(round(1.1547 * float(np.sum(tri_area / h_face**2)))), 20)
    per_cluster = src.n_points / max(area, 1e-300) * field.smallest**2 / 1.1547
    nsub = 0
    while per_cluster * 4**nsub < 15 and nsub < 4:
        nsub += 1
    if nsub:
        src = _subdivide(src, nsub)
    clus = pyacvd.Clustering(src)
    w = (size / field(np.asarray(src.points, dtype=np.float64))) ** 2
    clus.area = np.ravel(clus.area) * w
    clus.wcent = clus.wcent * w[:, None]
    return clus, nclus
