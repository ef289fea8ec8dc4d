"""Radius-edge repair at the boundary: nodes of a bad element's boundary sides slid on the surface.

An element whose three corners lie on one boundary triangle has a radius-edge
ratio at least that triangle's own (its circumsphere holds the triangle's
circumcircle, its shortest edge is at most the triangle's): moving interior
nodes cannot bring it under the bound.  The sliver pass may leave such an
element where sliding a node traded a worse one for it (the hole plate of
tests/fea/test_size_field.py at seed 0: 3.095).  Here each slidable node of
such an element's boundary sides tries a fan of positions in its tangent
plane, projected onto the true surface, and takes the one that raises the
worst margin of the elements around it to the bounds `tet_mesh` checks
(dihedral angles, radius-edge ratio), never folding one of its boundary
triangles.
"""

from __future__ import annotations

import numpy as np

from .facets import project_to_surface
from .incidence import node_cells
from .quality import dihedral_angles, radius_edge_ratio, tet_volumes
from .slivers import boundary_faces

__all__ = ["slide_boundary_nodes", "DIRECTIONS", "STEPS"]

#: Directions tried in the tangent plane of a node, and the steps along each, as fractions of the
#: shortest edge at the node.
DIRECTIONS = 16
STEPS = (0.03, 0.07, 0.15, 0.25, 0.4)
#: Sweeps over the elements still over the bound.
SWEEPS = 4


def _ratio_over(points, tets, radius_edge):
    return np.flatnonzero(radius_edge_ratio(points, tets[:, :4]) > radius_edge)


def _slack(points, tets, min_dihedral, max_dihedral, radius_edge, per=1):
    """The worst relative margin to the bounds `tet_mesh` checks (negative: one is missed) of `tets`,
    or ``(per,)`` of `per` equal groups of them."""
    ang = dihedral_angles(points, tets)
    margin = np.minimum.reduce([(ang.min(axis=1) - min_dihedral) / min_dihedral,
                                (max_dihedral - ang.max(axis=1)) / max_dihedral,
                                (radius_edge - radius_edge_ratio(points, tets)) / radius_edge])
    worst = margin.reshape(per, -1).min(axis=1)
    return float(worst[0]) if per == 1 else worst


def slide_boundary_nodes(points, tets, solid, slide, min_dihedral, max_dihedral, radius_edge, *, sweeps=SWEEPS):
    """Points with the slidable boundary nodes (`slide`, ``(n,)`` bool) of the elements over
    `radius_edge` moved on `solid`'s surface where that raises the worst margin to the bounds around them.

    Returns the new points ``(n, 3)`` and the number of moves.

    Examples
    --------
    >>> from implicit import box
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0.05, 0], [0.5, 0.5, -0.8]], dtype=float)
    >>> tets = np.array([[0, 2, 1, 3]])                      # a skinny triangle on the face z = 0
    >>> slide = np.array([False, False, True, False])
    >>> q, moves = slide_boundary_nodes(p, tets, box((4.0, 4.0, 2.0), center=(0, 0, -1)), slide, 10.0, 165.0, 3.0)
    >>> moves > 0, bool(q[2, 1] > 0.05), float(q[2, 2])
    (True, True, 0.0)
    """
    pts = np.array(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64)
    slide = np.zeros(len(pts), dtype=bool) if slide is None else np.asarray(slide, dtype=bool)
    if slide.size < len(pts):               # points the sliver pass inserted stay
        slide = np.concatenate([slide, np.zeros(len(pts) - slide.size, dtype=bool)])
    corners = tets[:, :4]
    order, starts = node_cells(corners, len(pts))
    bfaces, _, _ = boundary_faces(corners)
    on_b = np.zeros(len(pts), dtype=bool)
    on_b[bfaces.reshape(-1)] = True
    angle = 2.0 * np.pi * np.arange(DIRECTIONS) / DIRECTIONS
    moves = 0
    for _ in range(sweeps):
        bad = _ratio_over(pts, corners, radius_edge)
        if bad.size == 0:
            break
        moved = False
        for v in np.unique(corners[bad].reshape(-1)):
            if not (slide[v] and on_b[v]):
                continue
            around = order[starts[v]:starts[v + 1]] // 4
            local = corners[around]
            now = _slack(pts, local, min_dihedral, max_dihedral, radius_edge)
            # the boundary triangles at v, and their normals now
            tri = bfaces[(bfaces == v).any(axis=1)]
            n0 = np.cross(pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]])
            g = solid.gradient(pts[v][None])[0]
            g /= max(np.linalg.norm(g), 1e-300)
            u = np.cross(g, [1.0, 0.0, 0.0] if abs(g[0]) < 0.9 else [0.0, 1.0, 0.0])
            u /= np.linalg.norm(u)
            w = np.cross(g, u)
            shortest = np.linalg.norm(pts[local[:, [1, 2, 3, 2, 3, 3]]] - pts[local[:, [0, 0, 0, 1, 1, 2]]], axis=2).min()
            dirs = np.cos(angle)[:, None] * u + np.sin(angle)[:, None] * w
            cand = (pts[v] + shortest * np.array(STEPS)[:, None, None] * dirs[None]).reshape(-1, 3)
            cand = project_to_surface(solid, cand, max_move=shortest)
            # All candidates at once: the elements and boundary triangles around v with v at each.
            c = len(cand)
            xe = np.broadcast_to(pts[local], (c,) + local.shape + (3,)).copy()      # (c, k, 4, 3)
            xe[:, local == v] = cand[:, None]
            xt = np.broadcast_to(pts[tri], (c,) + tri.shape + (3,)).copy()          # (c, b, 3, 3)
            xt[:, tri == v] = cand[:, None]
            n1 = np.cross(xt[:, :, 1] - xt[:, :, 0], xt[:, :, 2] - xt[:, :, 0])
            flat_pts = xe.reshape(-1, 3)
            flat_tets = np.arange(len(flat_pts)).reshape(-1, 4)
            ok = (np.einsum("cbj,bj->cb", n1, n0) > 0).all(axis=1)
            ok &= (tet_volumes(flat_pts, flat_tets).reshape(c, -1) > 0).all(axis=1)
            score = _slack(flat_pts, flat_tets, min_dihedral, max_dihedral, radius_edge, per=c)
            score[~ok] = -np.inf
            pick = int(np.argmax(score))
            best = cand[pick] if score[pick] > now + 1e-9 else None
            if best is not None:
                pts[v] = best
                moves += 1
                moved = True
        if not moved:
            break
    return pts, moves
