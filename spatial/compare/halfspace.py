"""Half-space form: a polyhedral solid as a union of disjoint convex pieces.

Where every leaf of a CSG tree is a planar half-space or a convex polyhedron
(box, half-space, convex polyhedron, extruded polygon cut into trapezoids,
under affine maps), the tree is expanded into disjoint convex pieces, each an
intersection of planes ``n . p <= d``: a union is the pieces of both sides
with the first removed from the second, an intersection the pairwise
intersections, and the complement of a convex piece ``p_1 .. p_k`` the
disjoint pieces ``~p_1``, ``p_1 & ~p_2``, ...  Empty pieces are dropped (a
linear program), and each piece's exact volume comes from its vertices
(scipy's `HalfspaceIntersection` and `ConvexHull`).

References
----------
A. Requicha, "Representations for Rigid Solids", ACM Computing Surveys 12(4),
1980, doi:10.1145/356827.356833 (half-spaces as the primitives of CSG).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .leaves import THROUGH, leaf_planes

__all__ = ["HalfSpaceForm", "half_space_form"]

#: Largest number of convex pieces the expansion may reach before it gives up.
MAX_PIECES = 4096


@dataclass(frozen=True)
class HalfSpaceForm:
    """Disjoint convex pieces, each ``(normals (k, 3), offsets (k,))``."""

    pieces: tuple

    @property
    def n_planes(self) -> int:
        return int(sum(len(d) for _, d in self.pieces))

    @property
    def nbytes(self) -> int:
        """Four float64 numbers per plane."""
        return 32 * self.n_planes

    def contains(self, points) -> np.ndarray:
        """Inside or on the boundary, vectorized over points and planes of each piece."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        inside = np.zeros(p.shape[0], dtype=bool)
        for n, d in self.pieces:
            inside |= np.all(p @ n.T <= d + 1e-12, axis=1)
        return inside

    def piece_vertices(self) -> list:
        """Vertices (m, 3) of every piece."""
        from scipy.spatial import HalfspaceIntersection
        out = []
        for n, d in self.pieces:
            centre = _interior_point(n, d)
            hs = HalfspaceIntersection(np.hstack([n, -d[:, None]]), centre)
            out.append(hs.intersections)
        return out

    def volume(self) -> float:
        """Exact volume: the sum of the pieces' convex hull volumes."""
        from scipy.spatial import ConvexHull
        return float(sum(ConvexHull(v).volume for v in self.piece_vertices()))

    def to_dict(self) -> dict:
        return {"pieces": [{"normals": n.tolist(), "offsets": d.tolist()} for n, d in self.pieces]}


def _interior_point(n, d):
    """Chebyshev centre of ``n p <= d`` (None when the piece has no interior)."""
    from scipy.optimize import linprog
    a = np.hstack([n, np.linalg.norm(n, axis=1, keepdims=True)])
    res = linprog(c=[0, 0, 0, -1.0], A_ub=a, b_ub=d, bounds=[(None, None)] * 3 + [(0, None)], method="highs")
    if res.status != 0 or -res.fun <= 1e-9 * max(1.0, float(np.abs(d).max())):
        return None
    return res.x[:3]


def _nonempty(pieces):
    return [(n, d) for n, d in pieces if _interior_point(n, d) is not None]


def _meet(a, b):
    out = [(np.vstack([n1, n2]), np.concatenate([d1, d2])) for n1, d1 in a for n2, d2 in b]
    if len(out) > MAX_PIECES:
        raise ValueError(f"half-space form: more than {MAX_PIECES} convex pieces")
    return _nonempty(out)


def _complement(pieces):
    """Disjoint pieces of the complement of a union of disjoint convex pieces."""
    result = None
    for n, d in pieces:
        comp = []
        for i in range(len(d)):  # ~p_i & p_0 & .. & p_{i-1}
            comp.append((np.vstack([n[:i], -n[i:i + 1]]), np.concatenate([d[:i], -d[i:i + 1]])))
        result = comp if result is None else _meet(result, comp)
    return result if result is not None else [(np.zeros((0, 3)), np.zeros(0))]


def _pieces(node, matrix, offset):
    kind = node.kind
    if kind == "affine":
        a = np.asarray(node.params["matrix"], float)
        t = np.asarray(node.params["offset"], float)
        return _pieces(node.children[0], matrix @ a, matrix @ t + offset)
    if kind in THROUGH and not kind.startswith("smooth"):
        kids = [_pieces(c, matrix, offset) for c in node.children]
        if any(k is None for k in kids):
            return None
        if kind == "family":
            return kids[0]
        if kind == "complement":
            return _complement(kids[0])
        if kind == "intersection":
            out = kids[0]
            for k in kids[1:]:
                out = _meet(out, k)
            return out
        if kind == "difference":
            out = kids[0]
            for k in kids[1:]:
                out = _meet(out, _complement(k))
            return out
        if kind == "union":
            out = kids[0]
            for k in kids[1:]:
                out = out + _meet(k, _complement(out))
            return out
    return leaf_planes(node, matrix, offset)


def half_space_form(solid):
    """The half-space form of `solid`, or None when a leaf is not a planar half-space.

    Examples
    --------
    >>> from implicit import box
    >>> form = half_space_form(box((4, 2, 2)) - box((1, 3, 1), center=(0, 0, 0.5)))
    >>> round(form.volume(), 9)
    14.0
    """
    pieces = _pieces(solid, np.eye(3), np.zeros(3))
    if pieces is None:
        return None
    return HalfSpaceForm(tuple(_nonempty(pieces)))
