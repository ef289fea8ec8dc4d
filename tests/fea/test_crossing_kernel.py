"""The compiled proof that a surface crosses nowhere never hides a crossing pymeshfix counts."""

import numpy as np
import pymeshfix
import pytest
import pyvista as pv

from implicit import box, cylinder, sphere
from spatial.fea.crossing_kernel import surely_apart
from spatial.fea.surface import mesh_faces, self_intersections, surface_for_fea

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))


def _pymeshfix(points, faces):
    tm = pymeshfix.PyTMesh()
    tm.set_quiet(True)
    tm.load_array(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int32))
    return len(tm.select_intersecting_triangles(justproper=True))


def _apart(points, faces):
    return surely_apart(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int64))


@pytest.fixture(scope="module")
def bench_surface():
    s = surface_for_fea(BENCH, size=0.15)
    return np.asarray(s.points, dtype=np.float64), mesh_faces(s)


def test_fea_surfaces_and_flat_faces_are_proved_apart(bench_surface):
    assert _apart(*bench_surface) and _pymeshfix(*bench_surface) == 0
    cube = pv.Cube().triangulate().subdivide(2)  # coplanar neighbours on every face
    assert _apart(np.asarray(cube.points), mesh_faces(cube))


def test_random_moves_never_pass_a_crossing(bench_surface):
    points, faces = bench_surface
    rng = np.random.default_rng(7)
    proved = crossed = 0
    for _ in range(150):
        q = points.copy()
        idx = rng.choice(len(q), size=int(rng.integers(1, 4)), replace=False)
        q[idx] += rng.normal(scale=float(rng.choice([0.01, 0.05, 0.15])), size=(len(idx), 3))
        count = _pymeshfix(q, faces)
        if _apart(q, faces):
            proved += 1
            assert count == 0
        crossed += count > 0
    # both kinds occur, or the test would show nothing
    assert proved > 50 and crossed > 10


def test_touching_folded_and_crossing_pairs_go_to_pymeshfix():
    # two triangles sharing an edge, the second folded back onto the first (coplanar overlap)
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, 0.2, 0]], dtype=float)
    assert not _apart(p, [[0, 1, 2], [1, 0, 3]])
    # the same edge, the fourth vertex across it or lifted off the plane: apart
    assert _apart(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, -0.5, 0]], dtype=float), [[0, 1, 2], [1, 0, 3]])
    assert _apart(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, 0.2, 0.3]], dtype=float), [[0, 1, 2], [1, 0, 3]])
    # a shared vertex, the second triangle's far edge through the first
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, -0.5], [0.3, 0.3, 0.5]], dtype=float)
    assert not _apart(p, [[0, 1, 2], [0, 3, 4]])
    # a vertex of one exactly on the other (touching): not proved
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 0], [0.2, 0.2, 1], [1, 1, 1]], dtype=float)
    assert not _apart(p, [[0, 1, 2], [3, 4, 5]])
    # well apart
    assert _apart(p + np.array([[0, 0, 0]] * 3 + [[0, 0, 0.01]] * 3), [[0, 1, 2], [3, 4, 5]])
    # non-finite points: not proved
    assert not _apart(np.array([[0, 0, 0], [1, 0, 0], [0, np.nan, 0], [5, 5, 5]], dtype=float), [[0, 1, 2], [1, 3, 2]])


def test_self_intersections_still_counts_what_crosses():
    ball = pv.Sphere(theta_resolution=24, phi_resolution=24).triangulate()
    two = ball.merge(ball.translate((0.3, 0.0, 0.0)))
    assert self_intersections(two) == _pymeshfix(np.asarray(two.points), mesh_faces(two)) > 0
    assert self_intersections(ball) == 0
