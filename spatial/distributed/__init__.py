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

from ..files.lazy import lazy_exports
from .mesh import mesh  # noqa: F401  (eager: the name of its module too, which an import would bind here)

# The rest read on first use: `spatial.mesh` wraps its warnings with `warn` without loading the
# analysis room, which `mass` needs.
_LAZY = {
    "connect": (".cluster", "connect"), "local_cluster": (".cluster", "local_cluster"),
    "mass_properties": (".mass", "mass_properties"),
    "PartitionedMesh": (".parts", "PartitionedMesh"), "DEFAULT_BRICK": (".plan", "DEFAULT_BRICK"),
    "plan_bricks": (".plan", "plan_bricks"), "level_set_vdb": (".vdb", "level_set_vdb"),
    "save_level_set_vdb": (".vdb", "save_level_set_vdb"),
}
__getattr__, __dir__ = lazy_exports(__name__, _LAZY)

__all__ = ["mesh", "mass_properties", "PartitionedMesh", "level_set_vdb", "save_level_set_vdb", "connect",
           "local_cluster", "plan_bricks", "DEFAULT_BRICK"]
