"""The side of an extruded polygon split at its sharp corners, as facets of their own.

An extrusion's side is one face to the user (``gear.side``), but a polygon
profile with sharp corners (the tips and roots of a gear's teeth) has a
sharp edge of the solid at each of them.  Feature detection and the FEA
surface find sharp edges where two facets meet (`implicit.facets`), so the
side is cut into *runs*: chains of polygon edges between two corners whose
turn exceeds `SHARP_TURN_DEGREES`.  Each run's field is its signed distance,
continued past both ends along the end edges' lines (rays), so that the
fields of two neighbouring runs cross at their common corner and a corner
of the solid is the common zero of three facets (two runs and a cap).

Runs are dealt in turn to four facets (up to three more for the runs past
the last whole four), each facet's field that of its run nearest the point:
neighbouring runs always lie on different facets, and a gear of 80 runs
costs four facets, not 80, in every array of facet values and gradients.

The fields and their closed-form gradients come from one compiled loop over
points and edges (`implicit.profile_facets_kernel`, numba, loaded on first use).
"""

from __future__ import annotations

import numpy as np

__all__ = ["polygon_runs", "run_fields", "run_groups", "SHARP_TURN_DEGREES"]

#: A polygon vertex whose edges turn by more than this (degrees) is a sharp corner of the side.
SHARP_TURN_DEGREES = 30.0
_RUNS: dict = {}


def polygon_runs(vertices):
    """The polygon re-ordered to start at a sharp corner and the first vertex of each run.

    Returns ``(vertices (m, 2) counter-clockwise, starts (r,) int)``, or None
    when the polygon has fewer than two sharp corners (its side stays one facet).

    Examples
    --------
    >>> v, starts = polygon_runs([[0, 0], [2, 0], [2, 1], [0, 1]])
    >>> v.tolist(), starts.tolist()
    ([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]], [0, 1, 2, 3])
    >>> polygon_runs([[np.cos(t), np.sin(t)] for t in np.linspace(0, 2 * np.pi, 24, endpoint=False)]) is None
    True
    """
    v = np.asarray(vertices, dtype=np.float64)
    key = v.tobytes()
    if key in _RUNS:
        return _RUNS[key]
    x, y = v[:, 0], v[:, 1]
    if np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y) < 0:
        v = v[::-1]
    e = np.roll(v, -1, axis=0) - v                  # edge i: vertex i -> i + 1
    a = np.arctan2(e[:, 1], e[:, 0])
    turn = np.degrees((a - np.roll(a, 1) + np.pi) % (2 * np.pi) - np.pi)  # at vertex i
    sharp = np.flatnonzero(np.abs(turn) > SHARP_TURN_DEGREES)
    out = None
    if sharp.size >= 2:
        v = np.ascontiguousarray(np.roll(v, -sharp[0], axis=0))
        out = (v, sharp - sharp[0])
    if len(_RUNS) > 64:
        _RUNS.clear()
    _RUNS[key] = out
    return out


def run_groups(count):
    """The facet ``(count,)`` each of `count` runs goes to: ``j % 4``, the runs past the last
    whole four to facets 4, 5, 6 (runs go round a polygon: the first and last are neighbours).

    Four, not two: the two flanks of a gear's tooth, and the two flanks facing each other
    across a gap, then lie on different facets, as do neighbouring runs.

    Examples
    --------
    >>> run_groups(4).tolist(), run_groups(6).tolist(), run_groups(3).tolist()
    ([0, 1, 2, 3], [0, 1, 2, 3, 4, 5], [0, 1, 2])
    """
    g = np.arange(count, dtype=np.int64) % 4
    tail = count % 4 if count > 4 else 0
    if tail:
        g[count - tail:] = 4 + np.arange(tail)
    return g


def run_fields(vertices, starts, points, nearest=False):
    """Signed fields ``(k, n)`` and 2D gradients ``(k, n, 2)`` of the facets of a polygon's runs.

    `vertices` and `starts` come from `polygon_runs`; run ``j`` holds the
    edges ``starts[j] .. starts[j + 1] - 1`` and goes to facet
    ``run_groups(r)[j]`` (``k`` from 2 to 7).  A run's field is minus the
    distance inside the polygon and plus it outside; past its ends it is the
    signed distance to the line of its end edge, so neighbouring runs cross
    at their corner.  A facet's field is that of its run of least ``|field|``.
    When `nearest`, the third result is ``(facet (n,) int, distance (n,))``:
    the facet whose run holds the polygon edge nearest each point (rays left
    out) and the polygon's signed distance; else None.

    Examples
    --------
    >>> v, s = polygon_runs([[0, 0], [2, 0], [2, 1], [0, 1]])
    >>> f, g, (near, d) = run_fields(v, s, np.array([[1.0, 0.25], [3.0, 0.5]]), nearest=True)
    >>> f[:, 0].tolist(), f[:, 1].tolist(), near.tolist(), d.tolist()
    ([-0.25, -1.0, -0.75, -1.0], [-0.5, 1.0, -0.5, 3.0], [0, 1], [-0.25, 1.0])
    >>> g[1, 1].tolist()
    [1.0, 0.0]
    """
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 2))
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    s = np.ascontiguousarray(np.r_[starts, v.shape[0]], dtype=np.int64)
    group = run_groups(s.shape[0] - 1)
    k = int(group.max()) + 1
    vals = np.empty((k, p.shape[0]))
    grads = np.empty((k, p.shape[0], 2))
    near = np.zeros(p.shape[0], dtype=np.int64)
    dist = np.empty(p.shape[0])
    if p.shape[0]:
        _kernel()(p[:, 0].copy(), p[:, 1].copy(), v[:, 0].copy(), v[:, 1].copy(), s, group, vals, grads, near,
                  dist)
    return vals, grads, ((near, dist) if nearest else None)


def _kernel():
    """The compiled loop (`implicit.profile_facets_kernel`: numba is imported on first use)."""
    from .profile_facets_kernel import run_kernel

    return run_kernel
