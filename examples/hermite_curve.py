"""Hermite curve: the end points and end tangents as its geometric coefficients.

P(u) = [1 - 3u^2 + 2u^3, 3u^2 - 2u^3, u - 2u^2 + u^3, -u^2 + u^3] [P0, P1, P0', P1'].
Left: the four blending functions; right: the same end points with the end
tangents scaled by 0.5 .. 4 -- the longer the tangent, the further the curve
follows it before turning.
"""

import numpy as np

from _gallery import plt, save
from parametric import Hermite


def main(out_dir=None, small=False):
    u = np.linspace(0, 1, 60 if small else 200)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for f, label in ((1 - 3 * u ** 2 + 2 * u ** 3, "1 - 3u² + 2u³ (P0)"), (3 * u ** 2 - 2 * u ** 3, "3u² - 2u³ (P1)"),
                     (u - 2 * u ** 2 + u ** 3, "u - 2u² + u³ (P0')"), (-u ** 2 + u ** 3, "-u² + u³ (P1')")):
        a.plot(u, f, label=label)
    a.set_title("Hermite blending functions", fontsize=10)
    a.set_xlabel("u")
    a.legend(fontsize=8)
    a.grid(alpha=0.3)
    p0, p1 = np.array([0.0, 0.0]), np.array([4.0, 0.0])
    t0, t1 = np.array([1.0, 2.0]), np.array([1.0, -2.0])
    for k, s in enumerate((0.5, 1.0, 2.0, 4.0)):
        c = Hermite(p0, p1, s * t0, s * t1)
        pts = c(u)
        # the curve's own tangent at its ends equals the given tangent
        assert np.allclose(c.derivative(0.0)[0] if c.derivative(0.0).ndim > 1 else c.derivative(0.0), s * t0)
        b.plot(pts[:, 0], pts[:, 1], color=plt.cm.viridis(k / 3), label=f"tangents x {s:g}")
        b.annotate("", xy=p0 + 0.25 * s * t0, xytext=p0,
                   arrowprops=dict(arrowstyle="->", color=plt.cm.viridis(k / 3)))
        b.annotate("", xy=p1 + 0.25 * s * t1, xytext=p1,
                   arrowprops=dict(arrowstyle="->", color=plt.cm.viridis(k / 3)))
    b.plot(*zip(p0, p1), "ko")
    b.text(*(p0 - [0.2, 0.35]), "P0")
    b.text(*(p1 + [0.05, -0.35]), "P1")
    b.set_aspect("equal")
    b.set_title("Effect of the tangent vectors (arrows: P0', P1' at 1/4 scale)", fontsize=10)
    b.legend(fontsize=8)
    b.grid(alpha=0.3)
    fig.tight_layout()
    return save(fig, "hermite_curve", out_dir)


if __name__ == "__main__":
    print(main())
