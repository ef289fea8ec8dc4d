"""Alignment of a scan to its design: best fit (ICP) or datum planes.

`icp` runs in two stages.  A coarse point-to-point ICP (Besl and McKay,
"A Method for Registration of 3-D Shapes", IEEE PAMI 14(2), 1992,
doi:10.1109/34.121791) pairs every scan point with its nearest vertex of the
design's mesh (scipy's cKDTree), trims the worst pairs, and solves the rigid
motion in closed form (Kabsch / Horn, by SVD).  A fine point-to-plane stage
(Chen and Medioni, 1992) then uses the solid's own field: a point ``q``
lies ``f(q) / |grad f|`` from the surface along the normal
``grad f / |grad f|``, so each Gauss-Newton step solves the linearised
``f + n . (w x q + t) = 0`` in least squares, with Huber weights so that a
local defect (a bump, a burr) does not pull the fit.  The mesh's sampling
error therefore never enters the final transform.

`datum_align` is the 3-2-1 scheme of inspection fixtures: planes fitted to
the scan points near three datum planes of the design (primary, secondary,
tertiary) build a frame that is carried onto the design's datum frame.

Every transform is a 4x4 matrix that maps scan coordinates to design ones.
"""

from __future__ import annotations

import numpy as np

__all__ = ["icp", "datum_align", "apply", "rigid_fit", "vertex_areas"]

#: Coarse and fine iteration limits.
COARSE_ITERATIONS = 30
FINE_ITERATIONS = 30
#: Fraction of pairs kept by the coarse stage's trimming.
KEEP = 0.9


def apply(T, points):
    """``points`` (n, 3) moved by the 4x4 transform `T`."""
    return points @ T[:3, :3].T + T[:3, 3]


def _matrix(R, t):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def rigid_fit(a, b, weights=None):
    """The rigid motion (R, t) minimising ``sum w |R a_i + t - b_i|^2`` (Kabsch, by SVD)."""
    w = np.ones(len(a)) if weights is None else np.asarray(weights, dtype=float)
    w = w / w.sum()
    ca, cb = w @ a, w @ b
    H = (a - ca).T @ ((b - cb) * w[:, None])
    U, _, Vt = np.linalg.svd(H)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    R = Vt.T @ D @ U.T
    return R, cb - R @ ca


def _rodrigues(w):
    th = float(np.linalg.norm(w))
    if th < 1e-300:
        return np.eye(3)
    k = w / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * (K @ K)


def _signed_distance(solid, q):
    """Distance from the surface ``f / max(|grad f|, 1)`` and the unit normal at points q.

    A field steeper than a distance (a scaled solid) is divided by its
    slope; a central difference that straddles a crease of a Boolean
    (where the gradient's length drops below 1) leaves the field as it is.
    """
    f = solid(q)
    g = solid.gradient(q)
    n = np.linalg.norm(g, axis=1)
    d = f / np.maximum(n, 1.0)
    return d, g / np.maximum(n, 1e-12)[:, None]


def vertex_areas(mesh):
    """A third of the area of the triangles around each vertex of a triangle mesh."""
    faces = np.asarray(mesh.faces).reshape(-1, 4)[:, 1:]
    p = np.asarray(mesh.points, dtype=float)
    a = 0.5 * np.linalg.norm(np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]]), axis=1)
    out = np.zeros(len(p))
    np.add.at(out, faces.ravel(), np.repeat(a / 3.0, 3))
    return out


def icp(points, solid, *, initial=None, weights=None, resolution=48, fine=True, huber=None):
    """Best-fit rigid transform of scan `points` onto `solid`.

    Parameters
    ----------
    points : (n, 3) float
        The scan.
    solid : Solid
        The design.
    initial : (4, 4) float, optional
        Start transform (default: the identity; the scan is assumed roughly
        placed, within a fraction of the part's size and some tens of degrees).
    weights : (n,) float, optional
        The surface area each point stands for (a scanned mesh's vertex
        areas, `vertex_areas`): without them a scan denser on some faces
        pulls the fit towards them, and a uniform offset shifts it.
    resolution : int
        Cells across the design's mesh for the coarse stage.
    fine : bool
        Run the point-to-plane stage on the solid's field.
    huber : float, optional
        Residual beyond which a point's weight falls off (default: 3 x the
        median absolute residual, at least 1e-9 of the part's size).

    Returns
    -------
    T : (4, 4) float
        Scan -> design.
    info : dict
        ``coarse_iterations``, ``fine_iterations``, ``rms`` (point-to-surface
        after the fit, all points).

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.meshing import mesh
    >>> part = box((2.0, 1.0, 0.5))
    >>> pts = mesh(part, resolution=24).points + [0.01, -0.02, 0.005]
    >>> T, info = icp(pts, part)
    >>> bool(np.allclose(T[:3, 3], [-0.01, 0.02, -0.005], atol=1e-6))
    True
    """
    from scipy.spatial import cKDTree

    from ..meshing import mesh as mesh_solid

    p = np.asarray(points, dtype=float)
    wa = np.ones(len(p)) if weights is None else np.asarray(weights, dtype=float)
    if wa.shape != (len(p),) or not np.all(np.isfinite(wa)) or np.any(wa < 0) or not wa.sum() > 0:
        raise ValueError(f"weights: expected {len(p)} non-negative finite numbers, not all zero")
    T = np.eye(4) if initial is None else np.asarray(initial, dtype=float).copy()
    target = np.asarray(mesh_solid(solid, resolution=resolution).points, dtype=float)
    tree = cKDTree(target)
    size = float(np.ptp(target, axis=0).max())
    it_c = 0
    for it_c in range(1, COARSE_ITERATIONS + 1):
        q = apply(T, p)
        d, idx = tree.query(q)
        keep = d <= np.quantile(d, KEEP)
        R, t = rigid_fit(q[keep], target[idx[keep]], wa[keep])
        T = _matrix(R, t) @ T
        if np.linalg.norm(R - np.eye(3)) < 1e-4 and np.linalg.norm(t) < 1e-4 * size:
            break                                 # the fine stage takes it from here
    it_f = 0
    if fine:
        best = np.inf
        for it_f in range(1, FINE_ITERATIONS + 1):
            q = apply(T, p)
            d, n = _signed_distance(solid, q)
            k = huber if huber is not None else max(3 * float(np.median(np.abs(d))), 1e-9 * size)
            w = wa * np.where(np.abs(d) <= k, 1.0, k / np.maximum(np.abs(d), 1e-300))
            cost = float(np.sum(w * d * d))
            if cost > best * (1 + 1e-9):
                T = previous                      # the gradient's own noise: the last step did not help
                break
            best, previous = cost, T
            c = (wa @ q) / wa.sum()
            A = np.column_stack([np.cross(q - c, n), n])
            sw = np.sqrt(w)
            x, *_ = np.linalg.lstsq(A * sw[:, None], -d * sw, rcond=None)
            R = _rodrigues(x[:3])
            T = _matrix(R, c + x[3:] - R @ c) @ T
            if np.linalg.norm(x) < 1e-10 * max(size, 1.0):
                break
    d, _ = _signed_distance(solid, apply(T, p))
    return T, {"coarse_iterations": it_c, "fine_iterations": it_f, "rms": float(np.sqrt(np.mean(d * d)))}


def _fit_plane(pts):
    c = pts.mean(axis=0)
    _, _, Vt = np.linalg.svd(pts - c)
    return c, Vt[2]


def datum_align(points, solid, datums, *, band=None, prealign=True):
    """3-2-1 alignment on three datum planes of the design.

    Parameters
    ----------
    points : (n, 3) float
        The scan, roughly placed.
    solid : Solid
        The design (used for its size only).
    datums : sequence of three (point, normal)
        Primary, secondary and tertiary datum planes of the design, normals
        pointing out of the material, not parallel.
    band : float, optional
        Scan points within this distance of a datum plane belong to it
        (default: 2 % of the size).
    prealign : bool
        Find the datum faces' points after a coarse best fit (the scan may
        then be misplaced by more than the band); the fitted planes alone
        decide the transform.

    Returns
    -------
    T : (4, 4) float
        Scan -> design: the fitted primary plane onto the primary datum, the
        secondary's normal (made perpendicular) onto the secondary, the
        tertiary fixing the last translation.
    """
    p0 = np.asarray(points, dtype=float)
    if not isinstance(datums, (list, tuple)) or len(datums) != 3:
        raise ValueError(f"datums: expected three (point, normal) planes, got {datums!r}")
    planes = []
    for k, dm in enumerate(datums):
        if not isinstance(dm, (list, tuple)) or len(dm) != 2:
            raise ValueError(f"datums[{k}]: expected (point, normal), got {dm!r}")
        o = np.asarray(dm[0], dtype=float).reshape(3)
        n = np.asarray(dm[1], dtype=float).reshape(3)
        if not np.linalg.norm(n) > 0:
            raise ValueError(f"datums[{k}]: the normal is zero")
        planes.append((o, n / np.linalg.norm(n)))
    lo, hi = solid.bounds
    size = float(np.max(hi - lo))
    band = 0.02 * size if band is None else float(band)
    T0 = icp(p0, solid, fine=False)[0] if prealign else np.eye(4)
    p = apply(T0, p0)
    fitted = []
    for k, (o, n) in enumerate(planes):
        near = np.abs((p - o) @ n) <= band
        if near.sum() < 3:
            raise ValueError(f"datums[{k}]: fewer than 3 scan points within {band:g} of the datum plane")
        c, m = _fit_plane(p[near])
        fitted.append((c, m if m @ n > 0 else -m))

    def frame(n1, n2, n3, pts):
        e1 = n1 / np.linalg.norm(n1)
        e2 = n2 - (n2 @ e1) * e1
        e2 /= np.linalg.norm(e2)
        e3 = np.cross(e1, e2)
        if e3 @ n3 < 0:
            e3 = -e3
        # the point where the three planes meet
        N = np.array([n1, n2, n3])
        origin = np.linalg.solve(N, np.array([n1 @ pts[0], n2 @ pts[1], n3 @ pts[2]]))
        return np.array([e1, e2, e3]), origin

    Fd, od = frame(*(pl[1] for pl in planes), [pl[0] for pl in planes])
    Fs, os_ = frame(*(f[1] for f in fitted), [f[0] for f in fitted])
    R = Fd.T @ Fs
    return _matrix(R, od - R @ os_) @ T0
