"""The seed's claims about representations, checked with figures.

* B-rep needs more storage than CSG (bytes of each, and the ratio);
* a spatial-occupancy grid trades memory for simplicity: its memory grows as
  N^3 while its volume error falls only as N^-1 (count) or N^-2 (fraction)
  (`grid_sweep`, with a plot);
* a wireframe answers no inside/outside query (the representation has no
  membership function; `spatial.compare.ambiguity` shows three solids with
  one wireframe);
* a B-rep is simple to convert to a wireframe (seconds to take its edges, and to build it);
* the octree's FULL and FULL + BOUNDARY volumes bound the true volume.
"""

from __future__ import annotations

import numpy as np

from ..cells import OccupancyGrid
from ..files import atomic_write

__all__ = ["check_claims", "grid_sweep", "plot_grid_sweep"]


def _get(table, name):
    for r in table.rows:
        if r.name == name and r.applies:
            return r
    return None


def grid_sweep(solid, reference, resolutions=(8, 16, 32, 64)):
    """Occupancy-grid memory and volume errors at each resolution.

    Returns
    -------
    list of dict
        ``{"N", "bytes_bool", "bytes_float", "error_count", "error_fraction", "seconds"}``.
    """
    import time
    out = []
    for n in resolutions:
        t0 = time.perf_counter()
        g = OccupancyGrid.from_solid(solid, resolution=int(n), progress=False)
        dt = time.perf_counter() - t0
        out.append({"N": int(n), "bytes_bool": int(g.occupancy.nbytes), "bytes_float": int(g.distance.nbytes),
                    "error_count": abs(g.volume("count") - reference) / reference,
                    "error_fraction": abs(g.volume("fraction") - reference) / reference, "seconds": dt})
    return out


def plot_grid_sweep(rows, path=None, *, dpi=110):
    """Memory against volume error of the sweep (log-log); writes a PNG when `path` is given."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    mem_b = [r["bytes_bool"] for r in rows]
    mem_f = [r["bytes_float"] for r in rows]
    ax.loglog(mem_b, [max(r["error_count"], 1e-12) for r in rows], "o-", label="bool voxels, voxel count")
    ax.loglog(mem_f, [max(r["error_fraction"], 1e-12) for r in rows], "s-", label="float32 distances, fractional")
    for r, m in zip(rows, mem_f):
        ax.annotate(f"N={r['N']}", (m, max(r["error_fraction"], 1e-12)), textcoords="offset points", xytext=(4, 4),
                    fontsize=8)
    ax.set_xlabel("memory, bytes")
    ax.set_ylabel("relative volume error")
    ax.set_title("Spatial occupancy: memory grows as N^3, error falls as N^-1 .. N^-2", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    if path is not None:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"), ".png")
    return fig


def check_claims(table, solid, *, resolutions=(8, 16, 32, 64)) -> list:
    """The seed's claims as rows ``{"claim", "holds", "figures", ...}``."""
    claims = []
    csg, brep = _get(table, "CSG tree"), _get(table, "B-rep (faces by CSG leaf)")
    if csg and brep:
        claims.append({"claim": "B-rep requires more storage than CSG", "holds": brep.bytes > csg.bytes,
                       "figures": f"B-rep {brep.bytes} B in memory ({brep.file_bytes} B as PLY) vs CSG {csg.bytes} B "
                                  f"({csg.file_bytes} B as JSON): {brep.bytes / csg.bytes:.0f}x",
                       "ratio": brep.bytes / csg.bytes})
    sweep = grid_sweep(solid, table.reference_volume, resolutions)
    table.context["grid_sweep"] = sweep
    a, b = sweep[0], sweep[-1]
    mem_growth = b["bytes_bool"] / a["bytes_bool"]
    err_fall = a["error_fraction"] / max(b["error_fraction"], 1e-300)
    claims.append({"claim": "occupancy grids trade memory for simplicity", "holds": mem_growth > err_fall,
                   "figures": f"N {a['N']} -> {b['N']}: memory x{mem_growth:.0f} ({a['bytes_bool']} -> "
                              f"{b['bytes_bool']} B of voxels), fractional volume error /{err_fall:.0f} "
                              f"({a['error_fraction']:.1e} -> {b['error_fraction']:.1e}), count error "
                              f"{a['error_count']:.1e} -> {b['error_count']:.1e}",
                   "sweep": sweep})
    wire = _get(table, "wireframe")
    if wire:
        claims.append({"claim": "a wireframe cannot tell inside from outside", "holds": "inside/outside" not in wire.answers
                       and wire.volume is None,
                       "figures": f"{wire.note.split(';')[0]}; no membership query, no volume "
                                  "(three different solids share one wireframe: spatial.compare.ambiguity)"})
    if wire and brep:
        conv = wire.details.get("from_brep_seconds", wire.build_seconds)
        claims.append({"claim": "a B-rep is simple to convert to a wireframe", "holds": conv < brep.build_seconds,
                       "figures": f"the B-rep's edges as a wireframe in {conv:.3g} s vs {brep.build_seconds:.3g} s "
                                  "to build the B-rep"})
    tree = _get(table, "octree cells")
    if tree:
        lo, hi = tree.details["volume_bounds"]
        ref = table.reference_volume
        claims.append({"claim": "cell decomposition bounds the volume", "holds": lo <= ref <= hi,
                       "figures": f"FULL {lo:.6g} <= {ref:.6g} <= FULL + BOUNDARY {hi:.6g}"})
    return claims
