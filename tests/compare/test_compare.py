"""Representations compared: the B-rep's Euler-Poincare law, the half-space form, the table, the claims."""

import json
import math

import numpy as np
import pytest

from implicit import box, cylinder, sphere
from implicit.library import channel_section
from spatial.compare import brep, compare, half_space_form
from spatial.compare.ambiguity import BLOCK, ambiguous_solids, wire_matches, wireframe_segments
from spatial.meshing import feature_edges, mesh

BENCH = (sphere(1) & box(1.5)) - cylinder(0.5, 4, axis=(1, 0, 0)) - cylinder(0.5, 4, axis=(0, 1, 0)) \
    - cylinder(0.5, 4, axis=(0, 0, 1))
BENCH_VOLUME = 0.988789504774


@pytest.mark.parametrize("part, F, G, B", [
    (box((2, 2, 1)), 6, 0, 1),
    (box((2, 2, 1)) - cylinder(0.4, 2), 7, 1, 1),
    (BENCH, 13, 5, 1),
    (box(2) - sphere(0.5), 7, 0, 2),            # a cavity: two shells
    (sphere(1), 1, 0, 1),                       # one face, one vertex, no edge
])
def test_brep_counts_and_euler_poincare(part, F, G, B):
    rep = brep(part, mesh(part, resolution=40))
    assert (rep.F, rep.G, rep.B) == (F, G, B)
    lhs, rhs = rep.euler_poincare
    assert lhs == rhs == 2 * (B - G)


def test_brep_of_a_block_with_a_hole_has_the_textbook_counts():
    rep = brep(box((2, 2, 1)) - cylinder(0.4, 2), mesh(box((2, 2, 1)) - cylinder(0.4, 2), resolution=32))
    # 8 corners + one vertex on each circle; 12 + 2 edges; rings: top, bottom and the bore's second loop
    assert (rep.V, rep.E, rep.L) == (10, 14, 3)


def test_half_space_form_is_exact_and_agrees_with_the_tree():
    part = (box((4, 2, 2)) - box((1, 3, 1), center=(0, 0, 0.5))).rotate(20, axis=(1, 1, 0))
    form = half_space_form(part)
    assert form.volume() == pytest.approx(14.0, rel=1e-12)
    pts = np.random.default_rng(1).uniform(-3, 3, size=(20000, 3))
    inside = part(pts)
    sure = np.abs(inside) > 1e-9
    assert np.array_equal(form.contains(pts)[sure], (inside <= 0)[sure])
    assert half_space_form(BENCH) is None


def test_compare_benchmark_part_rows_and_json():
    table = compare(BENCH, resolution=24, reference=BENCH_VOLUME, n_queries=5000, claims=False, progress=False)
    names = [r.name for r in table.rows]
    assert names[0] == "CSG tree" and "wireframe" in names and "OpenVDB level set" in names
    d = json.loads(json.dumps(table.to_dict()))
    for row in d["representations"]:
        assert set(row) >= {"name", "bytes", "build_seconds", "volume", "volume_error", "query_seconds", "answers"}
    csg, rep, wire = table.row("CSG tree"), table.row("B-rep (faces by CSG leaf)"), table.row("wireframe")
    assert csg.volume_error < 5e-3 and rep.volume_error < 5e-2
    # the feature mesh (the default) keeps the edges: what is left is the curved faces' chord error, +1.4e-3
    assert abs(rep.volume - BENCH_VOLUME) < 2e-3 * BENCH_VOLUME
    assert wire.volume is None and "inside/outside" not in wire.answers
    assert rep.details["euler_poincare_holds"] and rep.details["G"] == 5
    lo, hi = table.row("octree cells").details["volume_bounds"]
    assert lo < BENCH_VOLUME < hi
    assert not table.row("half-space form").applies


def test_every_scheme_applies_to_a_polyhedral_family_instance():
    part = channel_section("UPN80", length=120)
    table = compare(part, resolution=24, n_queries=2000, progress=False)
    applies = {r.name for r in table.rows if r.applies}
    assert {"CSG tree", "half-space form", "sweep", "primitive instancing", "analytical (trivariate)", "octree cells",
            "B-rep (faces by CSG leaf)", "wireframe"} <= applies
    exact = table.reference_volume
    assert table.row("analytical (trivariate)").volume == pytest.approx(exact, rel=1e-12)
    p = part.params["params"]
    assert exact == pytest.approx(
        (p["height"] * p["width"] - (p["height"] - 2 * p["flange"]) * (p["width"] - p["web"])) * p["length"])
    inst, csg = table.row("primitive instancing"), table.row("CSG tree")
    assert inst.file_bytes < csg.file_bytes


def test_claims_are_checked_with_figures(tmp_path):
    table = compare(BENCH, resolution=24, reference=BENCH_VOLUME, n_queries=2000, progress=False)
    claims = {c["claim"]: c for c in table.claims}
    storage = claims["B-rep requires more storage than CSG"]
    assert storage["holds"] and storage["ratio"] > 10
    grid = claims["occupancy grids trade memory for simplicity"]
    sweep = grid["sweep"]
    assert [r["bytes_bool"] for r in sweep] == [(n + 2) ** 3 for n in (8, 16, 32, 64)] or \
        all(b > a for a, b in zip([r["bytes_bool"] for r in sweep], [r["bytes_bool"] for r in sweep][1:]))
    assert claims["a wireframe cannot tell inside from outside"]["holds"]
    table.chart(tmp_path / "chart.png")
    assert (tmp_path / "chart.png").stat().st_size > 10_000
    assert "| claim (seed) |" in table.markdown()


def test_three_solids_share_one_wireframe_and_differ_in_volume():
    solids = ambiguous_solids()
    ref = wireframe_segments()
    h = max(BLOCK) / 40
    volumes = []
    for name, solid in solids.items():
        m = mesh(solid, resolution=40)
        rep = brep(solid, m)
        out, cover = wire_matches(rep.edge_segments, ref, h)
        assert out < 1.5 * h, name       # every edge found lies on the shared wireframe
        assert cover < 1.5 * h, name     # and the whole wireframe is found
        assert rep.holds and rep.G == 1
        volumes.append(float(m.volume))
    assert min(abs(a - b) for i, a in enumerate(volumes) for b in volumes[i + 1:]) > 0.5
    # the meshing room's sharp feature curves find the same wireframe in all three
    counts = set()
    for name, solid in solids.items():
        curves = feature_edges(mesh(solid, resolution=40, features=True))
        seg = np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in curves.polylines])
        out, cover = wire_matches(seg, ref, h)
        assert out < 1.5 * h and cover < 1.5 * h, name
        counts.add(len(curves.polylines))
    assert len(counts) == 1
    # a wireframe from another solid (no hole) does not match
    block = box(BLOCK)
    out, cover = wire_matches(brep(block, mesh(block, resolution=40)).edge_segments, ref, h)
    assert cover > 0.3


@pytest.mark.parametrize("kwargs, message", [
    ({"resolution": 4}, "resolution: expected an integer in"),
    ({"n_queries": 3}, "n_queries"),
    ({"reference": -1.0}, "reference: expected a positive volume"),
])
def test_compare_refuses_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        compare(BENCH, **kwargs)
    with pytest.raises(TypeError, match="solid: expected an implicit.Solid"):
        compare("part.py")


def test_fitted_patches_of_a_star_shaped_part_hold_its_volume():
    table = compare(sphere(1.0), resolution=16, reference=4 * math.pi / 3, n_queries=1000, claims=False,
                    progress=False)
    patches = table.row("B-spline patches")
    assert patches.applies and patches.volume_error < 1e-6
    rounded = compare(sphere(1.0) & box(1.6), resolution=16, n_queries=1000, claims=False, progress=False)
    assert rounded.row("B-spline patches").volume_error < 1e-2
    assert not compare(BENCH, resolution=16, n_queries=1000, claims=False, progress=False).row(
        "B-spline patches").applies  # the holes pass through its centre: not star-shaped
