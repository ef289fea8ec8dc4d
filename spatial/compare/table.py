"""`compare`: every representation of one part in one table, its JSON form and its bar chart.

Examples
--------
>>> from implicit import box
>>> from spatial.compare import compare
>>> table = compare(box((2, 1, 1)) - box((0.5, 2, 0.5)), resolution=24, n_queries=2000)
>>> [r.name for r in table.rows][:2]
['CSG tree', 'half-space form']
>>> table.row("half-space form").volume_error < 1e-12
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from implicit.solid import Solid

from ..files import atomic_write
from .schemes import ANSWERS, build_all

__all__ = ["Comparison", "compare"]


def _fmt_bytes(n):
    if n is None:
        return "-"
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000.0


def _fmt(x, spec):
    return "-" if x is None else format(x, spec)


@dataclass
class Comparison:
    """The measured representations of one part, the reference volume and the checked claims."""

    rows: list
    reference_volume: float
    reference: str
    resolution: int
    n_queries: int
    claims: list = field(default_factory=list)
    context: dict = field(default_factory=dict, repr=False)

    def row(self, name):
        """The row called `name`."""
        for r in self.rows:
            if r.name == name:
                return r
        raise KeyError(name)

    def to_dict(self) -> dict:
        """``{"representations": [...], "reference_volume", "claims", ...}`` (plain JSON values)."""
        return {"representations": [r.to_dict() for r in self.rows],
                "reference_volume": self.reference_volume, "reference": self.reference,
                "resolution": self.resolution, "n_queries": self.n_queries,
                "claims": [dict(c) for c in self.claims]}

    def markdown(self) -> str:
        """The table (and the claims) as Markdown."""
        head = ["representation", "bytes (memory)", "bytes (file)", "build s", "volume", "volume error",
                f"{self.n_queries:.0e} queries s".replace("+0", ""), *[a.split("/")[0] for a in ANSWERS]]
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for r in self.rows:
            if not r.applies:
                lines.append(f"| {r.name} | n/a: {r.note} |" + " |" * (len(head) - 2))
                continue
            marks = ["yes" if a in r.answers else "no" for a in ANSWERS]
            lines.append("| " + " | ".join([
                r.name, _fmt_bytes(r.bytes), _fmt_bytes(r.file_bytes), _fmt(r.build_seconds, ".3g"),
                _fmt(r.volume, ".7g"), _fmt(r.volume_error, ".2e"), _fmt(r.query_seconds, ".3g"), *marks]) + " |")
        out = "\n".join(lines)
        out += f"\n\nReference volume {self.reference_volume:.10g} ({self.reference}); resolution N = {self.resolution}."
        notes = [f"- {r.name}: {r.note}" for r in self.rows if r.applies and r.note]
        if notes:
            out += "\n\n" + "\n".join(notes)
        if self.claims:
            out += "\n\n| claim (seed) | checked | figures |\n|---|---|---|\n"
            out += "\n".join(f"| {c['claim']} | {'holds' if c['holds'] else 'does not hold'} | {c['figures']} |"
                             for c in self.claims)
        return out

    def chart(self, path=None, *, dpi=110):
        """Bar chart of storage and volume error (log scales); writes a PNG when `path` is given.

        Returns the matplotlib figure.
        """
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rows = [r for r in self.rows if r.applies]
        names = [r.name for r in rows]
        y = np.arange(len(rows))
        fig, (a, b) = plt.subplots(1, 2, figsize=(12, 0.45 * len(rows) + 1.8), sharey=True)
        mem = [r.bytes or np.nan for r in rows]
        fil = [r.file_bytes or np.nan for r in rows]
        a.barh(y - 0.2, mem, 0.4, label="in memory", color="#4477aa")
        a.barh(y + 0.2, fil, 0.4, label="in its file", color="#88ccee")
        a.set_xscale("log")
        a.set_xlabel("storage, bytes (log scale)")
        a.legend(loc="lower right", fontsize=8)
        err = [r.volume_error if r.volume_error else np.nan for r in rows]
        floor = 1e-16
        b.barh(y, [max(e, floor) if np.isfinite(e) else np.nan for e in err], 0.5, color="#cc6677")
        for i, r in enumerate(rows):
            if r.volume is None:
                b.text(floor * 3, i, "no volume (cannot answer)", va="center", fontsize=8, color="0.3")
            elif r.volume_error is not None and r.volume_error <= floor:
                b.text(floor * 3, i, "exact", va="center", fontsize=8, color="0.3")
        b.set_xscale("log")
        b.set_xlim(floor, 1.0)
        b.set_xlabel("relative volume error (log scale)")
        a.set_yticks(y)
        a.set_yticklabels(names, fontsize=9)
        a.invert_yaxis()
        fig.suptitle(f"Representations of one part (N = {self.resolution}); reference volume "
                     f"{self.reference_volume:.8g}", fontsize=10)
        fig.tight_layout()
        if path is not None:
            atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"), ".png")
        return fig


def compare(solid, *, resolution=64, reference=None, n_queries=100_000, claims=True, progress=None) -> Comparison:
    """Build every representation scheme that applies to `solid` and measure each.

    Parameters
    ----------
    solid : implicit.Solid
        The part (bounded).
    resolution : int
        Cells across the part's largest extent for the cell, grid, mesh and level-set forms.
    reference : float, optional
        The part's exact volume, when known; otherwise the half-space form's exact
        volume or a finer extrapolated mesh integral.
    n_queries : int
        Point-membership queries timed per representation (uniform in the bounds, seeded).
    claims : bool
        Also check the seed's claims (`spatial.compare.claims`), with figures.
    progress : bool, optional
        Progress bar (default: on a terminal).

    Returns
    -------
    Comparison
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected an implicit.Solid, got {type(solid).__name__}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 8 <= resolution <= 1024:
        raise ValueError(f"resolution: expected an integer in [8, 1024], got {resolution!r}")
    if isinstance(n_queries, bool) or not isinstance(n_queries, (int, np.integer)) or n_queries < 10:
        raise ValueError(f"n_queries: expected an integer >= 10, got {n_queries!r}")
    if reference is not None and not (isinstance(reference, (int, float)) and math.isfinite(reference) and reference > 0):
        raise ValueError(f"reference: expected a positive volume, got {reference!r}")
    solid.require_bounds()
    rows, ref, why, ctx = build_all(solid, resolution=int(resolution), reference=reference,
                                    n_queries=int(n_queries), progress=progress)
    table = Comparison(rows, ref, why, int(resolution), int(n_queries), context=ctx)
    if claims:
        from .claims import check_claims
        table.claims = check_claims(table, solid)
    return table
