"""Visible and hidden parts of 3D lines seen along a view direction.

The mesh is rasterized into a depth buffer by numpy alone (every triangle's
candidate pixels at once, a minimum scattered into the buffer); a point of a
line is visible when it is no deeper than the farthest surface in its 3 x 3
pixel neighbourhood plus a tolerance (a line on the outline of a face sees
past the face, a line behind a face sees only the face).

Examples
--------
>>> import numpy as np, pyvista as pv
>>> from spatial.drafting.views import view_frame
>>> cube = pv.Cube().triangulate()
>>> frame = view_frame("front")
>>> buf = DepthBuffer(np.asarray(cube.points), cube.faces.reshape(-1, 4)[:, 1:], frame, pixel=0.05)
>>> front_edge = np.array([[-0.5, -0.5, 0.5], [0.5, -0.5, 0.5]])
>>> back_edge = np.array([[-0.4, 0.5, 0.0], [0.4, 0.5, 0.0]])
>>> bool(buf.visible(front_edge, 0.01).all()), bool(buf.visible(back_edge, 0.01).any())
(True, False)
"""

from __future__ import annotations

import numpy as np

__all__ = ["DepthBuffer", "classify_polylines"]

#: Candidate pixels handled per batch of the rasterizer.
_BATCH = 4_000_000


class DepthBuffer:
    """Nearest depth of a triangle mesh per pixel, seen through `frame`.

    Parameters
    ----------
    points : (n, 3) float
    triangles : (t, 3) int
        A closed, outward-oriented triangle mesh (back faces are culled).
    frame : (3, 3) float
        Rows ``u`` (paper right), ``v`` (paper up), ``d`` (into the paper).
    pixel : float
        Pixel size in model units.
    """

    def __init__(self, points, triangles, frame, pixel):
        self.frame = np.asarray(frame, dtype=float)
        pts = np.asarray(points, dtype=float) @ self.frame.T
        self.pixel = float(pixel)
        lo = pts[:, :2].min(axis=0) - 3 * self.pixel if len(pts) else np.zeros(2)
        hi = pts[:, :2].max(axis=0) + 3 * self.pixel if len(pts) else np.ones(2)
        self.origin = lo
        self.shape = tuple(np.ceil((hi - lo) / self.pixel).astype(int) + 1)
        self.depth = np.full(self.shape, np.inf)
        tris = np.asarray(triangles, dtype=np.int64)
        if len(tris):
            self._rasterize(pts[tris])
        # The farthest surface around each pixel: an edge on an outline sees past it.
        from scipy.ndimage import maximum_filter

        self.far = maximum_filter(self.depth, size=3, mode="constant", cval=np.inf)

    def _rasterize(self, tri):
        # The nearest surface of a closed outward mesh faces the eye: back faces are skipped.
        # (The frame (u, v, d) is left-handed, so a front face turns counter-clockwise in (u, v).)
        e1, e2 = tri[:, 1, :2] - tri[:, 0, :2], tri[:, 2, :2] - tri[:, 0, :2]
        tri = tri[e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0]
        uv = (tri[:, :, :2] - self.origin) / self.pixel
        z = tri[:, :, 2]
        lo = np.floor(uv.min(axis=1)).astype(np.int64)
        span = np.ceil(uv.max(axis=1)).astype(np.int64) - lo + 1
        # Triangles grouped by size keep the candidate grids small.
        size = span.max(axis=1)
        for k in np.unique(size):
            rows = np.flatnonzero(size == k)
            step = max(1, _BATCH // int(k * k))
            for s in range(0, len(rows), step):
                self._rasterize_group(uv[rows[s:s + step]], z[rows[s:s + step]], lo[rows[s:s + step]], int(k))

    def _rasterize_group(self, uv, z, lo, k):
        gi, gj = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
        pi = lo[:, 0:1] + gi.ravel()[None]
        pj = lo[:, 1:2] + gj.ravel()[None]
        cx, cy = pi + 0.5, pj + 0.5
        a, b, c = uv[:, 0], uv[:, 1], uv[:, 2]
        det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
        ok = np.abs(det) > 1e-12
        det = np.where(ok, det, 1.0)[:, None]
        w1 = ((cx - a[:, 0:1]) * (c[:, 1:2] - a[:, 1:2]) - (c[:, 0:1] - a[:, 0:1]) * (cy - a[:, 1:2])) / det
        w2 = ((b[:, 0:1] - a[:, 0:1]) * (cy - a[:, 1:2]) - (cx - a[:, 0:1]) * (b[:, 1:2] - a[:, 1:2])) / det
        w0 = 1.0 - w1 - w2
        eps = -1e-9
        inside = (w0 >= eps) & (w1 >= eps) & (w2 >= eps) & ok[:, None]
        inside &= (pi >= 0) & (pj >= 0) & (pi < self.shape[0]) & (pj < self.shape[1])
        depth = w0 * z[:, 0:1] + w1 * z[:, 1:2] + w2 * z[:, 2:3]
        np.minimum.at(self.depth, (pi[inside], pj[inside]), depth[inside])

    def visible_uvz(self, uvz, tolerance):
        """Visibility of points already in view coordinates ``(n, 3)``."""
        ij = np.floor((uvz[:, :2] - self.origin) / self.pixel).astype(np.int64)
        ij = np.clip(ij, 0, np.array(self.shape) - 1)
        return uvz[:, 2] <= self.far[ij[:, 0], ij[:, 1]] + tolerance

    def visible(self, points, tolerance):
        """Visibility of world `points` ``(n, 3)``."""
        return self.visible_uvz(np.asarray(points, dtype=float) @ self.frame.T, tolerance)


def _runs(flags: np.ndarray):
    """(start, stop, value) of the runs of equal values in a 1D array."""
    change = np.flatnonzero(np.diff(flags)) + 1
    starts = np.concatenate([[0], change])
    stops = np.concatenate([change, [len(flags)]])
    return starts, stops, flags[starts]


def classify_polylines(polylines, buffer: DepthBuffer, frame, tolerance: float, *, covered_within: float = 0.0,
                       min_length: float = 0.0):
    """Split 3D polylines into visible and hidden 2D polylines of view coordinates.

    Every segment is cut into pieces no longer than a pixel; each piece is
    judged at its middle, and isolated flickers (shorter than 3 pieces) are
    smoothed away.  Hidden pieces lying within `covered_within` of a visible
    line are dropped (a hidden edge behind a visible one is not drawn), and
    so are pieces shorter than `min_length` (what is left of a line where it
    passes behind an outline).

    Returns
    -------
    visible, hidden : list of (k, 2) float
    """
    frame = np.asarray(frame, dtype=float)
    dense = []
    for p in polylines:  # one step per polyline
        q = np.asarray(p, dtype=float) @ frame.T
        if len(q) < 2:
            continue
        seg = np.linalg.norm(np.diff(q[:, :2], axis=0), axis=1)
        pieces = np.maximum(1, np.ceil(seg / buffer.pixel).astype(int))
        t = (np.arange(pieces.sum()) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(pieces, pieces)
        idx = np.repeat(np.arange(len(seg)), pieces)
        pts = q[idx] + t[:, None] * (q[idx + 1] - q[idx])
        pts = np.concatenate([pts, q[-1:]])
        dense.append(pts)
    states = []
    from scipy.ndimage import median_filter

    for pts in dense:
        mid = 0.5 * (pts[1:] + pts[:-1])
        vis = buffer.visible_uvz(mid, tolerance)
        if len(vis) >= 5:
            vis = median_filter(vis.astype(np.int8), size=5, mode="nearest").astype(bool)
        states.append(np.where(vis, 0, 1).astype(np.int8))
    if covered_within > 0 and dense:
        from scipy.spatial import cKDTree

        vis_pts = [0.5 * (d[1:, :2] + d[:-1, :2])[s == 0] for d, s in zip(dense, states)]
        vis_pts = np.concatenate(vis_pts) if vis_pts else np.zeros((0, 2))
        if len(vis_pts):
            tree = cKDTree(vis_pts)
            for d, s in zip(dense, states):
                hid = np.flatnonzero(s == 1)
                if hid.size:
                    dist, _ = tree.query(0.5 * (d[hid + 1, :2] + d[hid, :2]))
                    s[hid[dist < covered_within]] = 2
                if len(s) >= 5:
                    s[:] = median_filter(s, size=5, mode="nearest")
    visible, hidden = [], []
    for d, s in zip(dense, states):
        starts, stops, values = _runs(s)
        for a, b, v in zip(starts, stops, values):
            piece = d[a:b + 1, :2]
            if len(piece) < 2 or np.linalg.norm(np.diff(piece, axis=0), axis=1).sum() < min_length:
                continue
            (visible if v == 0 else hidden if v == 1 else []).append(piece)
    return visible, hidden
