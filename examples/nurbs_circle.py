"""NURBS: the exact circle, and the pull of a weight.

Left: the NURBS circle (nine control points, weights 1 and sqrt(2)/2) with
its largest radial error against sampled points.  Right: raising the weight
h_i of one control point draws the curve towards it; with every weight 1 the
NURBS is the B-spline.
"""

import numpy as np

from _gallery import plt, save
from parametric import NURBS, BSpline, circle


def main(out_dir=None, small=False):
    u = np.linspace(0, 1, 200 if small else 800)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.8))
    c = circle(1.0, center=(0.0, 0.0))
    pts = c(u)
    err = np.abs(np.linalg.norm(pts, axis=1) - 1).max()
    ctrl = np.asarray(c.control_points)
    a.plot(*ctrl[:, :2].T, "o--", color="0.5", lw=0.8, ms=4)
    a.plot(pts[:, 0], pts[:, 1], lw=2)
    for p, w in zip(ctrl, np.asarray(c.weights)):
        a.annotate(f"{w:.3f}", p[:2], textcoords="offset points", xytext=(4, 4), fontsize=7)
    a.set_title(f"NURBS circle: radial error {err:.1e}", fontsize=10)
    a.set_aspect("equal")
    P = np.array([[0, 0], [1, 2], [3, 2.5], [4, 0], [6, 1]], float)
    for k, w in enumerate((0.25, 1.0, 3.0, 10.0)):
        weights = np.ones(len(P))
        weights[2] = w
        q = NURBS(P, weights, 3)(u)
        b.plot(q[:, 0], q[:, 1], color=plt.cm.viridis(k / 3), label=f"h_2 = {w:g}")
    plain = BSpline(P, 3)(u)
    b.plot(plain[:, 0], plain[:, 1], "k:", lw=1, label="B-spline (all h = 1)")
    b.plot(*P.T, "o--", color="0.5", lw=0.8, ms=4)
    b.annotate("P2", P[2], textcoords="offset points", xytext=(5, 5))
    b.set_title("Increasing h_2 draws the curve towards P2", fontsize=10)
    b.legend(fontsize=8)
    b.set_aspect("equal")
    for ax in (a, b):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return save(fig, "nurbs_circle", out_dir)


if __name__ == "__main__":
    print(main())
