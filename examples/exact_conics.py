"""The four exact conics as rational quadratic Bezier arcs (weights 1, w, 1).

w < 1: ellipse, w = 1: parabola, w > 1: hyperbola; the circle is the ellipse
with w = cos(theta/2).  Each arc is checked against its implicit equation.
"""

import numpy as np

from _gallery import plt, save
from parametric import circle, conic_arc, ellipse, hyperbola, parabola


def main(out_dir=None, small=False):
    u = np.linspace(0, 1, 100 if small else 400)
    fig, axes = plt.subplots(1, 5, figsize=(17, 3.9))
    shapes = [("circle x² + y² = 1", circle(1.0, center=(0, 0)), lambda p: p[:, 0] ** 2 + p[:, 1] ** 2 - 1),
              ("ellipse x²/4 + y² = 1", ellipse(2.0, 1.0, center=(0, 0)),
               lambda p: p[:, 0] ** 2 / 4 + p[:, 1] ** 2 - 1),
              ("parabola y = x²", parabola(1.0, (-1.5, 1.5)), lambda p: p[:, 1] - p[:, 0] ** 2),
              ("hyperbola x² - y² = 1", hyperbola(1.0, 1.0, (-1.5, 1.5)), lambda p: p[:, 0] ** 2 - p[:, 1] ** 2 - 1)]
    for ax, (title, curve, implicit) in zip(axes[:4], shapes):
        p = curve(u)[:, :2]
        err = np.abs(implicit(p)).max()
        ctrl = np.asarray(curve.control_points)[:, :2]
        ax.plot(*ctrl.T, "o--", color="0.6", lw=0.8, ms=3)
        ax.plot(p[:, 0], p[:, 1], lw=2)
        ax.set_title(f"{title}\nequation residual {err:.1e}", fontsize=9)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    # the same three points, three weights: the conic family of one control triangle
    p0, p1, p2 = np.array([0.0, 0.0]), np.array([1.0, 1.0]), np.array([2.0, 0.0])
    last = axes[4]
    for w, col, kind in ((0.5, "C0", "ellipse"), (1.0, "C1", "parabola"), (2.0, "C3", "hyperbola")):
        q = conic_arc(p0, p1, p2, w)(u)
        last.plot(q[:, 0], q[:, 1], color=col, lw=2, label=f"w = {w:g}: {kind}")
    last.plot(*np.array([p0, p1, p2]).T, "ko--", lw=0.8, ms=4)
    last.set_title("one control triangle, weights (1, w, 1)", fontsize=9)
    last.legend(fontsize=7, loc="lower center")
    last.set_aspect("equal")
    fig.tight_layout()
    return save(fig, "exact_conics", out_dir)


if __name__ == "__main__":
    print(main())
