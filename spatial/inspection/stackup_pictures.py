"""The picture of a tolerance stack-up: the distribution and the contributions."""

from __future__ import annotations

import math
import os

import numpy as np

from ..files.atomic import atomic_write

__all__ = ["stackup_picture"]


def stackup_picture(result, path, *, title=None):
    """Histogram of the Monte-Carlo measure with the RSS normal curve, the
    worst-case limits and the interference side shaded; beside it each
    tolerance's share of the variance.  Returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = os.fspath(path)
    if not p.lower().endswith(".png"):
        raise ValueError(f"path: expected a .png file name, got {p!r}")
    folder = os.path.dirname(os.path.abspath(p))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, "No such directory", folder)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6), dpi=120, gridspec_kw={"width_ratios": [2.2, 1]})
    try:
        x = result.samples
        lo = min(result.worst_min, float(x.min()) if len(x) else result.worst_min, 0.0)
        hi = max(result.worst_max, float(x.max()) if len(x) else result.worst_max)
        pad = 0.08 * (hi - lo or 1.0)
        lo, hi = lo - pad, hi + pad
        if len(x):
            ax.hist(x, bins=40, range=(lo, hi), density=True, color="#6a9fb5", edgecolor="#234", lw=0.4,
                    label=f"Monte-Carlo, {len(x)} samples (seed {result.seed})")
        if result.rss_std > 0:
            t = np.linspace(lo, hi, 400)
            pdf = np.exp(-0.5 * ((t - result.rss_mean) / result.rss_std) ** 2) / (result.rss_std * math.sqrt(2 * math.pi))
            ax.plot(t, pdf, color="black", lw=1.2, label=f"RSS normal: mean {result.rss_mean:.4g}, "
                                                        f"sigma {result.rss_std:.3g}")
        ax.axvspan(lo, 0.0, color="#d62728", alpha=0.12, label="interference (< 0)")
        ax.axvline(0.0, color="#d62728", lw=1.0)
        for v, name in ((result.worst_min, "worst case min"), (result.worst_max, "worst case max")):
            ax.axvline(v, color="#ff7f0e", ls="--", lw=1.2)
            ax.annotate(f"{name}\n{v:.4g}", (v, ax.get_ylim()[1] * 0.6), fontsize=7, ha="center",
                        color="#b35900", bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
        ax.axvline(result.nominal, color="#2ca02c", lw=1.0, label=f"nominal {result.nominal:.4g}")
        ax.set_xlim(lo, hi)
        ax.set_xlabel(f"{result.label} (model units)")
        ax.set_ylabel("probability density")
        pi = result.probability_interference
        ax.set_title(title or f"P(interference) = {pi:.3%} +/- {result.probability_error:.2%}", fontsize=10)
        ax.legend(fontsize=7, loc="upper left", framealpha=0.9)
        ax.grid(True, lw=0.3)
        names = sorted(result.names, key=lambda k: result.contributions[k])
        shares = [100 * result.contributions[n] for n in names]
        bars = bx.barh(names, shares, color="#6a9fb5", edgecolor="#234")
        for b, n in zip(bars, names):
            bx.text(b.get_width() + 1, b.get_y() + b.get_height() / 2,
                    f"{result.contributions[n]:.1%} (slope {result.effects[n]:.3g})", va="center", fontsize=8)
        bx.set_xlim(0, 130)
        bx.set_xlabel("share of the variance (%)")
        bx.set_title("which tolerance contributes most", fontsize=10)
        bx.grid(True, axis="x", lw=0.3)
        fig.tight_layout()
        atomic_write(p, lambda tmp: fig.savefig(tmp, format="png"))
    finally:
        plt.close(fig)
    return p
