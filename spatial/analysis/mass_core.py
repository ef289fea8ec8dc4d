"""Mass properties with known error: the results, the raw moments and their integrals over triangles.

`mass_properties` accepts a closed triangle mesh, an occupancy grid, an octree
or a `Solid`, and returns a frozen `MassProperties` whose `error` holds an
absolute error bound (or estimate, see below) for every quantity.

* Meshes integrate exactly by the divergence theorem, one signed tetrahedron
  per triangle (Mirtich 1996; Eberly, "Polyhedral Mass Properties
  (Revisited)"), relative to the centre of the bounding box so that parts far
  from the origin lose no precision.  The error is the floating-point
  round-off bound.
* Occupancy grids and octrees integrate FULL cells exactly as boxes (each
  cell's own inertia included) and BOUNDARY cells with the fractional
  occupancy ``clamp(0.5 - d/h, 0, 1)`` of the sampled distance ``d`` (second
  order).  The error is a rigorous bound: the true solid lies between the FULL
  cells and the FULL plus BOUNDARY cells.
  (`spatial.analysis.mass_cells`)
* Solids are meshed (vertices on the surface) at ``N/4``, ``N/2`` and ``N``
  cells across, each mesh corrected by the thin shell between it and the
  true surface.  Levels chosen for a tolerance have their sharp edges
  rebuilt and report the finest level with an estimate from the steps
  between levels; at a given resolution plain marching-cubes integrals are
  Richardson-extrapolated, ``(4 Q_N - Q_{N/2}) / 3``, the error estimate from
  the same sequence one level further down with a safety factor
  (`spatial.analysis.mass_solid`).

Everything here works on the raw moments of the solid about a reference point
``c0``: ``V = int 1``, ``m1 = int (x - c0)``, ``M2 = int (x - c0)(x - c0)^T``
and the boundary area; `_finish` turns raw moments and their errors into the
reported quantities.

References
----------
B. Mirtich, "Fast and Accurate Computation of Polyhedral Mass Properties",
J. Graphics Tools 1(2):31-50, 1996. doi:10.1080/10867651.1996.10487458

D. Eberly, "Polyhedral Mass Properties (Revisited)", Geometric Tools, 2002.

F. Tonon, "Explicit Exact Formulas for the 3-D Tetrahedron Inertia Tensor in
Terms of its Vertex Coordinates", J. Math. Stat. 1(1), 2004.
doi:10.3844/jmssp.2005.8.11
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np

from ..meshing.arrays import faces_array as _faces_array  # noqa: F401

__all__ = [
    "MassProperties",
    "MassError",
    "mesh_moments",
    "UNITS",
    "OpenMeshError",
    "ToleranceError",
]

#: Length units accepted, with their length in metres.
UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "in": 0.0254, "ft": 0.3048}

#: Safety factor applied to the extrapolation error estimate of solids.
SAFETY = 4.0

#: Default relative tolerance when a solid is given without a discretisation.
DEFAULT_TOLERANCE = 1e-4

#: Coarsest and finest number of cells across a solid in the adaptive loop.
MIN_CELLS = 32
MAX_CELLS = 512

#: Cells of the coarsest extrapolation level across the thinnest wall (at
#: least one lattice node inside the wall on every line through it).
WALL_CELLS = 1.2

#: Most cells across a solid that a thin wall may ask for.
MAX_WALL_CELLS = 4096

_EPS = np.finfo(np.float64).eps


class OpenMeshError(ValueError):
    """A mesh is not a closed, consistently oriented surface."""


class ToleranceError(RuntimeError):
    """The requested tolerance was not reached within the finest mesh allowed.

    Attributes ``tolerance``, ``estimate`` (the relative error reached) and
    ``cells`` (of the finest level) say how far it got.
    """

    def __init__(self, message, *, tolerance=None, estimate=None, cells=None):
        super().__init__(message)
        self.tolerance = tolerance
        self.estimate = estimate
        self.cells = cells


# ---------------------------------------------------------------------------
# result types
# ---------------------------------------------------------------------------

def _frozen(a) -> np.ndarray:
    arr = np.array(a, dtype=np.float64)
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True)
class MassError:
    """Absolute error bounds of every quantity of `MassProperties`.

    Each field has the shape of the quantity it bounds (``centroid`` (3,),
    ``inertia`` (3, 3), ...); ``principal_axes`` bounds each component of the
    unit axis vectors (2 when an axis is not determined, e.g. a sphere).
    """

    volume: float
    mass: float
    area: float
    centroid: np.ndarray
    inertia: np.ndarray
    inertia_origin: np.ndarray
    principal_moments: np.ndarray
    principal_axes: np.ndarray

    def to_dict(self) -> dict:
        """Plain-Python form (floats and nested lists) for JSON."""
        return {k: _plain(getattr(self, k)) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class MassProperties:
    """Mass properties of a solid and their absolute error bounds.

    Lengths are in `units`; `density` is in kg per cubic metre, so `mass` is
    in kg and the inertia tensors in kg * units^2.

    Attributes
    ----------
    volume : float
        Volume in units^3.
    mass : float
        ``density * volume`` converted to kg.
    area : float
        Boundary area in units^2.
    centroid : (3,) float
        Centre of volume (= centre of mass for a uniform density).
    inertia : (3, 3) float
        Inertia tensor about the centroid (kg * units^2).
    inertia_origin : (3, 3) float
        Inertia tensor about the origin of coordinates.
    principal_moments : (3,) float
        Eigenvalues of `inertia`, ascending.
    principal_axes : (3, 3) float
        Unit eigenvectors of `inertia`, one per row, matching
        `principal_moments`, forming a right-handed frame.
    density : float
        kg / m^3.
    units : str
        Length unit of the model: one of `UNITS`.
    voxel_size : float
        Cell size of the discretisation (0 for an exact mesh integral).
    error : MassError
        Absolute error bound of every quantity above.
    method : str
        How the integrals were computed.
    """

    volume: float
    mass: float
    area: float
    centroid: np.ndarray
    inertia: np.ndarray
    inertia_origin: np.ndarray
    principal_moments: np.ndarray
    principal_axes: np.ndarray
    density: float
    units: str
    voxel_size: float
    error: MassError
    method: str = "mesh"

    @property
    def mass_unit(self) -> str:
        """Unit of `mass`."""
        return "kg"

    @property
    def inertia_unit(self) -> str:
        """Unit of the inertia tensors."""
        return f"kg*{self.units}^2"

    def relative_error(self) -> float:
        """Error bound of the volume relative to the volume."""
        return self.error.volume / abs(self.volume) if self.volume else float("inf")

    def to_dict(self) -> dict:
        """Plain-Python form for JSON: every field, `error` as a nested object."""
        out = {}
        for k in self.__dataclass_fields__:
            v = getattr(self, k)
            out[k] = v.to_dict() if isinstance(v, MassError) else _plain(v)
        out["mass_unit"] = self.mass_unit
        out["inertia_unit"] = self.inertia_unit
        return out


def _plain(v):
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    return v


# ---------------------------------------------------------------------------
# raw moments
# ---------------------------------------------------------------------------

@dataclass
class _Raw:
    """Raw moments about `c0` and their absolute errors."""

    c0: np.ndarray
    volume: float
    m1: np.ndarray
    m2: np.ndarray
    area: float
    e_volume: float = 0.0
    e_m1: np.ndarray = field(default_factory=lambda: np.zeros(3))
    e_m2: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    e_area: float = 0.0

    def vector(self) -> np.ndarray:
        """The moments as one vector (14,) for extrapolation."""
        return np.concatenate([[self.volume], self.m1, self.m2.ravel(), [self.area]])

    @classmethod
    def from_vector(cls, c0, vec, err) -> "_Raw":
        return cls(c0, float(vec[0]), vec[1:4].copy(), vec[4:13].reshape(3, 3).copy(), float(vec[13]),
                   float(err[0]), err[1:4].copy(), err[4:13].reshape(3, 3).copy(), float(err[13]))


def _check_closed(tri: np.ndarray, n_points: int) -> None:
    """Raise `OpenMeshError` unless every edge is in exactly two triangles,
    used once in each direction."""
    a = tri.ravel()
    b = np.roll(tri, -1, axis=1).ravel()
    keys = a * n_points + b
    uniq, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 1):
        bad = uniq[counts > 1][0]
        raise OpenMeshError(f"mesh: not consistently oriented or not manifold: edge "
                            f"({bad // n_points}, {bad % n_points}) is used twice in the same direction")
    rev = b * n_points + a
    pos = np.searchsorted(uniq, rev)
    pos = np.minimum(pos, uniq.size - 1)
    missing = uniq[pos] != rev
    if np.any(missing):
        i = int(np.flatnonzero(missing)[0])
        raise OpenMeshError(f"mesh: not closed: {int(missing.sum())} half-edges have no opposite, "
                            f"e.g. edge ({a[i]}, {b[i]}) (a closed mesh has every edge in two triangles "
                            f"with opposite directions)")


def mesh_moments(points, triangles, *, center=None, check: bool = True) -> _Raw:
    """Exact raw moments of the polyhedron bounded by `triangles`.

    Each triangle ``(a, b, c)`` (relative to `center`) spans a signed
    tetrahedron with the reference point, of volume ``det / 6`` with
    ``det = a . (b x c)``; its first moment is ``det (a + b + c) / 24`` and
    its second moment ``det (s s^T + a a^T + b b^T + c c^T) / 120`` with
    ``s = a + b + c``.  Summed over a closed surface these are the integrals
    of 1, x and x x^T over the enclosed volume (divergence theorem).

    Parameters
    ----------
    points : (n, 3) float
    triangles : (m, 3) int
        Outward-oriented (counter-clockwise seen from outside).
    center : (3,) float, optional
        Reference point; default the centre of the bounding box.
    check : bool
        Verify the surface is closed and consistently oriented.
    """
    points = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    if check:
        _check_closed(tri, points.shape[0])
    if center is None:
        center = 0.5 * (points.min(axis=0) + points.max(axis=0))
    c0 = np.asarray(center, dtype=np.float64)
    a, b, c, cross, area_terms = _corners(points, tri, c0)
    return _moments_of(a, b, c, cross, area_terms, c0)


def _corners(points, tri, c0):
    """Triangle corners relative to `c0` as (3, m) rows (contiguous per
    coordinate), their ``(b - a) x (c - a)`` and areas."""
    pt = np.ascontiguousarray((points - c0).T)
    a = pt[:, tri[:, 0]]
    b = pt[:, tri[:, 1]]
    c = pt[:, tri[:, 2]]
    u = b - a
    v = c - a
    cross = np.empty_like(u)
    np.subtract(u[1] * v[2], u[2] * v[1], out=cross[0])
    np.subtract(u[2] * v[0], u[0] * v[2], out=cross[1])
    np.subtract(u[0] * v[1], u[1] * v[0], out=cross[2])
    area = 0.5 * np.sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2])
    return a, b, c, cross, area


def _moments_of(a, b, c, cross, area_terms, c0) -> _Raw:
    det = a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]     # a . ((b - a) x (c - a)) = a . (b x c)
    s = a + b + c
    volume = det.sum() / 6.0
    ds = s * det
    m1 = ds.sum(axis=1) / 24.0
    m2 = (ds @ s.T + (a * det) @ a.T + (b * det) @ b.T + (c * det) @ c.T) / 120.0
    # Round-off: each term carries a few ulps; the sum of |terms| bounds the error.
    adet = np.abs(det)
    scale = 16 * _EPS * (np.sqrt(det.shape[0]) + 8)
    e_volume = scale * adet.sum() / 6.0
    e_m1 = scale * (np.abs(s) @ adet) / 24.0
    e_m2 = np.full((3, 3), scale * (adet @ (s * s).sum(axis=0)) * 4 / 120.0)
    e_area = scale * area_terms.sum()
    return _Raw(c0, float(volume), m1, m2, float(area_terms.sum()),
                float(e_volume), e_m1, e_m2, float(e_area))


# ---------------------------------------------------------------------------
# raw moments -> reported quantities
# ---------------------------------------------------------------------------

def _check_density_units(density, units) -> tuple[float, str, float]:
    if isinstance(density, bool) or not isinstance(density, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"density: expected a positive number (kg/m^3), got {density!r}")
    rho = float(density)
    if not np.isfinite(rho) or rho <= 0:
        raise ValueError(f"density: expected a positive finite number (kg/m^3), got {density!r}")
    if not isinstance(units, str):
        raise TypeError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
    if units not in UNITS:
        raise ValueError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
    return rho, units, UNITS[units]


def _inertia_from_second(c: np.ndarray) -> np.ndarray:
    """Inertia tensor ``tr(C) E - C`` of a second-moment tensor `c`."""
    return np.trace(c) * np.eye(3) - c


def _inertia_error(ec: np.ndarray) -> np.ndarray:
    """Absolute error bound of ``tr(C) E - C`` from elementwise bounds of C."""
    d = np.diag(ec)
    out = ec.copy()
    out[np.diag_indices(3)] = d.sum() - d
    return out


def _finish(raw: _Raw, density: float, units: str, voxel_size: float, method: str) -> MassProperties:
    rho, units, metre = _check_density_units(density, units)
    V = raw.volume
    if not V > 0:
        raise ValueError(f"solid: expected a positive volume, got {V:g} "
                         "(is the mesh oriented inward, or the solid empty?)")
    # mass in kg: rho [kg/m^3] * V [units^3] * (m/unit)^3; inertia in kg * units^2
    kg_per_volume = rho * metre ** 3
    mass = kg_per_volume * V
    r = raw.m1 / V
    centroid = raw.c0 + r
    second_c = raw.m2 - np.outer(raw.m1, raw.m1) / V
    second_c = 0.5 * (second_c + second_c.T)
    inertia = kg_per_volume * _inertia_from_second(second_c)
    c = centroid
    inertia_origin = inertia + mass * (np.dot(c, c) * np.eye(3) - np.outer(c, c))

    w, vecs = np.linalg.eigh(inertia)
    axes = vecs.T.copy()
    # deterministic signs: largest component positive, right-handed frame
    idx = np.argmax(np.abs(axes), axis=1)
    signs = np.sign(axes[np.arange(3), idx])
    axes *= np.where(signs == 0, 1.0, signs)[:, None]
    if np.linalg.det(axes) < 0:
        axes[2] = -axes[2]

    # ---- error propagation (first order, absolute values) ----
    eV, e1, e2 = raw.e_volume, np.abs(raw.e_m1), np.abs(raw.e_m2)
    am1 = np.abs(raw.m1)
    e_r = e1 / V + am1 * eV / V ** 2
    gyration = np.sqrt(max(np.trace(second_c), 0.0) / V)
    e_centroid = e_r + 1e4 * _EPS * (np.abs(centroid) + gyration)
    e_second_c = e2 + (np.outer(e1, am1) + np.outer(am1, e1)) / V + np.outer(am1, am1) * eV / V ** 2
    e_inertia = kg_per_volume * _inertia_error(e_second_c)
    e_inertia = e_inertia + 8 * _EPS * np.abs(inertia).max()
    # about the origin: M2o = M2 + c0 m1^T + m1 c0^T + V c0 c0^T
    ac0 = np.abs(raw.c0)
    e_m2o = e2 + np.outer(ac0, e1) + np.outer(e1, ac0) + eV * np.outer(ac0, ac0)
    e_inertia_origin = kg_per_volume * _inertia_error(e_m2o) + 8 * _EPS * np.abs(inertia_origin).max()
    norm_e = float(np.linalg.norm(e_inertia))
    e_moments = np.full(3, norm_e)
    gaps = np.array([min(abs(w[i] - w[j]) for j in range(3) if j != i) for i in range(3)])
    with np.errstate(divide="ignore", invalid="ignore"):
        sin_bound = np.where(gaps > 0, 2.0 * norm_e / gaps, np.inf)
    e_axes = np.repeat(np.minimum(np.sqrt(2.0) * sin_bound, 2.0)[:, None], 3, axis=1)

    err = MassError(
        volume=float(eV), mass=float(kg_per_volume * eV), area=float(raw.e_area),
        centroid=_frozen(e_centroid), inertia=_frozen(e_inertia), inertia_origin=_frozen(e_inertia_origin),
        principal_moments=_frozen(e_moments), principal_axes=_frozen(e_axes),
    )
    return MassProperties(
        volume=float(V), mass=float(mass), area=float(raw.area), centroid=_frozen(centroid),
        inertia=_frozen(inertia), inertia_origin=_frozen(inertia_origin), principal_moments=_frozen(w),
        principal_axes=_frozen(axes), density=rho, units=units, voxel_size=float(voxel_size),
        error=err, method=method,
    )


# ---------------------------------------------------------------------------
# the entry point
# ---------------------------------------------------------------------------
