"""implicad's spatial side: cells, grids, meshes, analysis, files and the command line.

The package is a house of rooms in layers (docs/ARCHITECTURE.md); a room
imports only from itself and the rooms below it:

==============  ==========================================================
``files``       mesh files, atomic writes, progress bars (bottom)
``cells``       lattice, octree, occupancy grid, OpenVDB level sets
``meshing``     boundary marching cubes, stitching, vertex refinement
``analysis``    mass properties, sections, interference, validity
``convert``     grids and meshes <-> parametric curves and patches
``fea``         FEA surfaces, tetrahedra, quality, solver files
``drafting``    pictures and drawings
``manufacturing`` layer slices, 2.5D milling tool paths, G-code, verification
``inspection``  scans against designs, tolerance stack-up
``distributed`` meshing and mass properties as Dask tasks on a cluster
``compare``     representations compared on one part, the full report
``cli``         the ``implicad`` command (top)
==============  ==========================================================

This module re-exports the public names, so ``spatial.mesh``,
``spatial.mass_properties`` and the rest work as before.
"""

from .cells import EMPTY, FULL, BOUNDARY, Octree, OccupancyGrid  # noqa: F401
from .cells import mesh_to_solid, save_vdb, load_vdb  # noqa: F401
from .cells import min_feature_size, thin_wall  # noqa: F401
from .files import save_mesh, load_mesh  # noqa: F401
from .meshing import mesh as _mesh_here, feature_edges, FeatureCurves  # noqa: F401
from .analysis import MassProperties, ToleranceError, mass_properties as _mass_here  # noqa: F401
from .distributed.warn import user_warnings as _user_warnings  # noqa: E402
from .analysis import Topology, ValidityReport, topology, check, triangle_defects  # noqa: F401
# (the functions `section` and `interference` stay in their modules, whose names they share)
from .analysis import Section  # noqa: F401
from .analysis import Interference, check_assembly  # noqa: F401
from .analysis import BillOfMaterials, bill_of_materials  # noqa: F401
# (`spatial.manufacturing.slice` keeps its room's name: it would hide the built-in here)
from .manufacturing import Slices, ToolPath, Verification, toolpath  # noqa: F401
from .inspection import Inspection, StackUp, Tolerance, stackup  # noqa: F401
from .fea import surface_for_fea, surface_quality, tet_mesh, TetMesh, TetQuality, write_fea  # noqa: F401
from .fea import write_static_deck, run_calculix, read_frd  # noqa: F401
from .convert import (  # noqa: F401
    fit_section_curve, loft_sections, fit_star_surface, surface_to_mesh, curve_to_polydata, isoparametric_polydata,
)
from .drafting import part_drawing, assembly_drawing, write_drawing  # noqa: F401


def mesh(solid, *, client=None, workers=None, **options):
    """Closed boundary mesh of a solid: `spatial.meshing.mesh`, or on a Dask cluster.

    With ``client=`` (a `distributed.Client`, a scheduler address or
    ``"local"``) or ``workers=N`` (a local cluster of N processes) the work
    runs brick by brick on the cluster (`spatial.distributed.mesh`, which
    also takes ``brick=`` and ``parts=``); otherwise in this process.  The
    two give the same triangles.  See `spatial.meshing.mesh` for `options`.

    Examples
    --------
    >>> from implicit import sphere
    >>> mesh(sphere(1.0), resolution=16).is_manifold
    True
    """
    if client is None and workers is None:
        # (warnings at the caller's line, not this wrapper's)
        return _user_warnings(_mesh_here)(solid, **options)
    from .distributed import mesh as _mesh_on_cluster

    return _mesh_on_cluster(solid, client=client, workers=workers, **options)


def mass_properties(obj, *, client=None, workers=None, **options):
    """Mass properties with error bounds: `spatial.analysis.mass_properties`, or on a Dask cluster.

    With ``client=`` or ``workers=`` a Solid's meshes are integrated brick
    by brick on the cluster (`spatial.distributed.mass_properties`); the
    result agrees with the single-process one to rounding.

    Examples
    --------
    >>> import pyvista as pv
    >>> round(mass_properties(pv.Box((0, 2, 0, 1, 0, 1)).triangulate()).volume, 12)
    2.0
    """
    if client is None and workers is None:
        return _user_warnings(_mass_here)(obj, **options)
    from .distributed import mass_properties as _mass_on_cluster

    return _mass_on_cluster(obj, client=client, workers=workers, **options)


# (the function `compare` stays in its room, whose name it shares: spatial.compare.compare)
from .compare import brep, half_space_form, Comparison, BRep  # noqa: E402,F401
from .compare.report import report  # noqa: E402,F401
