"""The FEA surface is remeshed finer when it misses the solid's volume or intersects itself."""

import pyvista as pv
import pytest

import spatial.fea.tetmesh as tetmesh
from implicit import box


def _fake_surfaces(monkeypatch, by_size):
    """`surface_for_fea` replaced by cubes whose edge depends on the size asked (None: it intersects itself)."""
    asked = []

    def fake(solid, *, size, feature_mesh=None):
        asked.append(size)
        edge = by_size(size)
        if edge is None:
            raise ValueError("size: the remeshed surface has 4 self-intersecting triangles")
        return pv.Cube(x_length=edge, y_length=edge, z_length=edge).triangulate()

    monkeypatch.setattr(tetmesh, "surface_for_fea", fake)
    return asked


def test_a_surface_missing_the_volume_is_remeshed_finer(monkeypatch):
    # at the asked size the surface encloses 0.9^3 = 73 % of the unit cube; at 0.8 of it, all
    asked = _fake_surfaces(monkeypatch, lambda s: 0.9 if s > 0.9 else 1.0)
    surface, size, known = tetmesh._surface_for(box(1.0), 1.0, (1.0, 0.0), 0.005, 1)
    assert size == pytest.approx(0.8) and known == (1.0, 0.0)
    assert asked == pytest.approx([1.0, 0.8])
    assert abs(surface.volume) == pytest.approx(1.0)


def test_without_a_volume_the_solids_is_measured_and_counts(monkeypatch):
    # 0.9^3 of the measured volume at every size free of intersections: all sizes tried, the last kept
    asked = _fake_surfaces(monkeypatch, lambda s: None if s > 0.9 else 0.9)
    _, size, (volume, err) = tetmesh._surface_for(box(1.0), 1.0, (None, 0.0), 0.005, 1)
    assert size == pytest.approx(tetmesh.SURFACE_RETRIES[-1]) and len(asked) == len(tetmesh.SURFACE_RETRIES)
    assert volume == pytest.approx(1.0, rel=1e-4) and 0 < err <= tetmesh.ESTIMATE_SHARE * 0.005


def test_order_2_allows_twice_the_miss(monkeypatch):
    # 0.998^3 = 99.4 % of the volume: missed by order 1's 0.5 %, within order 2's 1 %
    for order, size in ((1, 0.8), (2, 1.0)):
        _fake_surfaces(monkeypatch, lambda s: 0.998 if s > 0.9 else 1.0)
        assert tetmesh._surface_for(box(1.0), 1.0, (1.0, 0.0), 0.005, order)[1] == pytest.approx(size)


def test_the_last_surface_free_of_intersections_is_kept_when_none_has_the_volume(monkeypatch):
    # every surface misses the volume: the mesh's own volume check reports it later
    asked = _fake_surfaces(monkeypatch, lambda s: None if s > 0.9 else 0.5)
    surface, size, _ = tetmesh._surface_for(box(1.0), 1.0, (1.0, 0.0), 0.005, 1)
    assert size == pytest.approx(tetmesh.SURFACE_RETRIES[-1])
    assert len(asked) == len(tetmesh.SURFACE_RETRIES)
    assert abs(surface.volume) == pytest.approx(0.125)


def test_intersecting_at_every_size_raises(monkeypatch):
    _fake_surfaces(monkeypatch, lambda s: None)
    with pytest.raises(ValueError, match="self-intersecting"):
        tetmesh._surface_for(box(1.0), 1.0, (1.0, 0.0), 0.005, 1)
