"""Boundary meshes: scikit-image's marching cubes over the octree's boundary cells.

The room holds the boundary mesher `mesh` (`boundary`: classification of the
lattice down to cells of two voxels), the pipeline over a set of boundary
cells `mesh_cells` (`cells`: slabs of blocks, merge, vertex refinement), one
slab's two-pass sampling (`slab`), one block's marching cubes and the merge of
blocks by lattice-edge ids (`blocks`), vertex refinement along lattice edges
(`refine`), the rebuilding of sharp edges and corners (`features`) and the
labelled feature curves read from its result (`feature_curves`: `feature_edges`),
the dense grid mesher (`dense`) and the constants and array helpers
the stages share (`arrays`).

Importing the room provides `Octree.to_mesh` and `OccupancyGrid.to_mesh` with
their meshers (the cells room sits below and never imports this one).

Examples
--------
>>> from implicit import sphere
>>> from spatial.meshing import mesh
>>> mesh(sphere(1.0), resolution=16).is_manifold
True
"""

from ..cells.lattice import provide
from .arrays import (CLASSIFY_CHUNK, DEFAULT_BLOCK, EVAL_CHUNK, REFINE_ACCEPT, REFINE_STEPS, REFINE_TOL,  # noqa: F401
                     ZERO_NUDGE, empty_mesh, faces_array)
from .blocks import merge_blocks, mesh_block  # noqa: F401
from .boundary import mesh  # noqa: F401
from .cells import mesh_cells  # noqa: F401
from .dense import grid_mesh  # noqa: F401
from .feature_curves import FeatureCurves, feature_edges  # noqa: F401

provide("mesh_cells", mesh_cells)
provide("grid_mesh", grid_mesh)

__all__ = ["mesh", "feature_edges", "FeatureCurves", "mesh_cells", "mesh_block", "merge_blocks", "grid_mesh", "empty_mesh", "faces_array",
           "ZERO_NUDGE", "DEFAULT_BLOCK", "REFINE_STEPS", "REFINE_TOL", "REFINE_ACCEPT"]
