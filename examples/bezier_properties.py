"""Bezier curve properties: end interpolation, end tangents, a changed vertex, coincident points.

(a) Changing one vertex of the polygon moves the whole curve (global
control); (b) keeping the polygon fixed and repeating a vertex (multiple
coincident points) pulls the curve towards it.
"""

import numpy as np

from _gallery import plt, save
from parametric import Bezier


def _draw(ax, ctrl, color, label, u, dashed=False):
    c = Bezier(ctrl)
    pts = c(u)
    ax.plot(*np.asarray(ctrl).T, "o--" if not dashed else "s:", color=color, lw=0.8, ms=4, alpha=0.7)
    ax.plot(pts[:, 0], pts[:, 1], color=color, lw=2, label=label)
    # the curve interpolates the first and last vertices, tangent to the first and last legs
    assert np.allclose(pts[0], ctrl[0]) and np.allclose(pts[-1], ctrl[-1])
    return c


def main(out_dir=None, small=False):
    u = np.linspace(0, 1, 80 if small else 300)
    base = np.array([[0, 0], [1, 2.5], [3, 3], [4.5, 0.5], [6, 1.5]], float)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    _draw(a, base, "C0", "original", u)
    moved = base.copy()
    moved[2] = [3.2, 4.5]
    _draw(a, moved, "C3", "vertex 2 moved", u, dashed=True)
    a.set_title("(a) Changing a vertex moves the whole curve", fontsize=10)
    for k, repeat in enumerate((1, 2, 4)):
        ctrl = np.vstack([base[:2], np.repeat(base[2:3], repeat, axis=0), base[3:]])
        _draw(b, ctrl, plt.cm.plasma(k / 3), f"vertex 2 taken {repeat} time{'s' if repeat > 1 else ''}", u)
    b.set_title("(b) Multiple coincident points at a vertex", fontsize=10)
    for ax in (a, b):
        ax.set_aspect("equal")
        ax.legend(fontsize=8, loc="upper right")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return save(fig, "bezier_properties", out_dir)


if __name__ == "__main__":
    print(main())
