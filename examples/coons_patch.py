"""Coons patch: a surface interpolating four boundary curves by linear blending.

P(u, v) = C0(u) f(v) + C1(u) g(v) + D0(v) f(u) + D1(v) g(u) - bilinear corner terms,
with f(t) = 1 - t and g(t) = t.  The patch is checked to reproduce its four
boundary curves.
"""

import numpy as np

from _gallery import plt, save
from parametric import BSpline, CoonsPatch


def main(out_dir=None, small=False):
    c0 = BSpline([[0, 0, 0], [1, 0, 1.2], [2, 0, -0.4], [3, 0, 0]], 3)
    c1 = BSpline([[0, 3, 0.5], [1, 3, -0.8], [2, 3, 1.0], [3, 3, 0.3]], 3)
    d0 = BSpline([[0, 0, 0], [0, 1.5, 1.5], [0, 3, 0.5]], 2)
    d1 = BSpline([[3, 0, 0], [3, 1.5, -1.0], [3, 3, 0.3]], 2)
    patch = CoonsPatch(c0, c1, d0, d1)
    n = 16 if small else 40
    t = np.linspace(0, 1, n)
    S = patch.grid(t, t)
    assert np.allclose(S[:, 0], c0(t)) and np.allclose(S[:, -1], c1(t))
    assert np.allclose(S[0, :], d0(t)) and np.allclose(S[-1, :], d1(t))
    fig = plt.figure(figsize=(7.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(S[..., 0], S[..., 1], S[..., 2], cmap="viridis", alpha=0.75, linewidth=0)
    for curve, name in ((c0, "C0(u)"), (c1, "C1(u)"), (d0, "D0(v)"), (d1, "D1(v)")):
        p = curve(np.linspace(0, 1, 100))
        ax.plot(*p.T, color="C3", lw=3)
        ax.text(*p[50], name, fontsize=9)
    ax.set_title("Coons patch through four boundary curves (linear blending)", fontsize=10)
    ax.view_init(elev=28, azim=-58)
    fig.tight_layout()
    return save(fig, "coons_patch", out_dir)


if __name__ == "__main__":
    print(main())
