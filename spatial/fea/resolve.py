"""Whether an element size can resolve a part: the narrowest gaps of its extruded profiles.

A gap narrower than the element size (the space between two gear teeth, a
slot in a plate) cannot be followed by a surface of that edge length: the
remeshed surface bridges it, cuts the material around it or folds onto
itself.  The gaps of extruded 2D profiles are found before any meshing from
the profile's own distance field, sampled on a grid: a point outside the
profile whose two nearest boundary parts lie on nearly opposite sides
(central-difference gradient of the distance under `RIDGE_GRADIENT`) is on
the medial axis of a gap, twice its distance is the gap's width there.
"""

from __future__ import annotations

import numpy as np

from implicit.solid import Solid

__all__ = ["narrowest_gap", "check_resolvable", "resolving_field", "RIDGE_GRADIENT"]

#: Largest gradient magnitude of the distance on a gap's medial axis (|grad d| = cos of half
#: the angle between the directions to the two sides: 0.35 is an angle over 139 degrees).
RIDGE_GRADIENT = 0.35
#: The largest size reported as working, as a fraction of the narrowest gap, rounded to two
#: digits (the gear of examples/gear.py, gap 2.22: 2.0 meshes and solves, 2.2 leaves a 9.8
#: degree element, 2.4 a self-intersecting surface).
LARGEST_FRACTION = 0.9
#: Most grid points sampled per profile, and grid cells across its longer side.
MAX_SAMPLES = 400_000
GRID_CELLS = 400


def narrowest_gap(solid: Solid, size: float):
    """The narrowest gap ``(width, (x, y))`` of the extruded profiles of `solid` (profile
    coordinates), or None when it has none narrower than twice `size`.

    Examples
    --------
    >>> from implicit import extrude, polygon
    >>> slot = polygon([[0, 0], [10, 0], [10, 10], [6, 10], [6, 2], [4, 2], [4, 10], [0, 10]])
    >>> round(narrowest_gap(extrude(slot, 5.0), 1.5)[0], 1)
    2.0
    """
    best = None
    for node in solid.walk():
        if node.kind != "extrude":
            continue
        prof = node._profile
        lo, hi = (np.asarray(b, dtype=np.float64) for b in prof.bounds)
        if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
            continue
        ext = hi - lo
        # The same grid whatever the size asked (the answer must not depend on it).
        h = max(float(ext.max()) / GRID_CELLS, float(np.sqrt(ext[0] * ext[1] / MAX_SAMPLES)))
        xs = np.arange(lo[0] + 0.5 * h, hi[0], h)
        ys = np.arange(lo[1] + 0.5 * h, hi[1], h)
        if xs.size < 8 or ys.size < 8:
            continue
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        d = prof._evaluate(np.ascontiguousarray(np.column_stack([gx.ravel(), gy.ravel()]))).reshape(gx.shape)
        # Differences over 3 cells each way: a ridge between two samples (at most half a cell
        # from one) then shows a gradient under 1/6, not up to 1/2 as with neighbouring cells.
        k = 3
        grad = np.full(d.shape, np.inf)
        ddx = (d[2 * k:, k:-k] - d[:-2 * k, k:-k]) / (2 * k * h)
        ddy = (d[k:-k, 2 * k:] - d[k:-k, :-2 * k]) / (2 * k * h)
        grad[k:-k, k:-k] = np.hypot(ddx, ddy)
        ridge = (d > (k + 1) * h) & (d < size) & (grad < RIDGE_GRADIENT)
        if not ridge.any():
            continue
        i = np.argmin(np.where(ridge, d, np.inf))
        width = 2.0 * float(d.ravel()[i])
        if best is None or width < best[0]:
            best = (width, (float(gx.ravel()[i]), float(gy.ravel()[i])))
    return best


def check_resolvable(solid: Solid, size: float) -> None:
    """Raise a ValueError naming the largest size that works when `size` cannot resolve a gap
    (sizes above `LARGEST_FRACTION` of the narrowest gap, to two digits, are refused).

    Examples
    --------
    >>> from implicit import extrude, polygon
    >>> slot = polygon([[0, 0], [10, 0], [10, 10], [6, 10], [6, 2], [4, 2], [4, 10], [0, 10]])
    >>> check_resolvable(extrude(slot, 5.0), 3.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: size: 3 cannot follow a gap ... wide (...); the largest size that resolves it is 1.8
    """
    gap = narrowest_gap(solid, size)
    if gap is None:
        return
    width, (x, y) = gap
    largest = float(f"{LARGEST_FRACTION * width:.2g}")
    if size <= largest:
        return
    raise ValueError(f"size: {size:g} cannot follow a gap {width:.3g} wide (the narrowest gap of an extruded "
                     f"profile, at ({x:.3g}, {y:.3g})); the largest size that resolves it is {largest:g}")


def resolving_field(solid: Solid, size: float):
    """None when elements of `size` follow every gap of `solid`'s extruded profiles (sizes up to
    `LARGEST_FRACTION` of the narrowest), else the graded `spatial.fea.graded.SizeField` that
    does: fine in the gaps, `size` away from them.

    Raises a ValueError naming the largest size that works only when the gap would need
    elements under ``SMALLEST_FRACTION`` of `size` (a mesh then mostly made of the gap's
    elements and of the grading away from it).

    Examples
    --------
    >>> from implicit import extrude, polygon
    >>> slot = polygon([[0, 0], [10, 0], [10, 10], [6, 10], [6, 2], [4, 2], [4, 10], [0, 10]])
    >>> resolving_field(extrude(slot, 5.0), 1.5) is None, resolving_field(extrude(slot, 5.0), 3.0).smallest < 1.8
    (True, True)
    """
    from .graded import graded_size_field
    from .size_field import GAP_FRACTION, SMALLEST_FRACTION

    gap = narrowest_gap(solid, size)
    if gap is None:
        return None
    width, (x, y) = gap
    if size <= float(f"{LARGEST_FRACTION * width:.2g}"):
        return None
    largest = float(f"{GAP_FRACTION * width / SMALLEST_FRACTION:.2g}")
    if size > largest:
        raise ValueError(f"size: {size:g} cannot follow a gap {width:.3g} wide (the narrowest gap of an extruded "
                         f"profile, at ({x:.3g}, {y:.3g})): its elements would be under {SMALLEST_FRACTION:g} of the "
                         f"size; the largest size that resolves it is {largest:g}")
    return graded_size_field(solid, size, voxel=max(GAP_FRACTION * width, SMALLEST_FRACTION * size) / 4.0)
