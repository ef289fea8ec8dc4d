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
``spatial.mass_properties`` and the rest work as before; each is imported
the first time it is read (`spatial.files.lazy`), so ``import spatial``
loads no room and a job pays only for the rooms it uses.
"""

from .files.deferred_imports import install as _install_deferred_imports
from .files.frozen_imports import install as _install_frozen_imports
from .files.lazy import lazy_exports
from .files.vtk_listing import install as _install_vtk_listing
from .files.shutdown import install as _install_shutdown

#: Public names and the room each comes from (read on first use; the functions `section`,
#: `interference` and `compare` stay in their modules, whose names they share, and
#: `spatial.manufacturing.slice` keeps its room's name: it would hide the built-in here).
_LAZY = {
    "EMPTY": (".cells", "EMPTY"), "FULL": (".cells", "FULL"), "BOUNDARY": (".cells", "BOUNDARY"),
    "Octree": (".cells", "Octree"), "OccupancyGrid": (".cells", "OccupancyGrid"),
    "mesh_to_solid": (".cells", "mesh_to_solid"), "save_vdb": (".cells", "save_vdb"),
    "load_vdb": (".cells", "load_vdb"), "min_feature_size": (".cells", "min_feature_size"),
    "thin_wall": (".cells", "thin_wall"),
    "save_mesh": (".files", "save_mesh"), "load_mesh": (".files", "load_mesh"),
    "feature_edges": (".meshing", "feature_edges"), "FeatureCurves": (".meshing", "FeatureCurves"),
    "MassProperties": (".analysis", "MassProperties"), "ToleranceError": (".analysis", "ToleranceError"),
    "Topology": (".analysis", "Topology"), "ValidityReport": (".analysis", "ValidityReport"),
    "topology": (".analysis", "topology"), "check": (".analysis", "check"),
    "triangle_defects": (".analysis", "triangle_defects"), "Section": (".analysis", "Section"),
    "Interference": (".analysis", "Interference"), "check_assembly": (".analysis", "check_assembly"),
    "BillOfMaterials": (".analysis", "BillOfMaterials"), "bill_of_materials": (".analysis", "bill_of_materials"),
    "Slices": (".manufacturing", "Slices"), "ToolPath": (".manufacturing", "ToolPath"),
    "Verification": (".manufacturing", "Verification"), "toolpath": (".manufacturing", "toolpath"),
    "Inspection": (".inspection", "Inspection"), "StackUp": (".inspection", "StackUp"),
    "Tolerance": (".inspection", "Tolerance"), "stackup": (".inspection", "stackup"),
    "surface_for_fea": (".fea", "surface_for_fea"), "surface_quality": (".fea", "surface_quality"),
    "tet_mesh": (".fea", "tet_mesh"), "TetMesh": (".fea", "TetMesh"), "TetQuality": (".fea", "TetQuality"),
    "write_fea": (".fea", "write_fea"), "write_static_deck": (".fea", "write_static_deck"),
    "run_calculix": (".fea", "run_calculix"), "read_frd": (".fea", "read_frd"),
    "fit_section_curve": (".convert", "fit_section_curve"), "loft_sections": (".convert", "loft_sections"),
    "fit_star_surface": (".convert", "fit_star_surface"), "surface_to_mesh": (".convert", "surface_to_mesh"),
    "curve_to_polydata": (".convert", "curve_to_polydata"),
    "isoparametric_polydata": (".convert", "isoparametric_polydata"),
    "part_drawing": (".drafting", "part_drawing"), "assembly_drawing": (".drafting", "assembly_drawing"),
    "write_drawing": (".drafting", "write_drawing"),
    "brep": (".compare", "brep"), "half_space_form": (".compare", "half_space_form"),
    "Comparison": (".compare", "Comparison"), "BRep": (".compare", "BRep"),
    "report": (".compare.report", "report"),
    # the rooms themselves: `spatial.analysis.section(...)` after a bare `import spatial`
    "files": (".files", None), "cells": (".cells", None), "meshing": (".meshing", None),
    "analysis": (".analysis", None), "convert": (".convert", None), "fea": (".fea", None),
    "drafting": (".drafting", None), "manufacturing": (".manufacturing", None), "inspection": (".inspection", None),
    "distributed": (".distributed", None), "compare": (".compare", None), "cli": (".cli", None),
}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
_install_shutdown()  # the garbage collected once at exit, not walked again by the teardown (0.15 s)
_install_frozen_imports()  # numba's and pyvista's objects left out of the collector's walks (0.2 s)
_install_deferred_imports()  # pooch and yaml, which pyvista and numba import, run on first use (0.06 s)
_install_vtk_listing()  # VTK's extension modules found in one listing of their folder (0.02 s)
__all__ = sorted(["mesh", "mass_properties", *(name for name, (_, attribute) in _LAZY.items() if attribute)])


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
        from .files.warn import user_warnings
        from .meshing import mesh as mesh_here

        # (warnings at the caller's line, not this wrapper's)
        return user_warnings(mesh_here)(solid, **options)
    from .distributed import mesh as _mesh_on_cluster

    return _mesh_on_cluster(solid, client=client, workers=workers, **options)


def mass_properties(obj, *, client=None, workers=None, **options):
    """Mass properties with error bounds: `spatial.analysis.mass_properties`, or on a Dask cluster.

    With ``client=`` or ``workers=`` a Solid's meshes are integrated brick
    by brick on the cluster (`spatial.distributed.mass_properties`); at a
    resolution the result agrees with the single-process one to rounding
    (with a tolerance the cluster asks the same levels, meshed plain: its
    bricks are never fused for the sharp-edge pass).

    Examples
    --------
    >>> import pyvista as pv
    >>> round(mass_properties(pv.Box((0, 2, 0, 1, 0, 1)).triangulate()).volume, 12)
    2.0
    """
    if client is None and workers is None:
        from .analysis import mass_properties as mass_here
        from .files.warn import user_warnings

        return user_warnings(mass_here)(obj, **options)
    from .distributed import mass_properties as _mass_on_cluster

    return _mass_on_cluster(obj, client=client, workers=workers, **options)

