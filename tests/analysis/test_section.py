"""Planar sections: exact circles, holes, areas and second moments of area."""

import numpy as np
import pytest

from implicit import box, cylinder, sphere, torus
from spatial.analysis.section import parse_plane, section

RADIUS_TOL = 1e-6     # refined contour points lie on the true boundary
AREA_TOL = 1e-6       # relative, smooth outlines at 128 samples


def test_sphere_section_is_exact_circle():
    s = section(sphere(1.0, center=(0.1, -0.2, 0.0)), "z=0.6", resolution=128)
    assert len(s.loops) == 1 and s.holes == [False]
    r = np.linalg.norm(s.loops3d[0] - [0.1, -0.2, 0.6], axis=1)
    np.testing.assert_allclose(r, 0.8, atol=RADIUS_TOL)
    np.testing.assert_allclose(s.loops3d[0][:, 2], 0.6, atol=1e-12)
    assert s.area == pytest.approx(np.pi * 0.64, rel=AREA_TOL)
    np.testing.assert_allclose(s.centroid3d, [0.1, -0.2, 0.6], atol=1e-9)
    J = np.pi * 0.8 ** 4 / 4
    assert s.Ixx == pytest.approx(J, rel=1e-5) and s.Iyy == pytest.approx(J, rel=1e-5)
    assert s.polar == pytest.approx(2 * J, rel=1e-5) and abs(s.Ixy) < 1e-8


def test_area_converges_fast():
    errs = [abs(section(sphere(1.0), "z=0.3", resolution=n).area - np.pi * 0.91) for n in (32, 64)]
    assert errs[1] < errs[0] / 8          # better than second order


def test_box_with_hole():
    plate = box((2.0, 1.0, 0.5)) - cylinder(0.25, 1.0, center=(0.3, 0.0, 0.0))
    s = section(plate, "z=0.1", resolution=128)
    assert sorted(s.holes) == [False, True]
    A = 2.0 - np.pi * 0.25 ** 2
    assert s.area == pytest.approx(A, rel=1e-6)
    # centroid shifted away from the hole: -(pi r^2 * 0.3) / A
    assert s.centroid[0] == pytest.approx(-np.pi * 0.0625 * 0.3 / A, abs=1e-6)
    # Iyy = int u^2 about the centroid: rectangle minus disc, parallel axes
    cu = s.centroid[0]
    Iyy = (1.0 * 8 / 12 + 2.0 * cu ** 2) - (np.pi * 0.25 ** 4 / 4 + np.pi * 0.0625 * (0.3 - cu) ** 2)
    assert s.Iyy == pytest.approx(Iyy, rel=1e-5)


def test_annulus_hole_and_orientation():
    ring = cylinder(1.0, 1.0) - cylinder(0.5, 2.0)
    s = section(ring, "z=0.2", resolution=128)
    assert len(s.loops) == 2
    outer = [lp for lp, h in zip(s.loops, s.holes) if not h][0]
    inner = [lp for lp, h in zip(s.loops, s.holes) if h][0]
    np.testing.assert_allclose(np.linalg.norm(inner, axis=1), 0.5, atol=RADIUS_TOL)
    # material counter-clockwise, holes clockwise

    def signed(lp):
        return 0.5 * np.sum(lp[:, 0] * np.roll(lp[:, 1], -1) - np.roll(lp[:, 0], -1) * lp[:, 1])
    assert signed(outer) > 0 > signed(inner)
    assert s.area == pytest.approx(np.pi * 0.75, rel=AREA_TOL)


def test_oblique_plane_and_torus():
    s = section(torus(1.0, 0.3), "y=0", resolution=128)
    assert len(s.loops) == 2 and not any(s.holes)
    assert s.area == pytest.approx(2 * np.pi * 0.09, rel=AREA_TOL)
    tilted = section(sphere(1.0), ((0.0, 0.0, 0.5), (1.0, 1.0, 1.0)), resolution=128)
    d = 0.5 / np.sqrt(3)                      # distance of the plane from the centre
    assert tilted.area == pytest.approx(np.pi * (1 - d * d), rel=AREA_TOL)


def test_empty_section_and_errors():
    s = section(sphere(1.0), "z=2", resolution=32)
    assert s.loops == [] and s.area == 0.0
    with pytest.raises(ValueError, match="plane"):
        parse_plane("w=3")
    with pytest.raises(TypeError, match="plane"):
        parse_plane(3.0)
    with pytest.raises(ValueError, match="plane normal"):
        parse_plane(((0, 0, 0), (0, 0, 0)))
    with pytest.raises(TypeError, match="solid"):
        section("sphere", "z=0")
    with pytest.raises(ValueError, match="resolution"):
        section(sphere(1.0), "z=0", resolution=3)
    d = section(sphere(1.0), "x=0", resolution=32).to_dict()
    assert d["loops"][0]["hole"] is False and len(d["loops"][0]["points"][0]) == 2
