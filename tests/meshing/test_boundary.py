"""Boundary meshes: closed, 2-manifold, outward, right topology, vertices on the surface."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from implicit import box, cylinder, halfspace, sphere, torus
from spatial import mesh
from spatial.meshing.blocks import mesh_block

from meshcheck import min_area, signed_volume, topology, vertex_manifold
from solid_strategies import solids as random_solids

#: Refined vertices lie this close to the surface, in voxels.
REFINED_TOL = 2e-3
#: Interpolated (unrefined) vertices stay within this many voxels of the surface.
UNREFINED_TOL = 0.2


def benchmark_part():
    return (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
        - cylinder(0.5, 4, axis=(0, 0, 1))


# name, solid, resolution, Euler characteristic, exact volume
PARTS = [
    ("sphere", sphere(1.0, center=(0.1, -0.2, 0.3)), 32, 2, 4 / 3 * math.pi),
    ("torus", torus(1.0, 0.35), 48, 0, 2 * math.pi ** 2 * 1.0 * 0.35 ** 2),
    ("box", box((1.0, 0.7, 0.5)), 32, 2, 0.35),
    ("cylinder", cylinder(0.5, 1.5, axis=(1, 1, 0)), 40, 2, math.pi * 0.25 * 1.5),
    ("benchmark", benchmark_part(), 64, -8, 0.988789504774),
    # a difference whose tool shares a face with the base: the shared face carries no area
    ("touching", box(1.0) - box((0.5, 1.0, 0.5), center=(0.25, 0.0, 0.25)), 32, 2, 1.0 - 0.25),
]


@pytest.fixture(scope="module", params=PARTS, ids=[p[0] for p in PARTS])
def meshed(request):
    name, solid, n, euler, volume = request.param
    # the plain path (features=False): vertices refined along lattice edges; the feature path has test_features
    return name, solid, mesh(solid, resolution=n, features=False), euler, volume


def test_closed_manifold_oriented(meshed):
    name, solid, m, euler, volume = meshed
    topo = topology(m)
    assert topo["edge_counts"] == {2}, name
    assert topo["oriented"], name
    assert topo["degenerate"] == 0 and topo["duplicates"] == 0
    assert vertex_manifold(m), name
    assert topo["euler"] == euler
    assert min_area(m) > 0


def test_outward_and_volume(meshed):
    name, solid, m, euler, volume = meshed
    h = float(m.field_data["voxel_size"][0])
    v = signed_volume(m)
    assert v > 0
    # second-order accuracy; sharp edges are cut by about h^2/2 per unit length
    assert abs(v - volume) < 0.03 * volume, (name, v, volume)
    # outward normals: a point pushed outward along each face normal is outside
    faces = m.faces.reshape(-1, 4)[:, 1:]
    p = np.asarray(m.points)
    n = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    big = np.linalg.norm(n, axis=1) > 1e-3 * h * h
    c = p[faces[big]].mean(axis=1)
    u = n[big] / np.linalg.norm(n[big], axis=1, keepdims=True)
    outside = solid(c + 0.3 * h * u) > solid(c - 0.3 * h * u)
    assert outside.mean() > 0.97


def test_vertices_refined_onto_surface(meshed):
    name, solid, m, *_ = meshed
    h = float(m.field_data["voxel_size"][0])
    assert np.abs(solid(m.points)).max() < REFINED_TOL * h


def test_field_data_and_surface_cost():
    m = mesh(sphere(1.0), resolution=32)
    assert m.field_data["voxel_size"][0] == pytest.approx(2.0 / 32)
    evals = int(m.field_data["evaluations"][0])
    assert 0 < evals < 35 ** 3
    # cost follows the surface: doubling N multiplies it by about 4, not 8
    finer = int(mesh(sphere(1.0), resolution=64).field_data["evaluations"][0])
    assert 3.0 < finer / evals < 4.5


def test_unrefined_vertices_interpolated():
    s = sphere(1.0)
    m = mesh(s, resolution=32, refine=False)
    h = 2.0 / 32
    err = np.abs(s(m.points))
    assert err.max() < UNREFINED_TOL * h
    assert err.max() > REFINED_TOL * h  # refinement does something
    assert topology(m)["euler"] == 2


def test_faces_on_sample_planes_leave_no_hole():
    # box(1) at resolution 32: h = 1/32, the faces x, y, z = +-0.5 lie exactly on lattice nodes
    s = box(1.0)
    m = mesh(s, resolution=32, refine=False)
    h = 1.0 / 32
    nodes = (np.array([-0.5, 0.5]) - (-17 * h)) / h
    assert np.allclose(nodes, np.round(nodes))
    assert np.any(s(np.array([[0.5, 0.0, 0.0]])) == 0.0)
    topo = topology(m)
    assert topo["edge_counts"] == {2} and topo["euler"] == 2
    assert signed_volume(m) == pytest.approx(1.0, rel=0.02)


@pytest.mark.parametrize("small", [2, 6, 8])
def test_blocks_merge_independently_of_block_size(small):
    s = torus(1.0, 0.3)
    a = mesh(s, resolution=40, block=small)
    b = mesh(s, resolution=40, block=64)
    assert a.n_cells == b.n_cells and a.n_points == b.n_points
    assert int(a.field_data["blocks"][0]) > int(b.field_data["blocks"][0])
    assert np.allclose(np.sort(a.points, axis=0), np.sort(b.points, axis=0))
    assert topology(a)["edge_counts"] == {2}


def test_empty_solid_and_no_boundary_warn():
    empty = sphere(1.0) & sphere(1.0, center=(5, 0, 0))
    with pytest.warns(RuntimeWarning, match="empty"):
        m = mesh(empty, resolution=16)
    assert m.n_cells == 0
    with pytest.warns(RuntimeWarning, match="no boundary"):
        m = mesh(sphere(1.0), resolution=8, bounds=((5, 5, 5), (6, 6, 6)))
    assert m.n_cells == 0 and m.field_data["evaluations"][0] > 0
    # a solid filling the region is clipped to it: a closed cube of volume 8 minus the cut edges
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = mesh(sphere(10.0), resolution=16, bounds=((-1, -1, -1), (1, 1, 1)), features=False)
        sharp = mesh(sphere(10.0), resolution=16, bounds=((-1, -1, -1), (1, 1, 1)))
    assert topology(m)["euler"] == 2 and topology(sharp)["euler"] == 2
    assert signed_volume(m) == pytest.approx(8.0 - 24 * (2 / 16) ** 2 / 2, rel=0.01)
    # by default the clipping box's edges are rebuilt too
    assert signed_volume(sharp) == pytest.approx(8.0, rel=1e-3)


def test_clipped_to_bounds_stays_closed():
    m = mesh(halfspace((0, 0, 1)), resolution=16, bounds=((-1, -1, -1), (1, 1, 0)), features=False)
    topo = topology(m)
    assert topo["edge_counts"] == {2} and topo["euler"] == 2
    # the box's 12 edges (total length 20) lose a triangle of legs h each: h^2/2 per unit length
    h = 2.0 / 16
    assert signed_volume(m) == pytest.approx(4.0 - 20 * h * h / 2, rel=0.01)


def test_bad_arguments():
    with pytest.raises(ValueError, match="exactly one of voxel_size"):
        mesh(sphere(1.0), voxel_size=0.1, resolution=10)
    with pytest.raises(TypeError, match="resolution"):
        mesh(sphere(1.0), resolution=10.5)
    with pytest.raises(ValueError, match="voxel_size"):
        mesh(sphere(1.0), voxel_size=-1.0)
    with pytest.raises(TypeError, match="Solid"):
        mesh("sphere", resolution=8)
    with pytest.raises(ValueError, match="unbounded"):
        mesh(halfspace((0, 0, 1)), resolution=8)
    with pytest.raises(ValueError, match="bounds"):
        mesh(halfspace((0, 0, 1)))  # the default voxel needs finite bounds
    with pytest.raises(ValueError, match="bounds"):
        mesh(sphere(1.0), resolution=8, bounds=((0, 0, 0), (0, 1, 1)))
    with pytest.raises(ValueError, match="block"):
        mesh(sphere(1.0), resolution=8, block=1)


def test_mesh_block_is_pure_and_keys_edges():
    # a plane x = 1.25 through a 3x3x3-node block: 4 voxels, 8 triangles, 9 vertices on x-edges
    x = np.arange(3, dtype=np.float32)
    vals = np.broadcast_to((x - 1.25)[:, None, None], (3, 3, 3)).copy()
    mask = np.zeros((3, 3, 3), bool)
    mask[2, 1:, 1:] = True  # voxels with lower node (1, j, k)
    first = mesh_block(vals, mask)
    again = mesh_block(vals.copy(), mask.copy())
    assert all(np.array_equal(u, v) for u, v in zip(first, again))
    node, axis, f0, f1, faces = first
    assert faces.shape == (8, 3) and node.shape == (9, 3)
    assert set(axis.tolist()) == {0} and set(node[:, 0].tolist()) == {1}
    assert np.allclose(f0, -0.25) and np.allclose(f1, 0.75)
    assert len({tuple(r) for r in node.tolist()}) == 9
    # no sign change: nothing, no error
    assert mesh_block(np.ones((3, 3, 3), np.float32), mask)[4].shape == (0, 3)


# ---------------------------------------------------------------------------
# sampling: signs inferred instead of sampled never change the mesh
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("solid, n", [(benchmark_part(), 64), (torus(1.0, 0.35), 48),
                                      (box(1.0) - sphere(0.6, center=(0.5, 0.5, 0.5)), 40)],
                         ids=["benchmark", "torus", "box-sphere"])
def test_inferred_signs_give_the_fully_sampled_mesh(solid, n):
    from spatial.meshing.boundary import _boundary_cells_2h, mesh_cells
    from spatial.cells.lattice import make_lattice

    lattice = make_lattice(solid, resolution=n)
    found = _boundary_cells_2h(lattice, False)
    assert found["uniform"] is not None and found["nodes"] is not None
    lean = mesh(solid, resolution=n, refine=False, features=False)
    # every node of every boundary cell sampled: no centre values, no uniform cells, no known nodes
    full = mesh_cells(solid, lattice.origin, lattice.voxel_size, found["cells"], cell_size=2, refine=False,
                      features=False)
    assert lean.n_cells == full.n_cells and lean.n_points == full.n_points
    assert np.allclose(np.sort(lean.points, axis=0), np.sort(full.points, axis=0), atol=1e-12)
    assert lean.field_data["evaluations"][0] < full.field_data["evaluations"][0] + found["evaluations"]


def test_benchmark_part_evaluation_budget():
    # the budget of 6 M evaluations at N=512 is 375 k at N=128 (the cost follows the surface)
    coarse = int(mesh(benchmark_part(), resolution=128).field_data["evaluations"][0])
    finer = int(mesh(benchmark_part(), resolution=256).field_data["evaluations"][0])
    assert coarse < 6e6 / 16
    assert finer / coarse < 4.5


def test_certified_vertices_skip_refinement():
    from spatial.meshing.refine import REFINE_ACCEPT, _certified

    h = 0.1
    f0 = np.array([-0.03, -0.03, -0.0001, -0.05], np.float32)
    f1 = np.array([0.07, 0.06, 0.0999, 0.05], np.float32)
    # square-on crossing (|f0| + |f1| = h): certified; slanted: not; a nudged end: not trusted
    got = _certified(f0, f1, h, 1.0)
    assert got.tolist() == [True, False, False, True]
    # a looser Lipschitz constant widens the bracket
    assert not _certified(f0[:1], f1[:1], h, 1.0 + 2 * REFINE_ACCEPT)[0]


@settings(max_examples=40, deadline=None, derandomize=True)
@given(shape=st.lists(st.integers(1, 5), min_size=1, max_size=4), axis=st.integers(0, 3),
       dtype=st.sampled_from([np.bool_, np.int8, np.uint8]))
def test_repeat2_is_numpy_repeat(shape, axis, dtype):
    from spatial.meshing.arrays import _repeat2

    axis = axis % len(shape)
    arr = (np.arange(int(np.prod(shape))).reshape(shape) % 3 - 1).astype(dtype)
    assert np.array_equal(_repeat2(arr, axis), np.repeat(arr, 2, axis=axis))
    assert np.array_equal(_repeat2(arr, -1), np.repeat(arr, 2, axis=-1))


def _lean_and_full(solid, n):
    """The mesh as `mesh` builds it, and the one from every node of the same boundary cells sampled."""
    from spatial.meshing.boundary import _boundary_cells_2h, mesh_cells
    from spatial.cells.lattice import make_lattice

    lattice = make_lattice(solid, resolution=n)
    found = _boundary_cells_2h(lattice, False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        lean = mesh(solid, resolution=n, refine=False, features=False)
        full = mesh_cells(solid, lattice.origin, lattice.voxel_size, found["cells"], cell_size=2, refine=False,
                      features=False)
    return lean, full


@settings(derandomize=True, max_examples=20, deadline=None)
@given(solid=random_solids(), n=st.sampled_from([20, 27, 34]),
       warp=st.sampled_from(["none", "scale", "smooth", "offset"]))
def test_inferred_signs_law_on_random_solids(solid, n, warp):
    from implicit import offset, scale, smooth_union

    # fields whose Lipschitz constant is not 1 or that are bounds rather than distances
    if warp == "scale":
        solid = scale(solid, (1.0, 0.55, 1.3))
    elif warp == "smooth":
        solid = smooth_union(solid, sphere(0.4, center=(0.6, 0.0, 0.0)), blend=0.3)
    elif warp == "offset":
        solid = offset(solid, 0.05)
    lean, full = _lean_and_full(solid, n)
    assert lean.n_cells == full.n_cells and lean.n_points == full.n_points
    if lean.n_points:
        assert np.allclose(np.sort(lean.points, axis=0), np.sort(full.points, axis=0), atol=1e-12)
        assert topology(lean)["edge_counts"] == {2}


def test_part_families_get_the_lean_sampling_too():
    from implicit import instance

    part = instance("hole_plate")
    lean, full = _lean_and_full(part, 40)
    assert lean.n_cells == full.n_cells > 0
    assert np.allclose(np.sort(lean.points, axis=0), np.sort(full.points, axis=0), atol=1e-12)
    assert lean.field_data["evaluations"][0] < 0.8 * full.field_data["evaluations"][0]


def test_slabs_prepared_on_a_worker_thread_give_the_same_mesh(monkeypatch):
    """`run_slabs(overlap=True)` (the next slab sampled while marching cubes runs) makes the parts
    and evaluations the serial order makes."""
    import spatial.meshing.cells as cells_mod
    from spatial.meshing.slab import run_slabs

    part = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0))
    monkeypatch.setattr(cells_mod, "run_slabs", lambda tasks, parts, overlap=False: run_slabs(tasks, parts))
    serial = mesh(part, resolution=40, block=8, progress=False, features=False)
    monkeypatch.setattr(cells_mod, "run_slabs", lambda tasks, parts, overlap=False: run_slabs(tasks, parts,
                                                                                              overlap=True))
    threaded = mesh(part, resolution=40, block=8, progress=False, features=False)
    assert np.array_equal(np.asarray(serial.points), np.asarray(threaded.points))
    assert np.array_equal(np.asarray(serial.faces), np.asarray(threaded.faces))
    assert serial.field_data["evaluations"][0] == threaded.field_data["evaluations"][0]


def test_refine_tolerances_shrink_with_the_voxel(monkeypatch):
    """Past REFINE_FULL_N voxels across the solid the stop tolerances beside ties fall as h (the distance
    left as h^2); the other vertices keep theirs."""
    from spatial.cells.lattice import make_lattice
    from spatial.meshing import cells
    from spatial.meshing.arrays import REFINE_ACCEPT, REFINE_FULL_N, REFINE_TOL, refine_scale
    from spatial.meshing.boundary import _boundary_cells_2h

    assert refine_scale(sphere(1.0), 2.0 / 64) == 1.0
    assert refine_scale(sphere(1.0), 2.0 / 512) == pytest.approx(REFINE_FULL_N / 512)
    assert refine_scale(halfspace((0, 0, 1)), 1e-6) == 1.0        # unbounded: as before
    seen = []
    real = cells._refine_on_edges

    def spy(*args, **kwargs):
        seen.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(cells, "_refine_on_edges", spy)
    # a patch of a large sphere (16 voxels across a region 1/200 of the solid's size), meshed with the
    # sphere itself (`mesh` would clip it to the region, whose size would then count)
    big = sphere(100.0)
    lattice = make_lattice(big, bounds=((99.5, -0.5, -0.5), (100.5, 0.5, 0.5)), resolution=16)
    found = _boundary_cells_2h(lattice, False)
    cells.mesh_cells(big, lattice.origin, lattice.voxel_size, found["cells"], cell_size=2, features=False)
    s = REFINE_FULL_N * lattice.voxel_size / 200.0
    assert s < 0.05
    assert len(seen) == 2 and "tol" not in seen[1] and "accept" not in seen[1]
    assert seen[0]["tol"] == pytest.approx(REFINE_TOL * s) and seen[0]["accept"] == pytest.approx(REFINE_ACCEPT * s)
