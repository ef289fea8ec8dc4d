"""`tet_mesh`'s volume check without a reference volume: the solid's volume measured on its feature
meshes (the finest one the surface starts from), against the solid, not the mesh's boundary."""

import numpy as np
import pytest
import pyvista as pv

import spatial.fea.tetmesh as tetmesh
from implicit import box, cylinder, sphere
from spatial.analysis.mass import ToleranceError
from spatial.analysis.mass_solid import level_moments, solid_volume, volume_on_finest
from spatial.fea.surface import surface_for_fea
from spatial.fea.tetmesh import ESTIMATE_SHARE, MeshQualityError, tet_mesh
from spatial.meshing.arrays import faces_array
from spatial.meshing.boundary import mesh

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
BENCH_VOLUME = 0.988789504774


def _feature(solid, h):
    return mesh(solid, voxel_size=h, features=True, progress=False)


def test_volume_on_the_surfaces_feature_mesh_meets_its_tolerance():
    h = 0.02  # the voxel of the benchmark part's surface at size 0.08
    finest = _feature(BENCH, h)
    v, err = solid_volume(BENCH, tolerance=1e-3, finest=finest, voxel_size=h)
    # the finest level is the mesh given, thin-shell corrected
    pts, tri = faces_array(finest)
    c0 = 0.5 * (np.asarray(BENCH.bounds[0]) + np.asarray(BENCH.bounds[1]))
    assert v == level_moments(BENCH, pts, tri, c0, voxel_size=h, area=False)[0]
    assert 2e-5 <= err <= 1e-3
    # the estimate holds the true error (-7.9e-6 here), and is no tighter than the levels' spread says
    assert abs(v - BENCH_VOLUME) <= err * BENCH_VOLUME
    assert abs(v - BENCH_VOLUME) / BENCH_VOLUME < 2e-5


def test_a_wrong_finest_mesh_is_caught_by_the_coarser_levels():
    h = 0.02
    bad = _feature(BENCH, h).scale(1.01, inplace=False)  # 3 % too much volume
    v, err = solid_volume(BENCH, tolerance=1e-3, finest=bad, voxel_size=h)
    # The coarser levels disagree with it: the estimate misses the tolerance, the levels are measured anew.
    assert abs(v - BENCH_VOLUME) / BENCH_VOLUME < 1e-3 and err <= 1e-3


def test_the_finest_mesh_is_skipped_where_its_coarsest_level_would_lose_the_thinnest_wall():
    beam = box((100, 10, 10), center=(50, 0, 0))
    # voxel 2.5: the coarsest level (10) would be as thick as the beam; the levels chosen for the tolerance
    bad = _feature(beam, 2.5).scale(1.05, inplace=False)
    v, err = solid_volume(beam, tolerance=1e-3, finest=bad, voxel_size=2.5)
    assert abs(v - 1e4) / 1e4 < 1e-4 and err <= 1e-3


def test_solid_volume_refuses_bad_options():
    with pytest.raises(ValueError, match="tolerance"):
        solid_volume(BENCH, tolerance=0.0)
    with pytest.raises(ValueError, match="tolerance"):
        volume_on_finest(BENCH, pv.Sphere(), 0.1, tolerance=-1.0)
    with pytest.raises(ValueError, match="tolerance"):
        solid_volume(BENCH, tolerance=1.5)
    with pytest.raises(ValueError, match="voxel_size"):
        solid_volume(BENCH, tolerance=1e-3, finest=pv.Sphere())


def test_the_mass_properties_at_128_cells_where_the_tolerance_cannot_be_met(monkeypatch):
    import spatial.analysis.mass_solid as mass_solid

    def unreachable(solid, **kw):
        raise ToleranceError("not reached", tolerance=kw["tolerance"], estimate=1.0, cells=512)

    monkeypatch.setattr(mass_solid, "solid_volume", unreachable)
    v, err = tetmesh._solid_volume(BENCH, None, 0.005)
    assert v == pytest.approx(BENCH_VOLUME, rel=1e-4) and 0 < err < 1e-4  # 3.6e-5 at 32, 64, 128 cells


def _spy(monkeypatch, module, name):
    calls = []
    real = getattr(module, name)

    def spy(solid, finest, voxel_size, **kw):
        got = real(solid, finest, voxel_size, **kw)
        calls.append((finest.n_cells, voxel_size, got is not None))
        return got

    monkeypatch.setattr(module, name, spy)
    return calls


def test_tet_mesh_measures_the_volume_on_the_surfaces_feature_mesh_alone(monkeypatch):
    import spatial.analysis.mass_shell as mass_shell
    import spatial.analysis.mass_solid as mass_solid

    one = _spy(monkeypatch, mass_shell, "volume_on_one_level")
    three = _spy(monkeypatch, mass_solid, "volume_on_finest")
    monkeypatch.setattr(tetmesh, "_solid_volume", None)  # no levels of its own
    for size in (0.1, 0.15):  # (at 0.15 the three levels' coarsest, 10 cells across, missed by 1 %)
        m = tet_mesh(BENCH, size=size)
        assert one[-1][0] > 4000 and one[-1][1:] == (size / 4, True)
        assert m.info["volume_estimate"] == pytest.approx(BENCH_VOLUME, rel=1e-4)
        assert abs(m.info["volume_estimate"] - BENCH_VOLUME) <= m.info["volume_estimate_error"] * BENCH_VOLUME
        assert 0 < m.info["volume_estimate_error"] <= ESTIMATE_SHARE * 0.005
        assert m.info["volume_error"] < 0.005
    assert len(one) == 2 and three == []  # no coarser level meshed


def test_tet_mesh_takes_the_coarser_levels_where_the_feature_mesh_alone_cannot_vouch(monkeypatch):
    import spatial.analysis.mass_shell as mass_shell
    import spatial.analysis.mass_solid as mass_solid

    monkeypatch.setattr(mass_shell, "volume_on_one_level", lambda *a, **kw: None)
    three = _spy(monkeypatch, mass_solid, "volume_on_finest")
    monkeypatch.setattr(tetmesh, "_solid_volume", None)
    m = tet_mesh(BENCH, size=0.1)
    assert len(three) == 1 and three[0][0] > 10000 and three[0][1:] == (0.1 / 4, True)
    assert m.info["volume_estimate"] == pytest.approx(BENCH_VOLUME, rel=1e-4)
    assert 0 < m.info["volume_estimate_error"] <= ESTIMATE_SHARE * 0.005


def test_tet_mesh_measures_levels_of_its_own_where_the_feature_mesh_cannot_serve():
    # the beam at size 10: the surface's voxel 2.5, its coarsest level 10 as thick as the beam
    beam = box((100, 10, 10), center=(50, 0, 0))
    m = tet_mesh(beam, size=10.0)
    assert m.info["volume_estimate"] == pytest.approx(1e4, rel=1e-4)
    assert 0 < m.info["volume_estimate_error"] <= ESTIMATE_SHARE * 0.005


def test_a_surface_that_misses_the_solid_is_refused_though_the_volume_comes_from_its_feature_mesh(monkeypatch):
    # The surface shrunk by 1 % (3 % of the volume) after it was made from the right feature mesh.
    real = tetmesh.surface_for_fea

    def shrunk(solid, **kw):
        s = real(solid, **kw)
        out = s.scale(0.99, inplace=False)
        out.field_data.update(dict(s.field_data))
        return out

    monkeypatch.setattr(tetmesh, "surface_for_fea", shrunk)
    with pytest.raises(MeshQualityError, match="differs from the solid's 0.988"):
        tet_mesh(BENCH, size=0.15)


def test_a_given_surface_of_another_solid_is_refused():
    ball = sphere(1.0)
    right = tet_mesh(ball, size=0.25, surface=surface_for_fea(ball, size=0.25), volume_tolerance=0.03)
    assert right.info["volume_estimate"] == pytest.approx(4 / 3 * np.pi, rel=1e-3)
    small = surface_for_fea(sphere(0.98), size=0.25)  # 5.9 % less volume
    with pytest.raises(MeshQualityError, match="differs from the solid's 4.18"):
        tet_mesh(ball, size=0.25, surface=small, volume_tolerance=0.03)
