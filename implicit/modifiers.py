"""Modifiers: grow or shrink a solid, hollow it into a shell."""

from __future__ import annotations

import numpy as np

from .csg import grown_bounds
from .solid import Solid, as_finite, as_positive, register_operator

__all__ = ["Offset", "Shell", "offset", "shell"]


class Offset(Solid):
    """The child grown by `distance` (shrunk when negative): ``f - distance``.

    A conservative bound (1-Lipschitz when the child is).  For an exact child
    and ``distance >= 0`` it is exact outside the result (the distance to a
    Minkowski sum with a ball), but not inside a non-convex result, so the node
    is marked exact only for ``distance == 0``.
    """

    kind = "offset"
    __slots__ = ()

    def __init__(self, solid: Solid, distance: float):
        if not isinstance(solid, Solid):
            raise TypeError(f"offset: solid must be a Solid, got {type(solid).__name__}")
        d = as_finite(distance, "distance")
        # A bound field grows farther than `d` beyond the child's bounds where it
        # underestimates the distance, and an intersection farther than its own box.
        super().__init__((solid,), {"distance": d}, grown_bounds(solid, max(d, 0.0)),
                         exact=solid.exact and d == 0, lipschitz=solid.lipschitz)

    def _evaluate(self, p):
        return self._children[0]._evaluate(p) - self._params["distance"]


class Shell(Solid):
    """Hollow solid: points within `thickness`/2 of the child's boundary
    (``|f| - thickness/2``), a wall centred on the original surface.

    A conservative bound: exact outside the wall for an exact child, not
    inside it.
    """

    kind = "shell"
    __slots__ = ()

    def __init__(self, solid: Solid, thickness: float):
        if not isinstance(solid, Solid):
            raise TypeError(f"shell: solid must be a Solid, got {type(solid).__name__}")
        t = as_positive(thickness, "thickness")
        super().__init__((solid,), {"thickness": t}, grown_bounds(solid, t / 2),
                         exact=False, lipschitz=solid.lipschitz)

    def _evaluate(self, p):
        return np.abs(self._children[0]._evaluate(p)) - 0.5 * self._params["thickness"]


@register_operator("offset")
def offset(solid: Solid, distance: float) -> Solid:
    """`solid` grown by `distance` (negative shrinks).

    Examples
    --------
    >>> from implicit import sphere, offset
    >>> float(offset(sphere(1.0), 0.5)([[1.5, 0, 0]])[0])
    0.0
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"offset: solid must be a Solid, got {type(solid).__name__}")
    return Offset(solid, distance)


@register_operator("shell")
def shell(solid: Solid, thickness: float) -> Solid:
    """A wall of `thickness` centred on the boundary of `solid`."""
    if not isinstance(solid, Solid):
        raise TypeError(f"shell: solid must be a Solid, got {type(solid).__name__}")
    return Shell(solid, thickness)
