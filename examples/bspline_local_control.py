"""B-spline local control: a cubic B-spline of 8 control points against a Bezier curve of degree 7.

Moving control point 5 changes the cubic B-spline only on the four knot
spans that point's basis function covers (the rest of the curve does not
move: measured below), while the Bezier curve of the same polygon moves
everywhere.  A degree-3 B-spline is C^2.
"""

import numpy as np

from _gallery import plt, save
from parametric import Bezier, BSpline


def main(out_dir=None, small=False):
    u = np.linspace(0, 1, 200 if small else 600)
    P = np.array([[0, 0], [1, 2], [2, -1], [3, 2], [4, 0], [5, 2], [6, -1], [7, 1]], float)
    Q = P.copy()
    Q[5] = [5.3, 3.5]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2), sharey=True)
    for ax, make, title in ((axes[0], lambda c: BSpline(c, 3), "cubic B-spline, 8 control points: local"),
                            (axes[1], lambda c: Bezier(c), "Bezier of the same polygon (degree 7): global")):
        a, b = make(P), make(Q)
        pa, pb = a(u), b(u)
        moved = np.linalg.norm(pa - pb, axis=1) > 1e-9
        ax.plot(*P.T, "o--", color="0.5", lw=0.8, ms=4)
        ax.plot(*Q[5], "o", color="C3")
        ax.annotate("", xy=Q[5], xytext=P[5], arrowprops=dict(arrowstyle="->", color="C3"))
        ax.plot(pa[:, 0], pa[:, 1], color="C0", lw=2, label="before")
        ax.plot(pb[:, 0], pb[:, 1], color="C3", lw=1.5, ls="--", label="after moving point 5")
        ax.set_title(f"{title}\ncurve moved on {moved.mean():.0%} of its parameter range", fontsize=10)
        ax.legend(fontsize=8, loc="lower left")
        ax.grid(alpha=0.3)
        ax.set_aspect("equal")
    fig.tight_layout()
    return save(fig, "bspline_local_control", out_dir)


if __name__ == "__main__":
    print(main())
