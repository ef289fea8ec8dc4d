"""The compiled polygon distance gives the vectorized one's numbers."""

import numpy as np

import implicit.profiles as profiles


def test_compiled_polygon_distance_matches_the_vectorized_one(monkeypatch):
    t = np.linspace(0, 2 * np.pi, 120, endpoint=False)
    r = 10 + 2 * np.sign(np.sin(10 * t))  # a castle-like star: concave, 120 edges
    v = np.column_stack([r * np.cos(t), r * np.sin(t)])
    p = np.random.default_rng(1).uniform(-14, 14, (3000, 2))
    fast = profiles.polygon_distance(p, v)
    monkeypatch.setattr(profiles, "POLYGON_KERNEL_EDGES", 10**9)
    slow = profiles.polygon_distance(p, v)
    np.testing.assert_array_equal(fast, slow)
    assert (fast < 0).any() and (fast > 0).any()


def test_the_boxes_passed_over_change_no_figure(monkeypatch):
    """The kernel measures only the edge boxes near a point or across its row: the same bits as all
    edges, on the gear's outline (240 edges, 30 boxes) at its vertices, edge middles, points along
    horizontal rows through vertices (the parity's ties) and far away."""
    import os
    import runpy

    from implicit.polygon_kernel import CHUNK

    gear = runpy.run_path(os.path.join(os.path.dirname(__file__), "..", "..", "examples", "gear.py"))
    v = gear["gear_outline"]()
    assert len(v) > 8 * CHUNK
    rng = np.random.default_rng(2)
    rows = np.column_stack([rng.uniform(-30, 30, len(v)), v[:, 1]])
    p = np.concatenate([v, 0.5 * (v + np.roll(v, -1, axis=0)), rows, rng.uniform(-30, 30, (2000, 2)),
                        v[rng.integers(0, len(v), 2000)] + rng.normal(scale=0.2, size=(2000, 2)),
                        [[1e3, -2e3], [0.0, 0.0]]])
    fast = profiles.polygon_distance(p, v)
    monkeypatch.setattr(profiles, "POLYGON_KERNEL_EDGES", 10**9)
    slow = np.concatenate([profiles.polygon_distance(p[i:i + 500], v) for i in range(0, len(p), 500)])
    np.testing.assert_array_equal(fast, slow)
    assert np.abs(fast[:2 * len(v)]).max() < 1e-12 and fast[-1] < -10.0 and fast[-2] > 2000.0
