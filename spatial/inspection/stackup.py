"""Tolerance stack-up of a clearance in an assembly: worst case, RSS and Monte-Carlo.

An assembly is a function ``build(values) -> {name: Solid}`` of named
parameters: family parameters (a hole's diameter) and placements (a shaft's
offset), each with a `Tolerance` (plus/minus band, uniform or normal).  The
measured quantity is by default the *signed gap* between two parts,

    gap(a, b) = 2 min_p max(f_a(p), f_b(p)),

the distance between them when they are apart (for exact distance fields)
and minus the thickness of their overlap when they interfere: a shaft of
diameter d centred in a hole of diameter D gives (D - d) / 2, the radial
clearance.  The minimum is found by sampling the region both parts share and
a pattern search from the best samples.  Any other measure
``measure(parts) -> float`` can be given.

* Worst case: the measure at every corner of the tolerance box (all
  ``2^n`` combinations of lower and upper limits, n <= 12; with n <= 4 also
  every parameter's middle, 3^n points): the exact extremes of a measure
  monotone in each parameter, and of one that peaks at a middle (an offset
  either way, ``-|e|``); otherwise the linear estimate ``centre +/- sum e_i
  half-band_i`` and the Monte-Carlo extremes complete the picture.
* Sensitivities ``s_i`` by central differences over each half-band, and
  effects ``e_i``, the larger one-sided slope (equal to ``|s_i|`` for a
  smooth measure; a kink such as ``|e|`` has ``s_i = 0`` but ``e_i = 1``);
  RSS (root sum of squares) standard deviation ``sqrt(sum (e_i sigma_i)^2)``
  and each tolerance's share of that variance.
* Monte-Carlo with a seeded generator: the distribution of the measure and
  the probability of interference (measure < 0) with its standard error.
* The worst-case corner is also checked by the project's interference test
  (`analysis.interference.check_assembly`) when asked.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Tolerance", "StackUp", "stackup", "signed_gap"]

#: Largest number of toleranced parameters whose corners are all evaluated.
MAX_CORNERS = 12
#: Up to this many parameters, the worst case also tries each one's middle (3^n points).
MAX_MIDDLES = 4
#: Samples per side of the coarse grid of `signed_gap`.
GAP_GRID = 12
#: Pattern-search rounds of `signed_gap`.
GAP_ROUNDS = 24


@dataclass(frozen=True)
class Tolerance:
    """A toleranced value: ``nominal`` with limits ``nominal - minus`` and ``nominal + plus``.

    `distribution` ``"uniform"`` spreads samples evenly between the limits;
    ``"normal"`` centres them on the middle of the band with standard deviation
    `sigma` (default: a sixth of the band, the limits at +/- 3 sigma).

    Examples
    --------
    >>> t = Tolerance(10.0, 0.05, 0.0)            # a hole 10 +0.05/-0
    >>> t.lower, t.upper, round(t.mean, 4), round(t.std, 6)
    (10.0, 10.05, 10.025, 0.008333)
    """

    nominal: float
    plus: float
    minus: float
    distribution: str = "normal"
    sigma: float | None = None

    def __post_init__(self):
        for name in ("nominal", "plus", "minus"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
                raise ValueError(f"{name}: expected a finite number, got {v!r}")
        if self.plus < 0 or self.minus < 0 or self.plus + self.minus == 0:
            raise ValueError(f"plus, minus: expected non-negative limits, not both zero, got +{self.plus}/-{self.minus}")
        if self.distribution not in ("uniform", "normal"):
            raise ValueError(f"distribution: expected 'uniform' or 'normal', got {self.distribution!r}")
        if self.sigma is not None and not (self.sigma > 0):
            raise ValueError(f"sigma: expected a positive number, got {self.sigma!r}")

    @classmethod
    def symmetric(cls, nominal, tolerance, distribution="normal", sigma=None):
        """``nominal +/- tolerance``."""
        return cls(nominal, tolerance, tolerance, distribution, sigma)

    @property
    def lower(self) -> float:
        return float(self.nominal - self.minus)

    @property
    def upper(self) -> float:
        return float(self.nominal + self.plus)

    @property
    def mean(self) -> float:
        return 0.5 * (self.lower + self.upper)

    @property
    def half_band(self) -> float:
        return 0.5 * (self.upper - self.lower)

    @property
    def std(self) -> float:
        if self.distribution == "uniform":
            return self.half_band / math.sqrt(3.0)
        return self.sigma if self.sigma is not None else self.half_band / 3.0

    def sample(self, rng, n):
        if self.distribution == "uniform":
            return rng.uniform(self.lower, self.upper, n)
        return rng.normal(self.mean, self.std, n)


def _project(solid, q, steps=3):
    """Newton steps of points q onto the zero level of `solid`."""
    for _ in range(steps):
        g = solid.gradient(q)
        f = solid(q)
        gg = np.einsum("ij,ij->i", g, g)
        q = q - (f / np.where(gg > 1e-20, gg, 1.0))[:, None] * g
    return q


def _surface_min(a, b, lo, hi, grid, rounds):
    """min of f_b over the surface of a (within the box lo..hi): a pattern search on the surface."""
    size = float(np.max(hi - lo))
    axes = [np.linspace(lo[k], hi[k], grid) for k in range(3)]
    P = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    fa = a(P)
    h = float(np.max((hi - lo) / (grid - 1)))
    P = P[np.abs(fa) < 2 * h]                      # start near the surface of a
    if len(P) == 0:
        return np.inf
    q = _project(a, P, 4)
    ok = np.abs(a(q)) < 1e-6 * size
    if not ok.any():
        return np.inf
    q = q[ok]
    v = b(q)
    keep = 2
    best = np.argsort(v)[:keep]
    pts, vals = q[best], v[best]
    offs = np.vstack([np.zeros(3), np.eye(3), -np.eye(3), np.array(list(itertools.product((-1, 1), repeat=3)))])
    step = h
    for _ in range(rounds):
        cand = _project(a, (pts[:, None, :] + offs[None, :, :] * step).reshape(-1, 3), 1)
        cand = cand[np.abs(a(cand)) < 1e-6 * size]
        if len(cand) == 0:
            break
        cv = b(cand)
        order = np.argsort(cv)[:keep]
        if cv[order[0]] <= vals[0]:
            pts, vals = cand[order], cv[order]
        else:
            step *= 0.5
        step *= 0.7                      # a compass search that always contracts: h 0.7^rounds at the end
    # the search accepts points a millionth off the surface: put the best ones on it
    pts = _project(a, pts, 3)
    return float(np.min(b(pts)))


def signed_gap(a, b, *, grid=GAP_GRID, rounds=GAP_ROUNDS):
    """Clearance between two solids (> 0), or minus the depth one's surface enters the other (< 0).

    ``min(min over the surface of a of f_b, min over the surface of b of f_a)``,
    each found by projecting samples onto the surface (Newton steps) and a
    pattern search on it.  For exact distance fields this is the distance
    between separate solids; a shaft of diameter d in a hole of diameter D,
    off its axis by e, gives (D - d) / 2 - e.

    Examples
    --------
    >>> from implicit import sphere
    >>> round(signed_gap(sphere(1.0), sphere(1.0, center=(2.5, 0, 0))), 6)
    0.5
    """
    alo, ahi = (np.asarray(v, dtype=float) for v in a.bounds)
    blo, bhi = (np.asarray(v, dtype=float) for v in b.bounds)
    if not (np.all(np.isfinite(alo)) and np.all(np.isfinite(ahi)) and np.all(np.isfinite(blo))
            and np.all(np.isfinite(bhi))):
        raise ValueError("signed_gap: expected bounded solids")
    # where the surfaces come close: the boxes' common part, grown by their distance
    apart = np.maximum(0.0, np.maximum(alo - bhi, blo - ahi))
    margin = float(np.linalg.norm(apart)) + 0.05 * float(min(np.max(ahi - alo), np.max(bhi - blo)))
    lo = np.maximum(alo, blo) - margin
    hi = np.minimum(ahi, bhi) + margin
    lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
    return min(_surface_min(a, b, lo, hi, grid, rounds), _surface_min(b, a, lo, hi, grid, rounds))


@dataclass(frozen=True)
class StackUp:
    """The result of `stackup` (see the module notes)."""

    names: list
    nominal: float
    worst_min: float
    worst_max: float
    worst_corner: dict
    linear_min: float
    linear_max: float
    sensitivities: dict
    effects: dict
    contributions: dict
    rss_mean: float
    rss_std: float
    samples: np.ndarray
    probability_interference: float
    probability_error: float
    seed: int
    worst_check: dict | None = None
    label: str = "gap"
    extra: dict = field(default_factory=dict)

    @property
    def mc_mean(self) -> float:
        return float(self.samples.mean())

    @property
    def mc_std(self) -> float:
        return float(self.samples.std(ddof=1))

    def to_dict(self) -> dict:
        return {"measure": self.label, "nominal": self.nominal, "worst_min": self.worst_min,
                "worst_max": self.worst_max, "worst_corner": self.worst_corner, "linear_min": self.linear_min,
                "linear_max": self.linear_max, "sensitivities": self.sensitivities,
                "effects": self.effects, "contributions": self.contributions, "rss_mean": self.rss_mean, "rss_std": self.rss_std,
                "mc_samples": int(len(self.samples)), "mc_mean": self.mc_mean, "mc_std": self.mc_std,
                "mc_min": float(self.samples.min()), "mc_max": float(self.samples.max()),
                "probability_interference": self.probability_interference,
                "probability_error": self.probability_error, "seed": self.seed, "worst_check": self.worst_check}

    def table(self) -> str:
        w = max(len(n) for n in self.names)
        lines = [f"{'parameter':<{w}}  {'sensitivity':>12}  {'effect':>8}  {'share of variance':>18}"]
        for n in sorted(self.names, key=lambda k: -self.contributions[k]):
            s = self.sensitivities[n]
            lines.append(f"{n:<{w}}  {0.0 if abs(s) < 1e-9 else s:12.6g}  {self.effects[n]:8.4g}  "
                         f"{100 * self.contributions[n]:17.2f}%")
        return "\n".join(lines)


def stackup(build, tolerances, *, between=None, measure=None, samples=1000, seed=0, check_worst=False,
            check_resolution=None, label=None):
    """Stack up `tolerances` through `build` to a clearance of the assembly.

    Parameters
    ----------
    build : callable
        ``build(values) -> {name: Solid}``, `values` a dict of floats.
    tolerances : dict of str -> Tolerance
        Every toleranced parameter (plain floats pass fixed values).
    between : (str, str), optional
        Two part names: the measure is their `signed_gap`.
    measure : callable, optional
        ``measure(parts) -> float`` instead of the gap.
    samples : int
        Monte-Carlo samples (0: none).
    seed : int
        Seed of the generator (numpy's default_rng).
    check_worst : bool
        Run `check_assembly` on the worst corner's assembly (at
        `check_resolution` cells, its default when None).

    Returns
    -------
    StackUp

    Examples
    --------
    >>> from implicit import box, cylinder
    >>> def build(v):
    ...     return {"plate": box((4, 4, 1)) - cylinder(v["D"] / 2, 2), "pin": cylinder(v["d"] / 2, 3)}
    >>> tol = {"D": Tolerance(1.0, 0.02, 0.0), "d": Tolerance(0.96, 0.0, 0.02)}
    >>> r = stackup(build, tol, between=("plate", "pin"), samples=0)
    >>> round(r.worst_min, 4), round(r.worst_max, 4)                 # (D - d) / 2
    (0.02, 0.04)
    """
    if not callable(build):
        raise TypeError(f"build: expected a function values -> parts, got {type(build).__name__}")
    if not isinstance(tolerances, dict) or not tolerances:
        raise TypeError("tolerances: expected a non-empty dict of name -> Tolerance")
    fixed = {k: float(v) for k, v in tolerances.items() if not isinstance(v, Tolerance)}
    tols = {k: v for k, v in tolerances.items() if isinstance(v, Tolerance)}
    if not tols:
        raise ValueError("tolerances: no Tolerance among the values")
    if (between is None) == (measure is None):
        raise ValueError("give exactly one of between=(part, part) or measure=function")
    if between is not None:
        if not isinstance(between, (tuple, list)) or len(between) != 2:
            raise ValueError(f"between: expected two part names, got {between!r}")
        a_name, b_name = between

        def measure(parts):  # noqa: F811 - the gap between the named parts
            for n in (a_name, b_name):
                if n not in parts:
                    raise ValueError(f"between: no part {n!r} in the assembly (parts: {', '.join(parts)})")
            return signed_gap(parts[a_name], parts[b_name])

        label = label or f"signed gap {a_name} / {b_name}"
    label = label or "measure"
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 0:
        raise ValueError(f"samples: expected a non-negative integer, got {samples!r}")
    names = list(tols)

    def evaluate(values):
        return float(measure(build({**fixed, **values})))

    mean_values = {n: tols[n].mean for n in names}
    nominal = evaluate({n: float(tols[n].nominal) for n in names})
    centre = evaluate(mean_values)
    sens, effect = {}, {}
    for n in names:
        hb = tols[n].half_band
        up = evaluate({**mean_values, n: tols[n].mean + hb})
        dn = evaluate({**mean_values, n: tols[n].mean - hb})
        sens[n] = (up - dn) / (2 * hb)
        # the larger one-sided slope: a measure such as (D - d) / 2 - |e| has no
        # central derivative in e at e = 0, yet e takes clearance either way
        effect[n] = max(abs(up - centre), abs(dn - centre)) / hb
    lin = sum(effect[n] * tols[n].half_band for n in names)
    var = {n: (effect[n] * tols[n].std) ** 2 for n in names}
    total = sum(var.values())
    shares = {n: (var[n] / total if total > 0 else 0.0) for n in names}
    if len(names) <= MAX_CORNERS:
        # corners; with few parameters the middles too, for measures that peak inside
        levels = [((tols[n].lower, tols[n].mean, tols[n].upper) if len(names) <= MAX_MIDDLES
                   else (tols[n].lower, tols[n].upper)) for n in names]
        corners = list(itertools.product(*levels))
        vals = [evaluate(dict(zip(names, c))) for c in corners]
        k = int(np.argmin(vals))
        worst_min, worst_max = float(min(vals)), float(max(vals))
        worst_corner = dict(zip(names, map(float, corners[k])))
    else:
        worst_corner = {n: (tols[n].lower if sens[n] > 0 else tols[n].upper) for n in names}
        worst_min, worst_max = centre - lin, centre + lin
    rng = np.random.default_rng(seed)
    draws = {n: tols[n].sample(rng, samples) for n in names}
    mc = np.array([evaluate({n: float(draws[n][i]) for n in names}) for i in range(samples)])
    p = float(np.mean(mc < 0)) if samples else float("nan")
    perr = float(math.sqrt(max(p * (1 - p), 0.0) / samples)) if samples else float("nan")
    check = None
    if check_worst:
        from ..analysis.interference import check_assembly

        report = check_assembly(build({**fixed, **worst_corner}), resolution=check_resolution)
        check = {"interfering": [[a, b, r.volume] for a, b, r in report.interfering],
                 "touching": [[a, b] for a, b, _ in report.touching]}
    return StackUp(names, nominal, worst_min, worst_max, worst_corner, centre - lin, centre + lin, sens, effect,
                   shares,
                   centre, math.sqrt(total), mc, p, perr, int(seed), check, label)
