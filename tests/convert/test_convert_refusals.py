"""Conversions that would lose or invert material refuse with a clear error."""

import numpy as np
import pytest

import implicit as I
import parametric as P
from implicit.parametric_solids import surface_solid
from spatial.convert.fitting import fit_star_surface, loft_sections


def test_star_fit_of_a_torus_needs_a_centre():
    with pytest.raises(ValueError, match="center: the default centre .* is outside the solid"):
        fit_star_surface(I.torus(2.0, 0.5))
    res = fit_star_surface(I.sphere(1.0), n_control=(8, 6), samples=(24, 13))
    assert np.allclose(res.center, 0.0, atol=1e-9)


def test_loft_refuses_sections_with_holes():
    with pytest.raises(ValueError, match="section z=.* has 1 hole"):
        loft_sections(I.cylinder(1.0, 2.0) - I.cylinder(0.5, 3.0), "z", 3, n_control=12)
    with pytest.raises(ValueError, match="2 separate loops"):
        loft_sections(I.cylinder(0.4, 2.0, center=(-1, 0, 0)) | I.cylinder(0.4, 2.0, center=(1, 0, 0)),
                      "z", 3, n_control=12)
    ok = loft_sections(I.cylinder(1.0, 2.0), "z", 3, n_control=12)
    assert ok.max_deviation < 1e-2


def test_surface_solid_refuses_an_open_surface():
    with pytest.raises(ValueError, match="the surface is open: the boundary v = start of patch 0"):
        surface_solid(P.cylinder(1.0, 2.0))
    ball = surface_solid(P.sphere(2.0))
    assert np.allclose(ball([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]]), [-2.0, 1.0], atol=1e-9)
    ring = surface_solid(P.torus(2.0, 0.5))
    assert np.allclose(ring([[2.0, 0.0, 0.0], [0.0, 0.0, 0.0]]), [-0.5, 1.5], atol=1e-9)
