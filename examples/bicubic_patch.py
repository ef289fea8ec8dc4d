"""Bicubic patch p(u, v) = sum k_ij u^i v^j: 16 coefficients from a 4 x 4 grid of points.

The coefficients come from Lagrange interpolation through the grid; the
patch passes through all 16 points (checked).
"""

import numpy as np

from _gallery import plt, save
from parametric import BicubicPatch


def main(out_dir=None, small=False):
    g = np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij"), -1)
    z = np.array([[0, 0.5, 0.3, 0], [0.4, 1.6, 1.2, 0.2], [0.2, 1.0, 1.8, 0.6], [0, 0.2, 0.5, 0.1]])
    pts = np.concatenate([g, z[..., None]], axis=-1)
    patch = BicubicPatch(pts)
    third = np.linspace(0, 1, 4)
    assert np.allclose(patch.grid(third, third), pts)
    n = 16 if small else 40
    t = np.linspace(0, 1, n)
    S = patch.grid(t, t)
    fig = plt.figure(figsize=(7.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(S[..., 0], S[..., 1], S[..., 2], cmap="coolwarm", alpha=0.7, linewidth=0)
    ax.scatter(*pts.reshape(-1, 3).T, color="k", s=18, depthshade=False, label="the 4 x 4 points")
    for i in range(4):
        ax.plot(*pts[i].T, color="0.4", lw=0.6)
        ax.plot(*pts[:, i].T, color="0.4", lw=0.6)
    ax.set_title("Bicubic patch interpolating a 4 x 4 grid", fontsize=10)
    ax.legend(fontsize=8)
    ax.view_init(elev=30, azim=-50)
    fig.tight_layout()
    return save(fig, "bicubic_patch", out_dir)


if __name__ == "__main__":
    print(main())
