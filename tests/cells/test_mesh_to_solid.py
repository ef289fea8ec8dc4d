"""mesh_to_solid refuses meshes without an inside, or repairs them when asked."""

import numpy as np
import pytest
import pyvista as pv

from spatial.cells.vdb import mesh_to_solid



def _ball():
    return pv.Sphere(radius=1.0, theta_resolution=24, phi_resolution=24).triangulate().clean()


def test_closed_mesh_is_a_solid():
    s = mesh_to_solid(_ball(), 0.05)
    assert s(np.zeros((1, 3)))[0] < -0.1 and s(np.array([[2.0, 0, 0]]))[0] > 0


def test_open_mesh_is_refused_or_repaired():
    holed = _ball().remove_cells(np.arange(5))
    with pytest.raises(ValueError, match="open or not consistently oriented .* repair=True"):
        mesh_to_solid(holed, 0.05)
    s = mesh_to_solid(holed, 0.05, repair=True)
    assert s(np.zeros((1, 3)))[0] < -0.1 and s(np.array([[0, 0, 1.5]]))[0] > 0


def test_inward_or_flipped_half_is_refused():
    m = _ball()
    faces = m.faces.reshape(-1, 4).copy()
    faces[:10, 1:] = faces[:10, :0:-1]          # ten triangles wound the other way
    with pytest.raises(ValueError, match="not consistently oriented"):
        mesh_to_solid(pv.PolyData(m.points, faces.ravel()), 0.05)


def test_self_intersecting_mesh_is_refused_or_repaired():
    two = _ball().merge(_ball().translate((0.3, 0.0, 0.0)))
    with pytest.raises(ValueError, match="self-intersecting"):
        mesh_to_solid(two, 0.05)
    s = mesh_to_solid(two, 0.05, repair=True)
    assert s(np.array([[0.15, 0, 0]]))[0] < -0.1
