"""Bezier and B-spline surfaces with their control nets and isoparametric curves.

Left: a bicubic Bezier surface from a 4 x 4 characteristic polygon (it
passes through the corner points).  Right: a bicubic B-spline surface of a
6 x 6 net; moving one control point changes it only near that point (local
control, measured).  The thin lines are curves of constant u and v, steps of 0.1.
"""

import numpy as np

from _gallery import plt, save
from parametric import BezierSurface, BSplineSurface


def _net(n, seed):
    rng = np.random.default_rng(seed)
    g = np.stack(np.meshgrid(np.linspace(0, 3, n), np.linspace(0, 3, n), indexing="ij"), -1)
    z = np.sin(g[..., 0]) * np.cos(g[..., 1]) + 0.08 * rng.standard_normal((n, n))
    return np.concatenate([g, z[..., None]], axis=-1)


def _draw(ax, surf, net, title, samples):
    u_lines, v_lines = surf.isoparametric_lines(step=0.1, samples=samples)
    for line in list(u_lines) + list(v_lines):
        ax.plot(*line.T, color="C0", lw=0.7)
    for i in range(net.shape[0]):
        ax.plot(*net[i].T, "o--", color="C3", lw=0.6, ms=2.5)
    for j in range(net.shape[1]):
        ax.plot(*net[:, j].T, "--", color="C3", lw=0.6)
    ax.set_title(title, fontsize=10)
    ax.view_init(elev=32, azim=-55)


def main(out_dir=None, small=False):
    samples = 20 if small else 60
    fig = plt.figure(figsize=(13, 5.5))
    bez_net = _net(4, 1)
    bez = BezierSurface(bez_net)
    assert np.allclose(bez(0.0, 0.0), bez_net[0, 0]) and np.allclose(bez(1.0, 1.0), bez_net[-1, -1])
    _draw(fig.add_subplot(1, 2, 1, projection="3d"), bez, bez_net,
          "Bezier surface (4 x 4 polygon): isoparametric curves", samples)
    net = _net(6, 2)
    bsp = BSplineSurface(net, 3, 3)
    moved = net.copy()
    moved[1, 1, 2] += 1.5
    t = np.linspace(0, 1, 41)
    change = np.linalg.norm(BSplineSurface(moved, 3, 3).grid(t, t) - bsp.grid(t, t), axis=-1) > 1e-12
    _draw(fig.add_subplot(1, 2, 2, projection="3d"), bsp, net,
          f"B-spline surface (6 x 6 net, bicubic)\nmoving control (1, 1) changes {change.mean():.0%} of the surface",
          samples)
    fig.tight_layout()
    return save(fig, "bezier_bspline_surfaces", out_dir)


if __name__ == "__main__":
    print(main())
