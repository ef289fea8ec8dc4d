"""Triangle surfaces as plain arrays, for jobs that only write them: no VTK loaded.

The meshers build their result through `triangle_surface`, which gives a
`pyvista.PolyData`, except inside `arrays_only()`, where it gives a
`TriangleArrays`: the same points, triangles, point data and field data as
numpy arrays.  ``implicad mesh part.py -o part.stl`` meshes and writes that
way, so the command never imports pyvista and VTK (0.3 s of a run); the
binary STL writer reads the arrays directly, and `TriangleArrays.to_polydata`
gives the PolyData for any other format.

Examples
--------
>>> import numpy as np
>>> with arrays_only():
...     s = triangle_surface(np.eye(3), np.array([[0, 1, 2]]))
>>> s.n_cells, s.is_manifold
(1, False)
"""

from __future__ import annotations

import contextlib
import contextvars

import numpy as np

__all__ = ["TriangleArrays", "arrays_only", "arrays_wanted", "triangle_surface"]

_ARRAYS = contextvars.ContextVar("spatial_files_surface_arrays", default=False)


@contextlib.contextmanager
def arrays_only():
    """Inside, `triangle_surface` (and so the meshers) gives `TriangleArrays` instead of PolyData."""
    token = _ARRAYS.set(True)
    try:
        yield
    finally:
        _ARRAYS.reset(token)


def arrays_wanted() -> bool:
    """True inside `arrays_only` (in this thread or task)."""
    return _ARRAYS.get()


def triangle_surface(points, faces):
    """The surface of `points` (n, 3) and triangles `faces` (m, 3): a PolyData, or arrays inside `arrays_only`."""
    if _ARRAYS.get():
        return TriangleArrays(points, faces)
    import pyvista as pv  # local: 0.3 s to import

    return pv.PolyData.from_regular_faces(points, faces)


class TriangleArrays:
    """A triangle surface as arrays: what `triangle_surface` gives inside `arrays_only`.

    Carries the attributes the meshers set and the command reads --
    ``points``, ``triangles`` (m, 3), ``point_data`` and ``field_data``
    (dicts of arrays), ``n_points``, ``n_cells``, ``is_manifold`` -- and turns
    into a `pyvista.PolyData` with `to_polydata`.
    """

    def __init__(self, points, faces):
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        self.point_data: dict = {}
        self.field_data: dict = {}

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_cells(self) -> int:
        return int(self.triangles.shape[0])

    @property
    def is_all_triangles(self) -> bool:
        return True

    @property
    def is_manifold(self) -> bool:
        """No open edge: every edge is shared by exactly two triangles (pyvista's `is_manifold`)."""
        if self.n_cells == 0:
            return True
        t = self.triangles
        if t.min() < 0 or t.max() >= self.n_points:  # ids the compiled count cannot bucket
            return _edges_twice_sorted(t, self.n_points)
        from .kernels import edges_twice

        return bool(edges_twice(np.ascontiguousarray(t), self.n_points))

    def to_polydata(self):
        """The same surface as a `pyvista.PolyData`, with its point and field data."""
        import pyvista as pv

        out = pv.PolyData.from_regular_faces(self.points, self.triangles)
        for name, values in self.point_data.items():
            out.point_data[name] = values
        for name, values in self.field_data.items():
            out.field_data[name] = values
        return out


def _edges_twice_sorted(t, n_points) -> bool:
    """`TriangleArrays.is_manifold` by sorting every edge's key: any vertex ids (the compiled count's reference)."""
    m, n = t.shape[0], np.int64(max(n_points, 1))
    keys = np.empty(3 * m, dtype=np.int64)
    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        a, b = t[:, i], t[:, j]
        part = keys[k * m:(k + 1) * m]
        np.minimum(a, b, out=part)
        part *= n
        part += np.maximum(a, b)
    # stable: timsort finds the runs a mesher's vertex order leaves (twice as fast here as quicksort)
    keys.sort(kind="stable")
    pairs = keys[0::2], keys[1::2]
    return bool(keys.size % 2 == 0 and np.array_equal(*pairs) and (pairs[1][:-1] < pairs[0][1:]).all())
