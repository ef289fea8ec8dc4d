"""FEA meshes: surfaces fit for meshing, tetrahedra, boundary sets, files, `implicad fea`."""

from __future__ import annotations

import warnings

import meshio
import numpy as np
import pytest
import pyvista as pv
from hypothesis import given, settings, strategies as st
from skimage.measure import marching_cubes

from implicit import box, cylinder, sphere, torus
from spatial.fea.files import FEA_FORMATS, set_name, write_fea
from spatial.fea.surface import FacetField, project_to_surface, self_intersections, surface_for_fea, surface_quality
from spatial.fea.quality import dihedral_angles, radius_edge_ratio, scaled_jacobian, tet_quality, tet_volumes
from spatial.fea.tetmesh import SIDE_NODES, MeshQualityError, MeshQualityWarning, tet_mesh

#: Quality every mesh must reach (degrees), and volume agreement with closed forms.
MIN_DIHEDRAL = 10.0
MAX_DIHEDRAL = 165.0
VOLUME_RTOL = 0.005

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
BENCH_VOLUME = 0.988789504774
BOX_HOLE = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0)
BOX_HOLE_VOLUME = 2.0 * 1.0 * 0.5 - np.pi * 0.25**2 * 0.5


def mc_mesh(solid, n=96):
    """A raw marching-cubes surface of `solid` (slivers included), outward."""
    lo, hi = solid.bounds
    pad = 0.05 * float(np.max(hi - lo))
    lo, hi = lo - pad, hi + pad
    h = float(np.max(hi - lo)) / n
    axes = [np.arange(lo[i], hi[i] + h, h) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    # The node's own numpy evaluation: no compiled fast path to build for a test grid.
    values = solid._evaluate(np.ascontiguousarray(grid.reshape(-1, 3))).reshape(grid.shape[:-1])
    verts, faces, _, _ = marching_cubes(values, 0.0, spacing=(h, h, h))
    return pv.PolyData.from_regular_faces(verts + lo, faces)


@pytest.fixture(scope="module")
def bench_surface():
    # Meshed by spatial.mesh (voxel size / 4), then remeshed.
    return surface_for_fea(BENCH, size=0.08)


@pytest.fixture(scope="module")
def bench_tets(bench_surface):
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshQualityWarning)
        return tet_mesh(BENCH, size=0.08, surface=bench_surface)


# --------------------------------------------------------------------------- quality measures

REGULAR = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)


def test_regular_tetrahedron_measures():
    tet = [[0, 1, 3, 2]]
    assert tet_volumes(REGULAR, tet)[0] == pytest.approx(8.0 / 3.0)
    np.testing.assert_allclose(dihedral_angles(REGULAR, tet), np.degrees(np.arccos(1 / 3)), rtol=1e-12)
    assert radius_edge_ratio(REGULAR, tet)[0] == pytest.approx(np.sqrt(6) / 4)
    assert scaled_jacobian(REGULAR, tet)[0] == pytest.approx(1.0)
    # The same element inverted.
    assert scaled_jacobian(REGULAR, [[0, 1, 2, 3]])[0] == pytest.approx(-1.0)


def test_quadratic_volume_of_a_straight_element_is_its_corner_volume():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    e = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    pts = np.concatenate([p, 0.5 * (p[e[:, 0]] + p[e[:, 1]])])
    assert tet_volumes(pts, [np.arange(10)])[0] == pytest.approx(1 / 6, rel=1e-14)
    assert scaled_jacobian(pts, [np.arange(10)])[0] == pytest.approx(scaled_jacobian(p, [[0, 1, 2, 3]])[0])
    # Moving the mid node of edge 01 out of the side y = 0 by d adds d * integral of the
    # bubble 4 L0 L1 over that side = d * 4 * (1/2) / 12 = d / 6 (exactly: det J is linear in y).
    bulged = pts.copy()
    bulged[4, 1] = -0.1
    assert tet_volumes(bulged, [np.arange(10)])[0] == pytest.approx(1 / 6 + 0.1 / 6, rel=1e-13)


def test_right_corner_tetrahedron_dihedrals():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    d = np.sort(dihedral_angles(p, [[0, 1, 2, 3]])[0])
    expected = np.sort([90, 90, 90] + [np.degrees(np.arccos(1 / np.sqrt(3)))] * 3)
    np.testing.assert_allclose(d, expected, atol=1e-10)


@settings(derandomize=True, max_examples=25, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=12, max_size=12))
def test_dihedral_angles_are_invariant_under_rigid_motion(coords):
    p = np.array(coords).reshape(4, 3)
    if abs(tet_volumes(p, [[0, 1, 2, 3]])[0]) < 1e-3:
        return
    rot = np.linalg.qr(np.array([[0.3, -1.2, 0.5], [0.9, 0.1, -0.4], [0.2, 0.7, 1.1]]))[0]
    q = p @ rot.T + [3.0, -2.0, 5.0]
    np.testing.assert_allclose(dihedral_angles(p, [[0, 1, 2, 3]]), dihedral_angles(q, [[0, 1, 2, 3]]), atol=1e-7)
    assert dihedral_angles(p, [[0, 1, 2, 3]]).sum() > 360.0 - 1e-9  # six angles sum to more than 2 pi


def test_tet_quality_rejects_bad_shapes():
    with pytest.raises(ValueError, match="tets: expected shape"):
        tet_quality(REGULAR, [[0, 1, 2]])
    with pytest.raises(ValueError, match="points: expected shape"):
        tet_quality(REGULAR[:, :2], [[0, 1, 2, 3]])


# --------------------------------------------------------------------------- CSG facets

def test_facets_name_the_deciding_face():
    ff = FacetField(BOX_HOLE)
    _, dec, _ = ff([[0.25, 0.0, 0.0], [1.0, 0.2, 0.0], [0.5, 0.0, 0.25], [0.5, -0.5, 0.0]])
    assert [ff.names[i] for i in dec] == ["cylinder_1.wall", "box_0.+x", "box_0.+z", "box_0.-y"]


def test_facets_follow_transforms():
    part = BOX_HOLE.translate((5.0, 0.0, 0.0)).rotate(90, axis=(0, 0, 1))
    ff = FacetField(part)
    value, dec, _ = ff([[0.0, 5.25, 0.0]])
    assert ff.names[dec[0]] == "cylinder_1.wall"
    assert value[0] == pytest.approx(float(part([[0.0, 5.25, 0.0]])[0]), abs=1e-12)


def test_projection_lands_on_the_surface():
    rng = np.random.default_rng(1)
    p = rng.normal(size=(200, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    q = project_to_surface(sphere(1.0), p * rng.uniform(0.8, 1.2, size=(200, 1)))
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)


# --------------------------------------------------------------------------- surfaces

def test_surface_for_fea_removes_slivers_of_marching_cubes():
    raw = mc_mesh(sphere(1.0), 40)
    assert surface_quality(raw).min_angle < 2.0  # the raw surface has slivers
    s = surface_for_fea(raw, size=0.15, solid=sphere(1.0))
    q = surface_quality(s, sphere(1.0))
    assert q.closed and s.is_manifold
    assert q.min_angle > 25.0
    # Vertices on the sphere; face centres within the chord error e^2 / (6 R) of it
    # (edges up to about 1.4 h long).
    assert np.abs(sphere(1.0)(s.points)).max() < 1e-9
    assert q.max_deviation < (1.4 * 0.15)**2 / 6
    assert s.volume > 0  # outward
    assert abs(q.mean_edge - 0.15) < 0.04
    assert self_intersections(s) == 0


def test_surface_of_the_benchmark_part_keeps_sharp_edges(bench_surface):
    q = surface_quality(bench_surface, BENCH)
    assert q.closed and self_intersections(bench_surface) == 0
    assert q.min_angle > 10.0
    assert int(bench_surface.field_data["snapped_vertices"][0]) > 200
    # Face centres stay within a few chord errors of the true surface, sharp edges included.
    assert q.max_deviation < 0.005
    assert bench_surface.volume == pytest.approx(BENCH_VOLUME, rel=0.01)


def test_surface_keeps_box_corners_and_hole_rims():
    s = surface_for_fea(BOX_HOLE, size=0.08)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-0.5, 0.5) for z in (-0.25, 0.25)])
    gap = np.linalg.norm(s.points[None] - corners[:, None], axis=2).min(axis=1)
    np.testing.assert_allclose(gap, 0.0, atol=1e-9)
    # Vertices on the rims of the hole: radius 0.25 at z = +-0.25, about 2 pi 0.25 / 0.08 of each.
    p = s.points
    rim = (np.abs(np.hypot(p[:, 0], p[:, 1]) - 0.25) < 1e-9) & (np.abs(np.abs(p[:, 2]) - 0.25) < 1e-9)
    assert rim.sum() >= 2 * 12


def test_surface_for_fea_of_a_bare_mesh():
    raw = pv.Sphere(radius=2.0, theta_resolution=80, phi_resolution=80)
    s = surface_for_fea(raw, size=0.4)
    q = surface_quality(s)
    assert q.closed and q.min_angle > 20.0 and s.volume > 0
    assert "max_deviation" not in s.field_data
    # Without a solid the points stay on the input surface (pyacvd moves them there).
    np.testing.assert_allclose(np.linalg.norm(s.points, axis=1), 2.0, atol=0.01)


def test_self_intersections_are_detected():
    a = pv.Sphere(radius=1.0).triangulate()
    b = pv.Sphere(radius=1.0, center=(0.5, 0, 0)).triangulate()
    assert self_intersections(a.merge(b)) > 0


def test_surface_for_fea_checks_arguments():
    with pytest.raises(TypeError, match="solid_or_mesh: expected a Solid or a pyvista.PolyData"):
        surface_for_fea([1, 2, 3], size=0.1)
    with pytest.raises(ValueError, match="size: expected a positive number"):
        surface_for_fea(pv.Sphere(), size=-1.0)
    with pytest.raises(ValueError, match="max_deviation: needs the solid"):
        surface_for_fea(pv.Sphere(), size=0.1, max_deviation=0.01)
    with pytest.raises(ValueError, match="max_deviation: the remeshed surface deviates"):
        surface_for_fea(pv.Sphere(radius=1.0), size=0.4, solid=sphere(1.0), max_deviation=1e-6)


# --------------------------------------------------------------------------- tetrahedra

def test_benchmark_part_tet_mesh_meets_the_targets(bench_tets):
    q = bench_tets.quality
    assert q.min_dihedral >= MIN_DIHEDRAL and q.max_dihedral <= MAX_DIHEDRAL
    assert np.all(scaled_jacobian(bench_tets.points, bench_tets.tets) > 0)
    assert bench_tets.volume == pytest.approx(BENCH_VOLUME, rel=VOLUME_RTOL)
    assert bench_tets.info["volume_error"] < VOLUME_RTOL


def test_boundary_sets_name_the_csg_faces(bench_tets):
    names = set(bench_tets.face_sets)
    assert {"surface", "sphere_0", "box_1.+x", "box_1.-z", "cylinder_2.wall", "cylinder_3.wall",
            "cylinder_4.wall"} <= names
    # The regions partition the boundary.
    parts = np.concatenate([v for k, v in bench_tets.face_sets.items() if k != "surface"])
    assert np.array_equal(np.sort(parts), np.arange(len(bench_tets.boundary)))
    # Nodes of the hole along x lie on its wall (y^2 + z^2 = 0.25), but for the odd
    # triangle that bridges a sharp edge no vertex of which could be snapped onto it.
    r = np.hypot(*bench_tets.points[bench_tets.node_sets["cylinder_2.wall"]][:, 1:].T)
    assert np.mean(np.abs(r - 0.5) < 1e-7) > 0.99
    assert np.abs(r - 0.5).max() < 0.5 * 0.08
    # The +x face set is on the plane x = 0.75.
    x = bench_tets.points[bench_tets.node_sets["box_1.+x"]][:, 0]
    assert np.mean(np.abs(x - 0.75) < 1e-7) > 0.99
    assert np.abs(x - 0.75).max() < 0.5 * 0.08


def test_element_sides_are_the_boundary_triangles(bench_tets):
    m = bench_tets
    sides = m.tets[m.boundary_element[:, None], SIDE_NODES[m.boundary_side]]
    np.testing.assert_array_equal(sides, m.boundary)
    # Outward: the enclosed volume of the boundary triangles is the mesh volume.
    a, b, c = (m.points[m.boundary[:, i]] for i in range(3))
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6 == pytest.approx(m.volume, rel=1e-10)


def test_quadratic_tets_put_boundary_midnodes_on_the_surface():
    s = torus(1.0, 0.4)
    raw = pv.ParametricTorus(ringradius=1.0, crosssectionradius=0.4, u_res=120, v_res=60, w_res=0)
    surf = surface_for_fea(raw.triangulate().clean(), size=0.12, solid=s)
    m = tet_mesh(s, size=0.12, surface=surf, order=2, volume_tolerance=0.05)
    assert m.tets.shape[1] == 10
    boundary_nodes = np.unique(np.concatenate([m.node_sets["surface"]]))
    assert np.abs(s(m.points[boundary_nodes])).max() < 1e-8
    assert np.all(scaled_jacobian(m.points, m.tets) > 0)
    # Curved elements hold the torus volume far better than their straight corners.
    exact = 2 * np.pi**2 * 1.0 * 0.4**2
    linear = tet_volumes(m.points, m.tets[:, :4]).sum()
    assert abs(m.volume - exact) < abs(linear - exact) / 5
    assert m.volume == pytest.approx(exact, rel=2e-3)
    # Interior mid nodes stay near their edge midpoints (they follow the curved boundary a little).
    mids = m.tets[:, 4:]
    ends = m.tets[:, [0, 1, 0, 0, 1, 2]], m.tets[:, [1, 2, 2, 3, 3, 3]]
    straight = 0.5 * (m.points[ends[0]] + m.points[ends[1]])
    interior = ~np.isin(mids, boundary_nodes)
    off = np.linalg.norm(m.points[mids][interior] - straight[interior], axis=1)
    assert off.max() < 0.1 * 0.12


def test_box_with_hole_mesh_volume():
    surf = surface_for_fea(mc_mesh(BOX_HOLE, 96), size=0.08, solid=BOX_HOLE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshQualityWarning)
        m = tet_mesh(BOX_HOLE, size=0.08, surface=surf)
    assert m.volume == pytest.approx(BOX_HOLE_VOLUME, rel=VOLUME_RTOL)
    assert m.quality.min_dihedral >= MIN_DIHEDRAL and m.quality.max_dihedral <= MAX_DIHEDRAL


def test_steiner_cap_is_reported():
    surf = pv.Icosphere(radius=1.0, nsub=3)
    with pytest.warns(MeshQualityWarning, match="Steiner-point cap"):
        tet_mesh(sphere(1.0), size=0.1, surface=surf, steiner_cap=10, volume_tolerance=0.1, allow_poor=True)
    with pytest.raises(MeshQualityError, match="Steiner-point cap"):
        tet_mesh(sphere(1.0), size=0.1, surface=surf, steiner_cap=10, volume_tolerance=0.1)


def test_tet_mesh_checks_arguments():
    with pytest.raises(TypeError, match="solid: expected a Solid"):
        tet_mesh("sphere", size=0.1)
    with pytest.raises(ValueError, match="order: expected 1 or 2"):
        tet_mesh(sphere(1.0), size=0.1, order=3)
    with pytest.raises(ValueError, match="radius_edge: expected a ratio > 1"):
        tet_mesh(sphere(1.0), size=0.1, radius_edge=0.9)
    with pytest.raises(ValueError, match="min_dihedral: expected degrees"):
        tet_mesh(sphere(1.0), size=0.1, min_dihedral=80)
    with pytest.raises(ValueError, match="solid: expected a bounded"):
        tet_mesh(~sphere(1.0), size=0.1)
    # Surfaces TetGen would abort on are refused first.
    a = pv.Sphere(radius=1.0).triangulate()
    b = pv.Sphere(radius=1.0, center=(0.5, 0, 0)).triangulate()
    with pytest.raises(ValueError, match="surface: [0-9]+ triangles intersect others"):
        tet_mesh(sphere(1.0), size=0.3, surface=a.merge(b))
    with pytest.raises(ValueError, match="surface: expected a closed, manifold"):
        tet_mesh(sphere(1.0), size=0.3, surface=a.clip())


# --------------------------------------------------------------------------- files

def _in_original_order(points, cells, original):
    """Renumber `cells` to the node numbers of `original`, matching coordinates (Gmsh 4
    groups nodes by entity); every node must be found within 1e-9."""
    assert points.shape == original.shape
    if np.allclose(points, original, rtol=0, atol=1e-9):
        return cells
    o1, o2 = np.lexsort(np.round(points, 7).T[::-1]), np.lexsort(np.round(original, 7).T[::-1])
    np.testing.assert_allclose(points[o1], original[o2], rtol=0, atol=1e-9)
    perm = np.empty(len(points), dtype=np.int64)
    perm[o1] = o2
    return perm[cells]

@pytest.mark.parametrize("name,version", [("m.msh", "4.1"), ("m.msh", "2.2"), ("m.inp", "4.1"),
                                          ("m.vtu", "4.1"), ("m.bdf", "4.1")])
def test_files_read_back(tmp_path, bench_tets, name, version):
    path = tmp_path / name
    write_fea(bench_tets, path, format_version=version)
    back = meshio.read(path)
    tets = [c.data for c in back.cells if c.type == "tetra"]
    assert len(tets) == 1
    np.testing.assert_array_equal(_in_original_order(back.points, tets[0], bench_tets.points), bench_tets.tets)
    if name.endswith(".inp"):
        assert "CYLINDER_2_WALL" in back.point_sets
        np.testing.assert_array_equal(np.sort(back.point_sets["CYLINDER_2_WALL"]),
                                      bench_tets.node_sets["cylinder_2.wall"])
        text = path.read_text()
        assert "*SURFACE, NAME=CYLINDER_2_WALL_F, TYPE=ELEMENT" in text
        assert "*ELEMENT, TYPE=C3D4, ELSET=EALL" in text
    if name.endswith(".msh"):
        assert "cylinder_2.wall" in back.field_data
        tri = [c.data for c in back.cells if c.type == "triangle"]
        assert sum(len(t) for t in tri) == len(bench_tets.boundary)
        # Each physical group holds its region's triangles.
        tag = back.field_data["cylinder_2.wall"][0]
        phys = np.concatenate([p for c, p in zip(back.cells, back.cell_data["gmsh:physical"]) if c.type == "triangle"])
        assert np.sum(phys == tag) == len(bench_tets.face_sets["cylinder_2.wall"])
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no temporary left behind


def test_quadratic_file_round_trip(tmp_path):
    s = sphere(1.0)
    surf = surface_for_fea(mc_mesh(s, 48), size=0.35, solid=s)
    m = tet_mesh(s, size=0.35, surface=surf, order=2, volume_tolerance=0.1)
    for name in ("q.inp", "q.msh", "q.bdf", "q.vtu"):
        write_fea(m, tmp_path / name)
        back = meshio.read(tmp_path / name)
        tets = [c.data for c in back.cells if c.type == "tetra10"]
        np.testing.assert_array_equal(_in_original_order(back.points, tets[0], m.points), m.tets, err_msg=name)


def test_surface_formats_and_bad_extension(tmp_path, bench_tets):
    write_fea(bench_tets, tmp_path / "b.stl")
    surf = pv.read(tmp_path / "b.stl")
    assert surf.n_cells == len(bench_tets.boundary)
    write_fea(bench_tets, tmp_path / "b.ply")
    ply = pv.read(tmp_path / "b.ply")
    assert ply.n_cells == len(bench_tets.boundary) and ply.n_points == len(np.unique(bench_tets.boundary))
    assert ply.volume == pytest.approx(bench_tets.volume, rel=1e-6)  # float32 coordinates
    (tmp_path / "b.ply").unlink()
    with pytest.raises(ValueError, match=r"unknown extension '\.xyz'; expected one of \.msh"):
        write_fea(bench_tets, tmp_path / "b.xyz")
    with pytest.raises(TypeError, match="mesh: expected a TetMesh"):
        write_fea(surf, tmp_path / "b.msh")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.stl"]
    assert set(FEA_FORMATS) >= {".msh", ".inp", ".vtu", ".bdf", ".stl", ".ply"}


# --------------------------------------------------------------------------- command line

def test_cli_unknown_extension_fails_before_work(tmp_path, capsys):
    from spatial.cli import main

    status = main(["fea", str(tmp_path / "missing.py"), "-o", str(tmp_path / "x.step"), "--size", "0.1"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith("implicad: error: output: unknown extension '.step'; expected one of .msh")
    assert len(err.strip().splitlines()) == 1


def test_cli_meshes_a_model(tmp_path, capsys):
    pytest.importorskip("spatial.meshing")
    from spatial.cli import main

    model = tmp_path / "ball.py"
    model.write_text("from implicit import sphere\nsolid = sphere(1.0)\n")
    out = tmp_path / "ball.inp"
    # Flat 4-node elements at size 0.3 miss 3.6 % of the ball: refused, nothing written.
    status = main(["fea", str(model), "-o", str(out), "--size", "0.3", "--no-progress"])
    err = capsys.readouterr().err
    assert status == 1 and not out.exists() and list(tmp_path.iterdir()) == [model]
    assert "differs from the solid's 4.18" in err and "nothing written" in err
    status = main(["fea", str(model), "-o", str(out), "--size", "0.3", "--no-progress", "--allow-poor"])
    captured = capsys.readouterr()
    text = captured.out
    assert "warning: mesh volume" in captured.err
    assert status == 0 and out.exists()
    assert "min dihedral (deg)" in text and "sphere_0 -> SPHERE_0" in text
    back = meshio.read(out)
    assert back.cells[0].type == "tetra"


def test_cli_quadratic_gmsh22_without_a_terminal(tmp_path, capsys):
    pytest.importorskip("spatial.meshing")
    from spatial.cli import main

    model = tmp_path / "ring.py"
    model.write_text("from implicit import torus\nsolid = torus(1.0, 0.35)\n")
    out = tmp_path / "ring.msh"
    status = main(["fea", str(model), "-o", str(out), "--size", "0.2", "--order", "2", "--format-version", "2.2"])
    captured = capsys.readouterr()
    assert status == 0
    assert "fea:" not in captured.err  # no progress bar off a terminal
    assert "(order 2)" in captured.out
    assert out.read_text().startswith("$MeshFormat\n2.2")
    back = meshio.read(out)
    assert [c.type for c in back.cells][:1] == ["tetra10"]
    assert "torus_0" in back.field_data


def test_cli_rejects_a_bad_size(tmp_path, capsys):
    from spatial.cli import main

    assert main(["fea", "model.py", "-o", str(tmp_path / "m.inp"), "--size", "-1"]) == 2
    assert "--size: expected a positive length" in capsys.readouterr().err
