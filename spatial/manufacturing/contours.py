"""Level contours of a sampled 2D field, moved onto the true level.

The tool-path planner contours fields built from the solid (its silhouette
seen from +z, offset by the tool radius, clipped by the stock): scikit-image's
``find_contours`` gives polylines through the grid samples; each point is then
moved onto the exact level by Newton steps on the field itself
(``q -= (g(q) - c) grad g / |grad g|^2``), so the offsets are the solid's own
distance levels, not polygon offsets of a sampled outline.
"""

from __future__ import annotations

import numpy as np

__all__ = ["level_loops", "newton_to_level"]

#: Newton steps onto the level.
NEWTON_STEPS = 4


def newton_to_level(field, q, level, h, steps=NEWTON_STEPS):
    """Move points `q` (n, 2) onto ``field(q) == level``.

    `field` maps probes of shape (n, 5, 2) (each point and its four
    gradient neighbours, point i first on axis 0) to values (n, 5), so a
    caller can evaluate each point's probes with data of its own (a height).

    A step never moves a point by more than half a sample step `h`, so a
    point stays on its own branch of the contour.
    """
    step = 1e-6 * h
    offs = np.array([[0.0, 0.0], [step, 0.0], [-step, 0.0], [0.0, step], [0.0, -step]])
    q = np.asarray(q, dtype=float).copy()
    for _ in range(steps):
        v = field(q[:, None, :] + offs)
        f = v[:, 0] - level
        g = np.column_stack([v[:, 1] - v[:, 2], v[:, 3] - v[:, 4]]) / (2 * step)
        gg = np.einsum("ij,ij->i", g, g)
        ok = gg > 1e-12
        move = np.where(ok[:, None], f[:, None] * g / np.where(ok, gg, 1.0)[:, None], 0.0)
        norm = np.linalg.norm(move, axis=1)
        move *= np.minimum(1.0, 0.5 * h / np.maximum(norm, 1e-300))[:, None]
        q -= move
    return q


def _orient_left(field, loop, h):
    """The loop reversed if needed so that the side where the field exceeds
    its level lies on the left of the direction of travel."""
    a = loop
    b = np.roll(loop, -1, axis=0)
    t = b - a
    mid = 0.5 * (a + b)
    left = np.column_stack([-t[:, 1], t[:, 0]])
    n = np.linalg.norm(left, axis=1, keepdims=True)
    probe = mid + 0.25 * h * left / np.maximum(n, 1e-300)
    back = mid - 0.25 * h * left / np.maximum(n, 1e-300)
    vote = np.sum(np.sign(field(probe) - field(back)) * n[:, 0])
    return loop if vote >= 0 else loop[::-1].copy()


def level_loops(values, xs, ys, level, *, refine=None, orient=None, min_points=4):
    """Closed loops where the sampled field equals `level`.

    Parameters
    ----------
    values : (nx, ny) float
        Samples ``g(xs[i], ys[j])``.
    xs, ys : (nx,), (ny,) float
        Uniform sample coordinates.
    level : float
    refine : callable, optional
        ``(n, 2) -> (n, 2)``: moves contour points onto the exact level (see
        `newton_to_level`); without it the samples' linear interpolation stays.
    orient : callable, optional
        A field ``(m, 2) -> (m,)`` (the samples' interpolation will do) that
        orients each loop with its higher values on the left.
    min_points : int
        Shorter polylines (sampling noise) are dropped.

    Returns
    -------
    list of (k, 2) float
        Closed loops (first point not repeated), each with the side where
        the field exceeds `level` on its left (counter-clockwise around a
        region of higher values).  Contours open at the edge of the sampled
        window are dropped: pad the window.
    """
    from skimage import measure

    h = float(xs[1] - xs[0])
    loops = []
    for c in measure.find_contours(values, level):
        if c.shape[0] < min_points + 1 or not np.allclose(c[0], c[-1]):
            continue
        c = c[:-1]
        loops.append(np.column_stack([xs[0] + c[:, 0] * h, ys[0] + c[:, 1] * (ys[1] - ys[0])]))
    if not loops:
        return []
    if refine is not None:
        sizes = np.cumsum([len(lp) for lp in loops])[:-1]
        loops = np.split(refine(np.concatenate(loops)), sizes)
    if orient is not None:
        loops = [_orient_left(orient, lp, h) for lp in loops]
    return loops
