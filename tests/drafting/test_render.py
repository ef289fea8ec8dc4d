"""Pictures: every style draws the part; hidden-line hides what wireframe shows."""

import os

import numpy as np
import pytest
import pyvista as pv

from spatial.drafting.render import exploded_view, explode_offsets, render, render_cells, render_views


@pytest.fixture(scope="module")
def cube():
    return pv.Cube().triangulate()


def dark_fraction(image):
    return float(np.mean(image.max(axis=2) < 100))


def test_every_style_draws_the_part(cube):
    for style in ("shaded", "wireframe", "mesh", "hidden-line"):
        image = render(cube, style=style, window_size=(160, 120))
        assert image.shape == (120, 160, 3)
        assert image.dtype == np.uint8
        assert (image.min(axis=2) < 250).mean() > 0.01, style


def test_hidden_lines_are_removed(cube):
    wire = render(cube, style="wireframe", window_size=(200, 160))
    hidden = render(cube, style="hidden-line", window_size=(200, 160))
    # The wire-frame model draws the three hidden edges of the cube as well.
    assert dark_fraction(wire) > dark_fraction(hidden) * 1.1


def test_png_written_atomically(tmp_path, cube):
    out = tmp_path / "cube.png"
    image = render(cube, out, window_size=(64, 48))
    assert out.exists()
    from PIL import Image

    assert np.array_equal(np.asarray(Image.open(out))[..., :3], image)
    assert [p.name for p in tmp_path.iterdir()] == ["cube.png"]


def test_bad_arguments_fail_before_any_file(tmp_path, cube):
    with pytest.raises(ValueError, match="style: expected one of shaded"):
        render(cube, tmp_path / "a.png", style="toon")
    with pytest.raises(ValueError, match=r"path: pictures are written as PNG"):
        render(cube, tmp_path / "a.jpg")
    with pytest.raises(ValueError, match="window_size"):
        render(cube, window_size=(0, 10))
    with pytest.raises(TypeError, match="expected pyvista meshes"):
        render({"a": np.zeros(3)})
    assert not os.listdir(tmp_path)


def test_views_sheet_has_four_tiles(cube):
    sheet = render_views(cube, window_size=(200, 160))
    assert sheet.shape == (160, 200, 3)
    for tile in (sheet[:80, :100], sheet[:80, 100:], sheet[80:, :100], sheet[80:, 100:]):
        assert dark_fraction(tile) > 0.001


def test_explode_offsets_push_parts_radially():
    centroids = np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 2.0, 0], [0, -2.0, 0]])
    off = explode_offsets(centroids, 0.5)
    assert np.allclose(off[0], [1.0, 0, 0])
    assert np.allclose(off[2], [0, 1.0, 0])
    assert np.allclose(explode_offsets(np.zeros((1, 3)), 1.0), 0.0)
    with pytest.raises(ValueError, match="factor"):
        explode_offsets(centroids, -1)


def test_exploded_view_renders(cube):
    parts = {"a": cube, "b": pv.Sphere(center=(1.5, 0, 0), radius=0.4)}
    image = exploded_view(parts, window_size=(120, 90))
    assert dark_fraction(image) > 0.001


def where_parts(image):
    """Mean (row, column) of the cube's (tan) and the ball's (blue) pixels in a shaded picture."""
    px = image.astype(int)
    ball = np.argwhere(px[..., 2] - px[..., 0] > 30).mean(axis=0)
    cube = np.argwhere(px[..., 0] - px[..., 2] > 30).mean(axis=0)
    return cube, ball


@pytest.mark.parametrize("view, centre, right, up", [
    ("front", (1.5, 0, 0), True, None), ("front", (0, 0, 1.5), None, True),
    ("top", (1.5, 0, 0), True, None), ("top", (0, 1.5, 0), None, True),
    ("left", (0, -1.5, 0), True, None), ("right", (0, 1.5, 0), True, None),
])
def test_views_are_seen_from_their_side_not_mirrored(view, centre, right, up):
    # Front: along +y with x right and z up; top: from above with x right and y up; left:
    # from -x with -y on the right; right: from +x with +y on the right.
    parts = {"cube": pv.Cube().triangulate(), "ball": pv.Sphere(radius=0.4, center=centre)}
    cube, ball = where_parts(render(parts, view=view, window_size=(200, 200)))
    if right:
        assert ball[1] > cube[1] + 20
    if up:
        assert ball[0] < cube[0] - 20


def test_wireframe_draws_edges_not_triangles():
    # A sphere has no sharp edge: its wire-frame model is empty, whatever its triangles.
    ball = pv.Sphere(radius=1.0, theta_resolution=40, phi_resolution=40)
    assert dark_fraction(render(ball, style="wireframe", window_size=(160, 120))) < 1e-4
    assert dark_fraction(render(ball, style="mesh", window_size=(160, 120))) > 0.01


def test_views_follow_the_projection(cube):
    first = render_views(cube, window_size=(200, 160), projection="first")
    third = render_views(cube, window_size=(200, 160), projection="third")
    # The cube looks the same from every side: the sheets differ only by placement, and the
    # iso tile (the one with three visible faces' worth of lines) swaps rows.
    assert dark_fraction(first[80:, 100:]) == pytest.approx(dark_fraction(third[:80, 100:]), rel=0.05)
    with pytest.raises(ValueError, match="projection"):
        render_views(cube, projection="second")


def test_octree_cells_coloured_by_class():
    from implicit import sphere
    from spatial.cells import Octree

    image = render_cells(Octree.from_solid(sphere(1.0), resolution=12), window_size=(200, 160), cutaway=True)
    px = image.reshape(-1, 3).astype(int)
    blue = ((px[:, 2] - px[:, 0]) > 60).mean()
    orange = ((px[:, 0] - px[:, 2]) > 60).mean()
    assert blue > 0.002 and orange > 0.02
