"""Parts that outgrow one machine: meshing, mass properties and level sets as Dask tasks.

The octree is cut into bricks (cells of `DEFAULT_BRICK` voxels); the client
classifies down to them (`plan`), and each BOUNDARY brick is one task on a
`distributed.Client` (`cluster`: a given client, a scheduler address or a
loopback `LocalCluster`; `run`: submission, Dask's progress bar, results as
they complete).  A task (`worker`) rebuilds the solid from its JSON tree once
per worker process, classifies, samples, meshes and refines its brick; its
memory is bounded by the brick's size, not the part's.

- `mesh`: the bricks' meshes fused by lattice-edge id, in memory or as .vtp
  parts under a .pvtp index (`parts`, `PartitionedMesh`); the same triangles
  as `spatial.meshing.mesh`.
- `mass_properties`: per-brick partial moments summed on the client (`mass`).
- `level_set_vdb` / `save_level_set_vdb`: the narrow band as a sparse
  OpenVDB grid (`vdb`).

Above `analysis`, `meshing`, `cells` and `files`; `spatial.mesh(...,
client=...)` and `spatial.mass_properties(..., client=...)` forward here.
"""

from .cluster import connect, local_cluster  # noqa: F401
from .mass import mass_properties  # noqa: F401
from .mesh import mesh  # noqa: F401
from .parts import PartitionedMesh  # noqa: F401
from .plan import DEFAULT_BRICK, plan_bricks  # noqa: F401
from .vdb import level_set_vdb, save_level_set_vdb  # noqa: F401

__all__ = ["mesh", "mass_properties", "PartitionedMesh", "level_set_vdb", "save_level_set_vdb", "connect",
           "local_cluster", "plan_bricks", "DEFAULT_BRICK"]
