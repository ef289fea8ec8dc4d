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
