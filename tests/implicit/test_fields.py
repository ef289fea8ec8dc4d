"""GridSolid: a solid backed by sampled distances."""

import json

import numpy as np
import pytest

from implicit import sphere
from implicit.fields import GridSolid
from implicit.solid import Solid
from spatial import Octree


def _sphere_grid(h=0.1, r=1.0, half=1.5):
    x = np.arange(-half, half + h / 2, h)
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    return GridSolid(np.sqrt(X ** 2 + Y ** 2 + Z ** 2) - r, origin=(-half,) * 3, voxel_size=h)


def test_reproduces_samples_and_linear_fields():
    g = _sphere_grid()
    idx = np.array([[0, 0, 0], [10, 15, 20], [30, 30, 30]])
    pts = g.origin + idx * g.voxel_size
    assert np.allclose(g(pts), g.distance[idx[:, 0], idx[:, 1], idx[:, 2]], atol=1e-12)
    # trilinear interpolation is exact for a linear field
    n = np.array([0.3, -0.5, 0.8])
    x = np.arange(6) * 0.2
    lin = np.einsum("i,ijkl->jkl", n, np.stack(np.meshgrid(x, x, x, indexing="ij"))) - 0.4
    solid = GridSolid(lin, voxel_size=0.2)
    p = np.random.default_rng(1).random((50, 3))
    assert np.allclose(solid(p), p @ n - 0.4)


def test_outside_the_grid_is_a_conservative_distance():
    g = _sphere_grid()
    rng = np.random.default_rng(2)
    d = rng.normal(size=(200, 3))
    p = d / np.linalg.norm(d, axis=1, keepdims=True) * rng.uniform(1.6, 5.0, (200, 1))
    values = g(p)
    true = np.linalg.norm(p, axis=1) - 1.0
    assert np.all(values > 0)
    # never above the true distance, up to the interpolation error on the box (convex field: ~h^2)
    assert np.all(values <= true + 0.1 ** 2)
    assert np.all(values >= 0.5 * true)


def test_lipschitz_and_value_bounds_are_conservative():
    g = _sphere_grid(h=0.15)
    assert g.lipschitz >= np.sqrt(3.0) * 0.99  # the data's slopes are about 1 per unit
    rng = np.random.default_rng(3)
    p = rng.uniform(-2.5, 2.5, (500, 3))
    q = p + rng.normal(scale=0.1, size=(500, 3))
    assert np.all(np.abs(g(p) - g(q)) <= g.lipschitz * np.linalg.norm(p - q, axis=1) + 1e-12)
    lo = rng.uniform(-2, 2, (100, 3))
    hi = lo + rng.uniform(0.01, 0.5, (100, 3))
    vmin, vmax = g.value_bounds(lo, hi)
    inside = lo[:, None, :] + rng.random((100, 20, 3)) * (hi - lo)[:, None, :]
    v = g(inside)
    assert np.all(v >= vmin[:, None] - 1e-12) and np.all(v <= vmax[:, None] + 1e-12)


def test_bounds_hold_the_interior_and_octree_works():
    g = _sphere_grid()
    lo, hi = g.bounds
    assert np.all(lo <= -0.9) and np.all(hi >= 0.9) and np.all(lo >= -1.5) and np.all(hi <= 1.5)
    tree = Octree.from_solid(g, resolution=16)
    vlo, vhi = tree.volume_bounds()
    assert vlo < 4 / 3 * np.pi < vhi
    # a grid-backed solid joins CSG trees
    both = g - sphere(0.5)
    assert both([[0.0, 0.0, 0.0]])[0] == pytest.approx(0.5, abs=0.02)
    empty = GridSolid(np.ones((3, 3, 3)))
    assert empty.is_empty_bounds


def test_params_round_trip_through_json():
    g = _sphere_grid(h=0.3)
    params = json.loads(json.dumps(g.to_params()))
    back = Solid.registry["grid"].from_params((), params)
    p = np.random.default_rng(4).uniform(-2, 2, (40, 3))
    assert np.allclose(back(p), g(p), atol=1e-6)
    with pytest.raises(ValueError, match="data"):
        GridSolid.from_params((), g.params)


def test_bad_input():
    with pytest.raises(ValueError, match="at least 2 samples"):
        GridSolid(np.zeros((1, 3, 3)))
    with pytest.raises(ValueError, match="3-d"):
        GridSolid(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="finite"):
        GridSolid(np.full((2, 2, 2), np.nan))
    with pytest.raises(TypeError, match="3-d array of numbers"):
        GridSolid("abc")
    with pytest.raises(ValueError, match="voxel_size"):
        GridSolid(np.zeros((2, 2, 2)), voxel_size=-1)
