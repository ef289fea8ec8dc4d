"""The feature pass on a part of hundreds of primitives evaluates the few near each point, not all of them."""

import pytest

from implicit import capsule
from implicit.facets import FacetField
from spatial.meshing import mesh
from parts import capsule_lattice


@pytest.fixture
def facet_work(monkeypatch):
    """Counts, during `FacetField`'s queries only, the points asked about and the points at which a
    capsule's field is evaluated."""
    seen = {"asked": 0, "capsule": 0, "active": False}
    kind = type(capsule((0, 0, 0), (1, 0, 0), 0.1))
    evaluate = kind._evaluate

    def counted(self, p):
        if seen["active"]:
            seen["capsule"] += len(p)
        return evaluate(self, p)

    monkeypatch.setattr(kind, "_evaluate", counted)
    for name in ("decide", "values_of", "facet_values", "gradients_of"):
        method = getattr(FacetField, name, None)
        if method is None:
            continue

        def query(self, points, *args, _method=method, **kwargs):
            seen["asked"] += len(points)
            seen["active"] = True
            try:
                return _method(self, points, *args, **kwargs)
            finally:
                seen["active"] = False

        monkeypatch.setattr(FacetField, name, query)
    return seen


def test_lattice_of_300_capsules_meshes_with_features_by_the_capsules_near_each_point(facet_work):
    solid, n_caps = capsule_lattice(4)
    assert n_caps == 300
    m = mesh(solid, resolution=56, progress=False)
    assert int(m.field_data["feature_cells"][0]) > 0           # the pass did rebuild edges
    assert facet_work["asked"] > 1000
    per_point = facet_work["capsule"] / facet_work["asked"]
    # walking the whole tree at every point costs all 300 capsules a point for the deciding facet
    # (and as many again for the Gauss-Newton's facet values)
    assert per_point < 40, per_point
