"""The lines of one view of a part: visible and hidden edges and silhouettes,
centre lines of holes and axes of revolution, and the view's extent.

Everything here is in view coordinates of model units (``u`` right, ``v``
up); the sheet's scale and position come later.

Examples
--------
>>> import spatial
>>> from implicit import box, cylinder
>>> part = box((40, 20, 10)) - cylinder(4, 30)
>>> m = part_mesh(part, resolution=48)
>>> top = view_lines(part, m, surface_edges(m, part), "top")
>>> [round(float(x), 3) for x in top.extent]
[-20.0, -10.0, 20.0, 10.0]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .csg_features import AxialFeature, axial_features
from .edges import SurfaceEdges, silhouettes, surface_edges
from .views import view_frame
from .visibility import DepthBuffer, classify_polylines

__all__ = ["ViewLines", "view_lines", "part_mesh", "present_features", "exact_bounds", "surface_edges"]

#: Shortest piece of line drawn, in voxels: shorter ones are what the depth test's tolerance
#: lets through where a line passes behind an outline.
MIN_PIECE = 3.0

#: Odd fractions of a voxel that shift the lattice off the round numbers faces sit on.
_SHIFT = (0.371, 0.417, 0.293)


@dataclass
class ViewLines:
    """One view of a part in view coordinates.

    Attributes
    ----------
    name : str
    frame : (3, 3) float
    visible, hidden : list of (k, 2) float
    axes : list of ((2,), (2,))
        Centre lines of axes lying in the view plane (end points).
    centres : list of ((2,), float)
        Centres and radii of circles seen end-on (they get centre crosses).
    pitch_circles : list of ((2,), float)
        Circles that three or more equally spaced holes seen end-on lie on (chain lines).
    extent : (4,) float
        ``umin, vmin, umax, vmax`` of the part in this view.
    features : list of AxialFeature
        The holes and bosses present in the part.
    """

    name: str
    frame: np.ndarray
    visible: list
    hidden: list
    axes: list = field(default_factory=list)
    centres: list = field(default_factory=list)
    extent: np.ndarray = None
    features: list = field(default_factory=list)
    pitch_circles: list = field(default_factory=list)


def part_mesh(solid, *, resolution: int = 160):
    """A mesh for drawing: the lattice shifted off round numbers, where part faces tend to lie
    (a face on lattice nodes leaves ragged chamfers at its corners)."""
    from ..meshing import mesh

    lo, hi = (np.asarray(b, dtype=float) for b in solid.bounds)
    if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
        raise ValueError("solid: expected a bounded solid to draw")
    h = float((hi - lo).max()) / resolution
    pad = 2.0 * h
    shift = np.asarray(_SHIFT) * h
    from .measured import is_measured

    # The meshing room's sharp features put vertices on the true edges (`feature_edges` draws them).
    return mesh(solid, voxel_size=h, bounds=(lo - pad - shift, hi + pad + shift), progress=False,
                features=not is_measured(solid))


def exact_bounds(solid, mesh) -> tuple[np.ndarray, np.ndarray]:
    """The tree's bounds where the mesh confirms them (within two voxels), else the mesh's
    (always the mesh's for a mesh, a sweep or another field whose bounds the tree only pads)."""
    from .measured import is_measured

    h = float(np.asarray(mesh.field_data["voxel_size"]).ravel()[0])
    pts = np.asarray(mesh.points)
    mlo, mhi = pts.min(axis=0), pts.max(axis=0)
    if is_measured(solid):
        return mlo, mhi
    tlo, thi = (np.asarray(b, dtype=float) for b in solid.bounds)
    lo = np.where(np.abs(tlo - mlo) <= 2 * h, tlo, mlo)
    hi = np.where(np.abs(thi - mhi) <= 2 * h, thi, mhi)
    return lo, hi


def present_features(solid, h: float) -> list[AxialFeature]:
    """The axial features whose surface is really part of the boundary of `solid`;
    those on the boundary only part of the way round come back as arcs (``arc=True``)."""
    from dataclasses import replace

    out = []
    lo, hi = (np.asarray(b, dtype=float) for b in solid.bounds)
    for f in axial_features(solid):
        # Sample the feature's wall inside the part's bounds: the feature counts when
        # two rings' worth of those points lie on the part's boundary.
        e = np.linalg.svd(np.eye(3) - np.outer(f.axis, f.axis))[0][:, :2].T
        s0, s1 = _axial_clip(f, lo, hi)
        if s1 <= s0:
            continue
        theta = np.linspace(0, 2 * np.pi, 48, endpoint=False)
        t = np.linspace(s0, s1, 34)[1:-1]
        radius = f.diameter / 2 if f.kind != "torus" else f.diameter / 2 + f.length / 2
        ring = radius * (np.cos(theta)[:, None] * e[0] + np.sin(theta)[:, None] * e[1])
        pts = (f.centre + t[:, None, None] * f.axis + ring[None]).reshape(-1, 3)
        on = (np.abs(solid(pts)) < 2.0 * h).reshape(len(t), len(theta))
        # A bolt hole through a flange is wall over a short stretch of its axis only.
        if on.sum() < 2 * len(theta):
            continue
        around = on.any(axis=0)
        if f.kind == "cylinder" and around.mean() < 0.9:
            # A quarter round in a corner: the middle of the longest run of angles on the boundary.
            k = np.flatnonzero(around)
            start = int(np.flatnonzero(~around)[0])
            rolled = np.roll(around, -start)
            idx = np.flatnonzero(rolled)
            mid_angle = theta[(start + int(np.median(idx))) % len(theta)]
            row = int(np.argmax(on[:, k].sum(axis=1)))
            mid = f.centre + t[row] * f.axis + radius * (np.cos(mid_angle) * e[0] + np.sin(mid_angle) * e[1])
            f = replace(f, arc=True, mid=mid)
        out.append(f)
    return out


def _axial_clip(f: AxialFeature, lo, hi):
    """The feature's axial extent cut to the part's bounding box (where its axis line is inside it)."""
    a = np.asarray(f.axis, dtype=float)
    c = np.asarray(f.centre, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (lo - c) / a, (hi - c) / a
    parallel = np.abs(a) < 1e-12
    inside = (c >= lo) & (c <= hi)
    if np.any(parallel & ~inside):
        return 0.0, -1.0
    t0, t1 = np.where(parallel, -np.inf, np.minimum(t0, t1)), np.where(parallel, np.inf, np.maximum(t0, t1))
    return max(f.start, float(t0.max())), min(f.stop, float(t1.min()))


def view_lines(solid, mesh, edges: SurfaceEdges, name: str, *, projection: str = "first",
               frame=None, hidden: bool = True, features=None, bounds=None) -> ViewLines:
    """Visible and hidden lines of `solid` in view `name` (or along `frame`).

    Parameters
    ----------
    solid : implicit.Solid
    mesh : pyvista.PolyData
        Its boundary mesh (`part_mesh`).
    edges : SurfaceEdges
        `surface_edges(mesh, solid)`.
    name : {"front", "top", "side", "iso"}
    hidden : bool
        Classify hidden lines too (iso and section views leave them out).
    """
    frame = view_frame(name, projection) if frame is None else np.asarray(frame, dtype=float)
    h = edges.voxel_size
    pts = np.asarray(mesh.points)
    buffer = DepthBuffer(pts, edges.triangles, frame, pixel=0.5 * h)
    lines = list(edges.polylines) + silhouettes(edges, frame[2])
    visible, hid = classify_polylines(lines, buffer, frame, tolerance=1.5 * h, covered_within=1.0 * h,
                                      min_length=MIN_PIECE * h)
    if bounds is None:
        bounds = exact_bounds(solid, mesh)
    lo, hi = bounds
    corners = np.array(np.meshgrid(*zip(lo, hi), indexing="ij")).reshape(3, -1).T @ frame[:2].T
    if name == "iso":
        uv = pts @ frame[:2].T
        extent = np.concatenate([uv.min(axis=0), uv.max(axis=0)])
    else:
        extent = np.concatenate([corners.min(axis=0), corners.max(axis=0)])
    visible, hid = drop_overlaps(visible, hid if hidden else [], tolerance=0.5 * h, min_length=MIN_PIECE * h)
    view = ViewLines(name, frame, visible, hid, extent=extent)
    feats = present_features(solid, h) if features is None else features
    view.features = feats
    if name != "iso":
        _centre_lines(view, feats, lo, hi)
    return view


def drop_overlaps(visible: list, hidden: list, *, tolerance: float, min_length: float):
    """The lines of a view with every stretch left out that lies on a line drawn before it:
    edges behind one another in the view (a block's top and bottom outline, a hole's two rims
    seen end-on) are drawn once, and a hidden line under a visible one is not drawn (ISO 128-20).

    Lines are resampled at a third of `tolerance`; a point is covered when a point of an
    earlier line (longer visible lines first, hidden lines after all visible ones) is within
    `tolerance`.  Pieces shorter than `min_length` are dropped.
    """
    from scipy.spatial import cKDTree

    lines = sorted(visible, key=lambda p: -_len2(p)) + sorted(hidden, key=lambda p: -_len2(p))
    kinds = [0] * len(visible) + [1] * len(hidden)
    if not lines:
        return [], []
    step = tolerance / 3.0
    samples, owner = [], []
    for i, p in enumerate(lines):  # one step per line
        q = _resample(np.asarray(p, dtype=float), step)
        samples.append(q)
        owner.append(np.full(len(q), i))
    pts, own = np.concatenate(samples), np.concatenate(owner)
    # Arc length along each line: a line folding back over itself (edges joined round a
    # corner, one above the other in the view) covers its own earlier stretch too.
    arc = np.concatenate([np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))])
                          for q in samples])
    tree = cKDTree(pts)
    dist, nb = tree.query(pts, k=min(32, len(pts)), distance_upper_bound=tolerance)
    valid = np.isfinite(dist)
    nb = np.minimum(nb, len(pts) - 1)
    me = np.arange(len(pts))[:, None]
    other = (own[nb] != own[:, None]) | (np.abs(arc[nb] - arc[:, None]) > 3 * tolerance)
    covered = (valid & (nb < me) & other).any(axis=1)
    out = ([], [])
    start = 0
    for i, q in enumerate(samples):  # one step per line
        c = covered[start:start + len(q)]
        start += len(q)
        if not c.any():
            out[kinds[i]].append(q if len(q) > 2 else np.asarray(lines[i], dtype=float))
            continue
        # Runs of uncovered points.
        edges = np.flatnonzero(np.diff(np.concatenate([[1], c.astype(int), [1]])))
        for a, b in zip(edges[::2], edges[1::2]):
            # Each piece reaches a tolerance into the stretch it meets, so that corners stay closed.
            piece = q[max(a - 3, 0):min(b + 3, len(q))]
            if len(piece) >= 2 and _len2(piece) >= min_length:
                out[kinds[i]].append(piece)
    return out


def _len2(p) -> float:
    p = np.asarray(p, dtype=float)
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) if len(p) > 1 else 0.0


def _resample(p: np.ndarray, step: float) -> np.ndarray:
    """`p` with points every `step` or closer along it (its own points kept)."""
    if len(p) < 2:
        return p
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    n = np.maximum(1, np.ceil(seg / step).astype(int))
    t = np.concatenate([np.arange(k) / k for k in n])  # one range per segment
    i = np.repeat(np.arange(len(seg)), n)
    return np.concatenate([p[i] + t[:, None] * (p[i + 1] - p[i]), p[-1:]])


def _centre_lines(view: ViewLines, feats, lo, hi):
    from .auto_dims import pitch_circle

    seen_axes, seen_centres = set(), set()
    d = view.frame[2]
    by_d = {}
    for f in feats:
        if f.negative and not f.arc and f.kind == "cylinder" and abs(float(f.axis @ d)) > 1 - 1e-9:
            by_d.setdefault(round(f.diameter, 6), set()).add(tuple(np.round(view.frame[:2] @ f.centre, 6)))
    for centres in by_d.values():
        pcd = pitch_circle(np.array(sorted(centres)))
        if pcd is not None:
            view.pitch_circles.append(pcd)
    for f in feats:
        if f.arc:
            continue
        along = abs(float(f.axis @ d))
        c2 = view.frame[:2] @ f.centre
        if along > 1 - 1e-9:
            key = tuple(np.round(c2, 6)) + (round(f.diameter, 6),)
            if key not in seen_centres:
                seen_centres.add(key)
                view.centres.append((c2, f.diameter / 2))
        else:
            # In the plane or oblique: the axis seen from the side, over the part.
            s0, s1 = _axial_clip(f, lo, hi)
            a = view.frame[:2] @ (f.centre + s0 * f.axis)
            b = view.frame[:2] @ (f.centre + s1 * f.axis)
            key = tuple(np.round(np.concatenate([np.minimum(a, b), np.maximum(a, b)]), 6))
            if key not in seen_axes:
                seen_axes.add(key)
                view.axes.append((a, b))
