"""Bad arguments of curves and patches raise errors that name the argument."""

import numpy as np
import pytest

import parametric as P


def test_conics_name_the_argument():
    with pytest.raises(ValueError, match="^a must be a finite"):
        P.parabola(np.nan)
    with pytest.raises(ValueError, match="x_range"):
        P.parabola(1.0, (0.0, np.inf))
    with pytest.raises(ValueError, match="a and b must be > 0 and finite"):
        P.ellipse(np.inf, 2)
    with pytest.raises(ValueError, match="start_angle"):
        P.arc(1, np.nan, 1)
    with pytest.raises(ValueError, match="radius"):
        P.arc(np.inf, 0.0, 1)
    with pytest.raises(ValueError, match="need a, b > 0"):
        P.hyperbola(1.0, 1.0, (0.0, np.nan))


def test_refine_knots_nan():
    c = P.BSpline(np.array([[0, 0], [1, 1], [2, 0], [3, 1]], float), 3)
    with pytest.raises(ValueError, match="new_knots must be finite"):
        c.refine_knots([np.nan])
    # a good refinement still leaves the curve unchanged
    r = c.refine_knots([0.25, 0.5])
    u = np.linspace(0, 1, 11)
    assert np.allclose(r(u), c(u), atol=1e-13)


def test_interpolate_repeated_points():
    q = np.array([[0, 0], [1, 1], [1, 1], [2, 0], [3, 1]], float)
    with pytest.raises(ValueError, match="consecutive points 1 and 2 coincide"):
        P.interpolate_curve(q, 3)
    c = P.interpolate_curve(np.delete(q, 2, axis=0), 3)
    assert np.allclose(c(P.parametrize(np.delete(q, 2, axis=0))), np.delete(q, 2, axis=0))


def test_end_multiplicity_above_degree_plus_one():
    with pytest.raises(ValueError, match="repeats 5 times; at most degree \\+ 1 = 4"):
        P.validate_knots([0, 0, 0, 0, 0, 0.5, 1, 1, 1], 3, 5)
    assert P.validate_knots([0, 0, 0, 0, 0.5, 1, 1, 1, 1], 3, 5)[4] == 0.5


def _grid():
    g = np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij"), -1)
    return np.concatenate([g, g[..., :1] * g[..., 1:]], -1)


def test_bicubic_refuses_nan_and_close_parameters():
    g = _grid()
    bad = g.copy()
    bad[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match="points must be finite"):
        P.BicubicPatch(bad)
    with pytest.raises(ValueError, match="u_params must be 4 distinct values in \\[0, 1\\] at least"):
        P.BicubicPatch(g, u_params=[0, 1e-13, 0.5, 1])
    with pytest.raises(ValueError, match="v_params"):
        P.BicubicPatch(g, v_params=[0, np.nan, 0.5, 1])
    patch = P.BicubicPatch(g, u_params=[0, 0.2, 0.5, 1])
    assert np.allclose(patch(0.2, 1 / 3), g[1, 1])


def test_nurbs_surface_refuses_infinite_weights():
    net = np.zeros((3, 2, 3))
    net[..., 0] = [[1, 1], [1, 1], [0, 0]]
    net[..., 1] = [[0, 0], [1, 1], [1, 1]]
    net[..., 2] = [[0, 1]] * 3
    with pytest.raises(ValueError, match="weights must be > 0 and finite"):
        P.NURBSSurface(net, np.array([[1, 1], [np.inf, 1], [1, 1]]), 2, 1)
