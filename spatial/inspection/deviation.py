"""A produced part against its design: scan loading, deviation, statistics, pass/fail.

`inspect(solid, scan)` aligns the scan (best fit, datum planes, or as
given), then takes every point's signed deviation from the design surface:
the solid's field divided by its gradient's length where that exceeds 1 (a
first-order step to the surface, exact for exact distance fields and their
offsets; a Boolean's field is a bound of the distance near its edges), positive
outside the material (excess), negative inside (missing material).  The
result carries the statistics and the 4x4 alignment transform, and passes
when every point lies within the tolerance band.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass

import numpy as np

from .align import _signed_distance, apply, datum_align, icp, vertex_areas

__all__ = ["Inspection", "inspect", "load_scan", "SCAN_FORMATS"]

#: Scan files `load_scan` reads.
SCAN_FORMATS = (".stl", ".ply", ".obj", ".vtp", ".vtk", ".xyz", ".txt", ".csv", ".pts")
#: Default number of worst points named in the report and on the picture.
WORST = 5


def load_scan(path):
    """Points of a scan file: mesh vertices (STL, PLY, OBJ, VTP, VTK) or an
    ASCII point cloud (XYZ, TXT, CSV, PTS: x y z in the first three columns).

    Returns
    -------
    points : (n, 3) float
    mesh : pyvista.PolyData or None
        The scanned mesh when the file holds faces.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"scan: expected a file name, got {type(path).__name__}")
    name = os.fspath(path)
    ext = os.path.splitext(name)[1].lower()
    if ext not in SCAN_FORMATS:
        raise ValueError(f"{name}: unknown scan format {ext or '(no extension)'!r}; known: {', '.join(SCAN_FORMATS)}")
    if not os.path.exists(name):
        raise FileNotFoundError(2, "No such file", name)
    if ext in (".xyz", ".txt", ".csv", ".pts"):
        try:
            data = np.loadtxt(name, delimiter="," if ext == ".csv" else None, ndmin=2, comments="#")
        except ValueError as exc:
            raise ValueError(f"{name}: expected rows of numbers x y z: {exc}") from None
        if data.shape[1] < 3 or len(data) < 3:
            raise ValueError(f"{name}: expected at least 3 rows of x y z, got shape {data.shape}")
        pts = data[:, :3].astype(float)
        mesh = None
    else:
        from ..files import load_mesh

        mesh = load_mesh(name)
        pts = np.asarray(mesh.points, dtype=float)
        if mesh.n_cells == 0:
            mesh = None
    if not np.all(np.isfinite(pts)):
        raise ValueError(f"{name}: the scan holds non-finite coordinates")
    return pts, mesh


@dataclass(frozen=True)
class Inspection:
    """The result of `inspect`.

    Attributes
    ----------
    points : (n, 3) float
        The scan in design coordinates (aligned).
    deviation : (n,) float
        Signed distance from the design surface (+ outside the material).
    transform : (4, 4) float
        Scan -> design.
    tolerance : float
        Symmetric band +/- tolerance.
    alignment : str
        ``"icp"``, ``"datum"`` or ``"none"``.
    """

    points: np.ndarray
    deviation: np.ndarray
    transform: np.ndarray
    tolerance: float
    alignment: str
    fit_rms: float = float("nan")
    mesh: object = None

    @property
    def max_deviation(self) -> float:
        return float(self.deviation.max())

    @property
    def min_deviation(self) -> float:
        return float(self.deviation.min())

    @property
    def mean_deviation(self) -> float:
        return float(self.deviation.mean())

    @property
    def rms_deviation(self) -> float:
        return float(np.sqrt(np.mean(self.deviation ** 2)))

    @property
    def std_deviation(self) -> float:
        return float(self.deviation.std())

    @property
    def within_tolerance(self) -> float:
        """Fraction of the points within +/- tolerance."""
        return float(np.mean(np.abs(self.deviation) <= self.tolerance))

    @property
    def passed(self) -> bool:
        return bool(np.all(np.abs(self.deviation) <= self.tolerance))

    def worst(self, k: int = WORST, *, separation: float | None = None) -> list:
        """The `k` worst places: points farthest from the surface, each at least
        `separation` (default 10 % of the scan's size) from those already named,
        so that one defect is named once; out-of-tolerance points only, or the
        single worst point when every point is within tolerance."""
        sep = 0.1 * float(np.ptp(self.points, axis=0).max()) if separation is None else float(separation)
        order = np.argsort(-np.abs(self.deviation))
        chosen = []
        for i in order[: max(2000, 50 * k)]:        # the candidates: the worst few thousand
            if chosen and abs(self.deviation[i]) <= self.tolerance:
                break
            if all(np.linalg.norm(self.points[i] - self.points[j]) >= sep for j in chosen):
                chosen.append(int(i))
                if len(chosen) == k:
                    break
        return [{"index": i, "point": self.points[i].tolist(), "deviation": float(self.deviation[i])}
                for i in chosen]

    def to_dict(self) -> dict:
        return {"points": int(len(self.points)), "alignment": self.alignment, "tolerance": self.tolerance,
                "max_deviation": self.max_deviation, "min_deviation": self.min_deviation,
                "mean_deviation": self.mean_deviation, "rms_deviation": self.rms_deviation,
                "std_deviation": self.std_deviation, "within_tolerance": self.within_tolerance,
                "passed": self.passed, "fit_rms": self.fit_rms, "transform": self.transform.tolist(),
                "worst": self.worst()}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2)


def inspect(solid, scan, *, tolerance=0.1, align="icp", datums=None, initial=None, resolution=48):
    """Deviation of a scanned part from its design.

    Parameters
    ----------
    solid : Solid
        The design.
    scan : (n, 3) float, pyvista.PolyData, or file name
        Scan points, a scanned mesh, or a scan file (see `load_scan`).
    tolerance : float
        The band +/- tolerance for the pass/fail verdict.
    align : {"icp", "datum", "none"}
        Best fit, the 3-2-1 datum planes in `datums`, or the scan as given.
    datums : three (point, normal), optional
        Datum planes of the design (``align="datum"``).
    initial : (4, 4) float, optional
        Start of the best fit.
    resolution : int
        Cells across the design's mesh for the coarse best fit.

    Returns
    -------
    Inspection

    Examples
    --------
    >>> from implicit import sphere
    >>> from spatial.meshing import mesh
    >>> scan = mesh(sphere(1.02), resolution=24).points
    >>> r = inspect(sphere(1.0), scan, tolerance=0.05)
    >>> round(r.mean_deviation, 6), r.passed
    (0.02, True)
    """
    from implicit import Solid
    from implicit.solid import as_positive

    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected a Solid, got {type(solid).__name__}")
    tol = as_positive(tolerance, "tolerance")
    if align not in ("icp", "datum", "none"):
        raise ValueError(f"align: expected 'icp', 'datum' or 'none', got {align!r}")
    if align == "datum" and datums is None:
        raise ValueError("datums: align='datum' needs three (point, normal) datum planes")
    mesh = None
    if isinstance(scan, (str, os.PathLike)):
        pts, mesh = load_scan(scan)
    elif hasattr(scan, "points") and hasattr(scan, "n_cells"):
        pts, mesh = np.asarray(scan.points, dtype=float), scan
    else:
        pts = np.asarray(scan, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 3:
        raise ValueError(f"scan: expected (n, 3) points with n >= 3, got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ValueError("scan: the points hold non-finite coordinates")
    rms = float("nan")
    if align == "icp":
        areas = vertex_areas(mesh) if mesh is not None else None
        T, info = icp(pts, solid, initial=initial, weights=areas, resolution=resolution)
        rms = info["rms"]
    elif align == "datum":
        T = datum_align(pts, solid, datums)
    else:
        T = np.eye(4)
    q = apply(T, pts)
    dev, _ = _signed_distance(solid, q)
    if mesh is not None:
        mesh = mesh.copy()
        mesh.points = q
    return Inspection(q, dev, T, tol, align, rms, mesh)
