"""What a drawing learns from the CSG tree: leaves in world coordinates,
holes, bosses and axes of revolution, rounded corners and exact extents.

A tree is walked once; each leaf comes out with the affine map that carries
world points into its own frame, and with its parity (a leaf under an odd
number of subtracting or complementing operators cuts material away: a
cylinder there is a hole).

Examples
--------
>>> from implicit import box, cylinder
>>> part = box((40, 20, 10)) - cylinder(4, 30, center=(10, 0, 0))
>>> [(f.kind, f.diameter, f.negative) for f in axial_features(part)]
[('cylinder', 8.0, True)]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Leaf", "AxialFeature", "leaves", "axial_features", "nearest_leaf", "leaf_gradients",
           "rounded_radii", "sphere_radii"]

#: Operators whose operands are walked into; every other node is one opaque leaf.
_PASS_THROUGH = {"union", "intersection", "difference", "complement", "smooth_union",
                 "smooth_intersection", "smooth_difference", "family"}


@dataclass(frozen=True)
class Leaf:
    """A leaf of the tree as seen from world coordinates.

    ``local = inverse @ (world - offset)``; the leaf's field in world units is
    ``factor * leaf(local)`` (``factor`` is the smallest singular value of the
    composed matrix, as `implicit.transforms.Affine` scales its child).
    """

    node: object
    matrix: np.ndarray
    offset: np.ndarray
    inverse: np.ndarray
    factor: float
    negative: bool

    def field(self, points: np.ndarray) -> np.ndarray:
        """Signed distance of the leaf at world `points` ``(n, 3)``."""
        local = (np.asarray(points, dtype=float) - self.offset) @ self.inverse.T
        return self.factor * self.node._evaluate(local)

    def to_world(self, local_points) -> np.ndarray:
        return np.asarray(local_points, dtype=float) @ self.matrix.T + self.offset

    def direction_to_world(self, local_direction) -> np.ndarray:
        d = self.matrix @ np.asarray(local_direction, dtype=float)
        return d / np.linalg.norm(d)


def leaves(solid) -> list[Leaf]:
    """Every leaf of `solid` with its world transform and parity."""
    out = []
    stack = [(solid, np.eye(3), np.zeros(3), False)]
    while stack:
        node, a, t, neg = stack.pop()
        kind = node.kind
        if kind == "affine":
            a2 = a @ node.matrix
            t2 = a @ node.offset_vector + t
            stack.append((node.children[0], a2, t2, neg))
        elif kind in _PASS_THROUGH and node.children:
            kids = node.children
            for i, child in enumerate(kids):
                flips = kind == "complement" or (kind in ("difference", "smooth_difference") and i > 0)
                stack.append((child, a, t, neg ^ flips))
        else:
            sv = np.linalg.svd(a, compute_uv=False)
            out.append(Leaf(node, a, t, np.linalg.inv(a), float(sv[-1]), neg))
    out.reverse()
    return out


@dataclass(frozen=True)
class AxialFeature:
    """A cylinder, cone or torus of the tree, in world coordinates.

    Attributes
    ----------
    kind : str
    centre : (3,) float
        A point of the axis (a cylinder's middle, a cone's base, a torus' centre).
    axis : (3,) float
        Unit axis direction.
    diameter : float
        Cylinder diameter; cone base diameter; torus major diameter.
    length : float
        Extent along the axis (cylinder height, cone height, torus tube diameter).
    start, stop : float
        Axial extent measured from `centre` along `axis`.
    negative : bool
        True when the feature removes material (a hole).
    arc : bool
        Only part of the way round is on the part's boundary: a fillet or a
        round (radius callout), not a hole or a boss.
    mid : (3,) float, optional
        A point of the wall in the middle of the part that is on the boundary.
    depth : float, optional
        A blind hole's depth from the face it leaves (``None``: through, or not a hole).
    """

    kind: str
    centre: np.ndarray
    axis: np.ndarray
    diameter: float
    length: float
    start: float
    stop: float
    negative: bool
    arc: bool = False
    mid: np.ndarray | None = None
    depth: float | None = None


def _scale_along(leaf: Leaf, axis_local) -> tuple[np.ndarray, float]:
    d = leaf.matrix @ np.asarray(axis_local, dtype=float)
    return d / np.linalg.norm(d), float(np.linalg.norm(d))


def axial_features(solid) -> list[AxialFeature]:
    """Cylinders, cones and tori of `solid` (holes and bosses), world coordinates.

    Only leaves whose transform is a similarity (rotation and uniform scale)
    are reported: a sheared cylinder is no longer a cylinder.
    """
    out = []
    for leaf in leaves(solid):
        node = leaf.node
        if node.kind not in ("cylinder", "cone", "torus"):
            continue
        sv = np.linalg.svd(leaf.matrix, compute_uv=False)
        if not np.isclose(sv[0], sv[-1], rtol=1e-9):
            continue
        s = float(sv[0])
        p = node.params
        axis, _ = _scale_along(leaf, p["axis"])
        centre = leaf.to_world(p["center"])
        if node.kind == "cylinder":
            d, length = 2 * p["radius"] * s, p["height"] * s
            start, stop = -length / 2, length / 2
        elif node.kind == "cone":
            d, length = 2 * p["radius"] * s, p["height"] * s
            start, stop = 0.0, length
        else:
            d, length = 2 * p["major_radius"] * s, 2 * p["minor_radius"] * s
            start, stop = -length / 2, length / 2
        out.append(AxialFeature(node.kind, centre, axis, float(d), float(length), start, stop, leaf.negative))
    return out


def rounded_radii(solid) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """(centre, half sizes, edge radius) of the material-adding rounded boxes in
    `solid` (world units; leaves under pure translations and uniform scales only)."""
    out = []
    for leaf in leaves(solid):
        if leaf.node.kind == "box" and leaf.node.params.get("radius") and not leaf.negative:
            m = leaf.matrix
            s = float(abs(np.linalg.det(m))) ** (1 / 3)
            if np.allclose(m, s * np.eye(3), rtol=1e-9, atol=1e-12):
                p = leaf.node.params
                out.append((leaf.to_world(p["center"]), 0.5 * s * np.asarray(p["size"], float), float(p["radius"] * s)))
    return out


def sphere_radii(solid) -> list[tuple[np.ndarray, float]]:
    """(centre, radius) of the material-adding spheres of `solid`."""
    out = []
    for leaf in leaves(solid):
        if leaf.node.kind == "sphere" and not leaf.negative:
            sv = np.linalg.svd(leaf.matrix, compute_uv=False)
            if np.isclose(sv[0], sv[-1], rtol=1e-9):
                out.append((leaf.to_world(leaf.node.params["center"]), float(leaf.node.params["radius"] * sv[0])))
    return out


def nearest_leaf(leaf_list: list[Leaf], points: np.ndarray) -> np.ndarray:
    """Index of the leaf whose surface is nearest each point (``|field|`` smallest)."""
    points = np.asarray(points, dtype=float)
    best = np.full(len(points), np.inf)
    label = np.zeros(len(points), dtype=np.int64)
    # A running minimum, one leaf at a time: memory stays one value per point.
    for i, leaf in enumerate(leaf_list):
        value = np.abs(leaf.field(points))
        closer = value < best
        best[closer] = value[closer]
        label[closer] = i
    return label


def leaf_gradients(leaf_list: list[Leaf], label: np.ndarray, points: np.ndarray, step: float):
    """Field value and unit gradient of leaf ``label[i]`` at ``points[i]``.

    Forward differences of step `step`, evaluated leaf by leaf (one batch
    per leaf, never per point).  Returns ``(values (n,), normals (n, 3))``.
    """
    points = np.asarray(points, dtype=float)
    values = np.zeros(len(points))
    normals = np.zeros((len(points), 3))
    offsets = np.eye(3) * step
    for i in np.unique(label):
        rows = np.flatnonzero(label == i)
        p = points[rows]
        probe = (p[:, None, :] + offsets[None]).reshape(-1, 3)
        f = leaf_list[i].field(np.concatenate([p, probe]))
        values[rows] = f[:len(p)]
        g = (f[len(p):].reshape(-1, 3) - f[:len(p), None]) / step
        norm = np.linalg.norm(g, axis=1, keepdims=True)
        normals[rows] = np.divide(g, norm, out=np.zeros_like(g), where=norm > 0)
    return values, normals
