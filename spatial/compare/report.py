"""The full report of one part: mesh, mass properties, validity, section, drawings, comparison.

`report(solid, out_dir)` writes into `out_dir`:

* ``part.stl`` -- the boundary mesh;
* ``shaded.png`` -- a shaded view; ``sheet.png`` -- the drawing sheet (the
  drafting room's drawing when it provides one, otherwise its multi-view
  picture, and the report says which); ``section.png`` -- the mid-height section;
* ``compare.png`` and ``occupancy.png`` -- the representation comparison's charts;
* ``report.md`` (pictures beside it), ``report.html`` (one self-contained page,
  the pictures inlined as base64) and ``report.json``.

Examples
--------
>>> from implicit import box
>>> from spatial.compare.report import report
>>> paths = report(box((2, 1, 1)), "out/box", resolution=24, progress=False)   # doctest: +SKIP
"""

from __future__ import annotations

import base64
import html
import json
import os
import re
import time

import numpy as np

from implicit.solid import Solid

from ..analysis import check, mass_properties
from ..analysis.section import section
from ..files import atomic_write, progress_bar, save_mesh
from ..meshing import mesh as mesh_solid
from .brep import brep
from .table import compare

__all__ = ["report", "STAGES"]

STAGES = ("mesh", "mass properties", "validity", "section", "drawings", "comparison", "pages")


def _write_text(path, text):
    atomic_write(path, lambda tmp: open(tmp, "w", encoding="utf-8").write(text), os.path.splitext(path)[1])


def _section_picture(sec, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.path import Path as MPath
    from matplotlib.patches import PathPatch
    fig, ax = plt.subplots(figsize=(5.5, 5))
    verts, codes = [], []
    for loop in sec.loops:
        loop = np.asarray(loop)
        verts += [*loop, loop[0]]
        codes += [MPath.MOVETO] + [MPath.LINETO] * (len(loop) - 1) + [MPath.CLOSEPOLY]
    if verts:
        ax.add_patch(PathPatch(MPath(np.asarray(verts), codes), facecolor="#9ecae1", edgecolor="k", hatch="///",
                               lw=1.2))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("u")
    ax.set_ylabel("v")
    fig.tight_layout()
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"), ".png")
    plt.close(fig)


def _drawing_sheet(solid, mesh, path, name, resolution, units, units_assumed):
    """The drafting room's drawing sheet (PNG, with an SVG beside it); the shaded views when it cannot draw.

    Returns ``(what was drawn, extra files)``; a fallback says why in the report.
    """
    from .. import drafting
    part_drawing = getattr(drafting, "part_drawing", None)
    write_drawing = getattr(drafting, "write_drawing", None)
    if part_drawing is not None and write_drawing is not None:
        try:
            sheet = part_drawing(solid, name=name, resolution=max(int(resolution), 48), units=units,
                                 units_assumed=units_assumed)
            write_drawing(sheet, path)
            svg = os.path.splitext(path)[0] + ".svg"
            write_drawing(sheet, svg)
            return (f"drawing sheet from spatial.drafting (first-angle projection, scale {sheet.meta.get('scale', '?')}; "
                    f"also as {os.path.basename(svg)})"), {"sheet_svg": svg}
        except (ValueError, ImportError, OSError) as exc:
            reason = f"spatial.drafting could not draw it ({str(exc).splitlines()[0]})"
    else:
        reason = "spatial.drafting has no part_drawing here"
    drafting.render_views(mesh, path, style="shaded", window_size=(1000, 800))
    return (f"shaded multi-view picture (front, top, right, iso): {reason}, so this picture stands in for "
            "the dimensioned sheet"), {}


def _img(path):
    with open(path, "rb") as fh:
        return "data:image/png;base64," + base64.b64encode(fh.read()).decode("ascii")


def _md_to_html(md, pictures):
    """The report's own small Markdown (headings, tables, lists, images, paragraphs) as HTML."""
    out, table = [], []

    def flush():
        if table:
            rows = [r for r in table if not re.fullmatch(r"\|?(\s*-+\s*\|)+\s*-*\s*", r)]
            cells = [[html.escape(c.strip()) for c in r.strip().strip("|").split("|")] for r in rows]
            out.append("<table>" + "".join(
                "<tr>" + "".join(f"<{'th' if i == 0 else 'td'}>{c}</{'th' if i == 0 else 'td'}>" for c in row) + "</tr>"
                for i, row in enumerate(cells)) + "</table>")
            table.clear()

    for line in md.splitlines():
        if line.startswith("|"):
            table.append(line)
            continue
        flush()
        m = re.fullmatch(r"!\[(.*)\]\((.*)\)", line.strip())
        if m:
            out.append(f'<figure><img alt="{html.escape(m.group(1))}" src="{pictures[m.group(2)]}">'
                       f"<figcaption>{html.escape(m.group(1))}</figcaption></figure>")
        elif line.startswith("#"):
            level = len(line) - len(line.lstrip("#"))
            out.append(f"<h{level}>{html.escape(line[level:].strip())}</h{level}>")
        elif line.startswith("- "):
            out.append(f"<li>{html.escape(line[2:])}</li>")
        elif line.startswith("    "):
            out.append(f"<pre>{html.escape(line[4:])}</pre>")
        elif line.strip():
            out.append(f"<p>{html.escape(line)}</p>")
    flush()
    style = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
             "table{border-collapse:collapse;font-size:13px;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 6px}"
             "th{background:#eee}img{max-width:100%;border:1px solid #ddd}figure{margin:1em 0}pre{margin:0}")
    return f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>implicad report</title><style>{style}</style>" \
           f"</head><body>{''.join(out)}</body></html>\n"


def report(solid, out_dir, *, name="part", resolution=96, compare_resolution=48, density=1.0, units=None,
           units_assumed=False, reference=None, progress=None) -> dict:
    """Write the full report of `solid` into `out_dir`; returns ``{what: path}``.

    Parameters
    ----------
    solid : implicit.Solid
    out_dir : str or os.PathLike
        Created when missing.
    name : str
        The part's name in the pages.
    resolution : int
        Cells across the part for the mesh, the mass properties and the pictures.
    compare_resolution : int
        Cells across the part for the representation comparison.
    density : float
        kg / m^3.
    units : str, optional
        The model's length unit (``"mm"``, ...); `units_assumed` says it was not declared.
    reference : float, optional
        The exact volume, when known.
    progress : bool, optional
        A bar over the stages (default: on a terminal).
    """
    if not isinstance(solid, Solid):
        raise TypeError(f"solid: expected an implicit.Solid, got {type(solid).__name__}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 8 <= resolution <= 1024:
        raise ValueError(f"resolution: expected an integer in [8, 1024], got {resolution!r}")
    if not isinstance(out_dir, (str, os.PathLike)):
        raise TypeError(f"out_dir: expected a folder name, got {type(out_dir).__name__}")
    solid.require_bounds()
    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    units = units or "m"
    paths, facts, started = {}, {"name": name, "units": units, "units_assumed": bool(units_assumed)}, time.perf_counter()
    p = lambda f: os.path.join(out_dir, f)  # noqa: E731
    with progress_bar(len(STAGES), "report", progress, unit="stage") as bar:
        bar.set_description("mesh")
        m = mesh_solid(solid, resolution=int(resolution), progress=False)
        paths["mesh"] = save_mesh(m, p(f"{name}.stl"))
        facts["mesh"] = {"file": os.path.basename(paths["mesh"]), "triangles": int(m.n_cells), "vertices": int(m.n_points)}
        bar.update(1)
        bar.set_description("mass properties")
        props = mass_properties(solid, resolution=int(resolution), density=density, units=units)
        facts["mass_properties"] = props.to_dict()
        lo, hi = solid.require_bounds()
        mlo, mhi = np.asarray(m.bounds[0::2]), np.asarray(m.bounds[1::2])
        facts["bounds"] = {"solid": [lo.tolist(), hi.tolist()], "mesh": [mlo.tolist(), mhi.tolist()]}
        bar.update(1)
        bar.set_description("validity")
        valid = check(m)
        rep = brep(solid, m)
        facts["validity"] = valid.to_dict()
        facts["brep"] = rep.to_dict()
        bar.update(1)
        bar.set_description("section")
        zc = float(0.5 * (lo[2] + hi[2]))
        sec = section(solid, f"z={zc:.6g}")
        _section_picture(sec, p("section.png"), f"section z = {zc:.4g}: area {sec.area:.6g} {units}^2, "
                                                f"{len(sec.loops)} loop(s)")
        paths["section"] = p("section.png")
        facts["section"] = {"plane": f"z={zc:.6g}", "area": sec.area, "loops": len(sec.loops),
                            "holes": int(sum(sec.holes)), "Ixx": sec.Ixx, "Iyy": sec.Iyy}
        bar.update(1)
        bar.set_description("drawings")
        from .. import drafting
        drafting.render(m, p("shaded.png"), style="shaded", view="iso", window_size=(900, 700))
        paths["shaded"] = p("shaded.png")
        facts["sheet"], extra = _drawing_sheet(solid, m, p("sheet.png"), name, resolution, units,
                                                       bool(units_assumed))
        paths["sheet"] = p("sheet.png")
        paths.update(extra)
        bar.update(1)
        bar.set_description("comparison")
        table = compare(solid, resolution=int(compare_resolution), reference=reference, progress=False)
        table.chart(p("compare.png"))
        from .claims import plot_grid_sweep
        plot_grid_sweep(table.context["grid_sweep"], p("occupancy.png"))
        paths["compare"], paths["occupancy"] = p("compare.png"), p("occupancy.png")
        facts["comparison"] = table.to_dict()
        bar.update(1)
        bar.set_description("pages")
        md = _markdown(name, facts, props, valid, rep, sec, table, units, units_assumed)
        paths["markdown"] = p("report.md")
        _write_text(paths["markdown"], md)
        pictures = {os.path.basename(v): _img(v) for v in paths.values() if v.endswith(".png")}
        paths["html"] = p("report.html")
        _write_text(paths["html"], _md_to_html(md, pictures))
        facts["seconds"] = time.perf_counter() - started
        facts["files"] = {k: os.path.basename(v) for k, v in paths.items()}
        paths["json"] = p("report.json")
        _write_text(paths["json"], json.dumps(facts, indent=1, default=_jsonable, allow_nan=False) + "\n")
        bar.update(1)
    return paths


def _jsonable(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


def _markdown(name, facts, props, valid, rep, sec, table, units, assumed):
    e = props.error
    lo, hi = facts["bounds"]["solid"]
    mlo, mhi = facts["bounds"]["mesh"]
    u = units + (" (assumed: the model declares no units)" if assumed else "")
    lines = [f"# {name}: report", "",
             f"Units: {u}. Density {props.density:g} kg/m^3.", "",
             "![shaded view](shaded.png)", "",
             "## Mass properties", "",
             "| quantity | value | +/- | unit |", "|---|---|---|---|",
             f"| volume (solid) | {props.volume:.9g} | {e.volume:.2g} | {units}^3 |",
             f"| mass | {props.mass:.9g} | {e.mass:.2g} | kg |",
             f"| area | {props.area:.9g} | {e.area:.2g} | {units}^2 |"]
    lines += [f"| centroid {a} | {props.centroid[i]:.9g} | {e.centroid[i]:.2g} | {units} |" for i, a in enumerate("xyz")]
    lines += [f"| principal I{k + 1} | {props.principal_moments[k]:.9g} | {e.principal_moments[k]:.2g} | "
              f"{props.inertia_unit} |" for k in range(3)]
    lines += ["", f"Bounds of the solid: ({', '.join(f'{v:.6g}' for v in lo)}) to ({', '.join(f'{v:.6g}' for v in hi)}); "
                  f"of its mesh: ({', '.join(f'{v:.6g}' for v in mlo)}) to ({', '.join(f'{v:.6g}' for v in mhi)}).", "",
              "## Validity and topology", "",
              f"Valid solid: {'yes' if valid.valid else 'NO'} (closed {valid.closed}, manifold {valid.manifold}, "
              f"oriented {valid.oriented}, bodies {valid.bodies}, genus {valid.genus}); mesh volume "
              f"{valid.volume:.9g} {units}^3 (the boundary mesh, {facts['mesh']['triangles']} triangles, "
              f"in {facts['mesh']['file']}).", "",
              f"B-rep with faces by CSG leaf: V = {rep.V}, E = {rep.E}, F = {rep.F}, L = {rep.L}, B = {rep.B}, "
              f"G = {rep.G}; F - E + V - L = {rep.euler_poincare[0]}, 2(B - G) = {rep.euler_poincare[1]}: "
              f"{'holds' if rep.holds else 'FAILS'}.", ""]
    lines += [f"- problem: {f}" for f in valid.flags]
    lines += ["## Section", "", f"Plane {facts['section']['plane']}: area {sec.area:.9g} {units}^2, "
              f"{len(sec.loops)} loop(s) ({int(sum(sec.holes))} holes), Ixx {sec.Ixx:.6g}, Iyy {sec.Iyy:.6g}.", "",
              "![section](section.png)", "", "## Drawing sheet", "", facts["sheet"] + ".", "",
              "![drawing sheet](sheet.png)", "", "## Representations compared", "", table.markdown(), "",
              "![storage and volume error](compare.png)", "",
              "![occupancy grid memory against error](occupancy.png)", ""]
    return "\n".join(lines)
