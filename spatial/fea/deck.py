"""Linear-static decks for CalculiX / Abaqus: material, supports, loads, outputs.

`write_static_deck` writes a complete input file that ``ccx`` runs as it
is: the mesh and its named sets (`spatial.fea.abaqus`), an isotropic
elastic material, a solid section on every element, one ``*STATIC`` step
with the named faces clamped (``*BOUNDARY``) and forces spread over named
faces, and requests for displacements, reactions and stresses in the
``.frd`` results file.

Units are the user's; the built-in materials (`MATERIALS`) are in mm, N,
MPa and t/mm^3, the usual consistent set for parts drawn in millimetres.

A force on a face is spread as a uniform traction ``F / A`` over the face's
boundary triangles and turned into *consistent* nodal loads: for a 3-node
triangle each corner takes a third of ``t A_i``; for a 6-node triangle
(10-node tetrahedra) the corners take nothing and each mid-edge node a
third (the integrals of the quadratic shape functions over a triangle are
0 at the corners and ``A/3`` at the mid-edge nodes).  The nodal loads add
up to the force exactly.

References
----------
O. C. Zienkiewicz, R. L. Taylor, *The Finite Element Method*, vol. 1,
6th ed., 2005, section 8.8 (consistent loads of quadratic triangles).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..files.atomic import atomic_write
from .abaqus import ELEMENT_SET, abaqus_names, inp_mesh_text, number_text

__all__ = ["Material", "MATERIALS", "parse_material", "parse_load", "face_nodal_loads", "static_deck_text",
           "write_static_deck"]


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material.

    Attributes
    ----------
    name : str
    E : float
        Young's modulus.
    nu : float
        Poisson's ratio, in (-1, 0.5).
    rho : float
        Density (0: none written).
    """

    name: str
    E: float
    nu: float
    rho: float = 0.0


#: Built-in materials in mm, N, MPa, t/mm^3.
MATERIALS = {
    "steel": Material("STEEL", 210000.0, 0.3, 7.85e-9),
    "aluminium": Material("ALUMINIUM", 70000.0, 0.33, 2.70e-9),
    "titanium": Material("TITANIUM", 114000.0, 0.34, 4.43e-9),
}


def parse_material(text) -> Material:
    """A `Material` from a name of `MATERIALS` or ``"E,nu"`` / ``"E,nu,rho"``.

    Examples
    --------
    >>> parse_material("steel").E
    210000.0
    >>> parse_material("70000,0.33,2.7e-9")
    Material(name='MATERIAL', E=70000.0, nu=0.33, rho=2.7e-09)
    """
    if isinstance(text, Material):
        return text
    if not isinstance(text, str):
        raise TypeError(f"material: expected a name or 'E,nu,rho', got {type(text).__name__}")
    key = text.strip().lower()
    if key in MATERIALS:
        return MATERIALS[key]
    parts = [p for p in key.split(",")]
    try:
        vals = [float(p) for p in parts]
    except ValueError:
        vals = []
    if len(vals) not in (2, 3):
        raise ValueError(f"material: expected one of {', '.join(MATERIALS)} or 'E,nu[,rho]', got {text!r}")
    E, nu = vals[0], vals[1]
    rho = vals[2] if len(vals) == 3 else 0.0
    if not (np.isfinite(E) and E > 0):
        raise ValueError(f"material: expected a positive Young's modulus E, got {E!r}")
    if not (-1.0 < nu < 0.5):
        raise ValueError(f"material: expected Poisson's ratio nu in (-1, 0.5), got {nu!r}")
    if not (np.isfinite(rho) and rho >= 0):
        raise ValueError(f"material: expected a density rho >= 0, got {rho!r}")
    return Material("MATERIAL", E, nu, rho)


def parse_load(text) -> tuple:
    """``"FACE=FX,FY,FZ"`` -> ``(face, (fx, fy, fz))``.

    Examples
    --------
    >>> parse_load("box_0.+x=0,0,-1000")
    ('box_0.+x', (0.0, 0.0, -1000.0))
    """
    m = re.fullmatch(r"\s*(.+?)\s*=\s*([^=]+)", str(text))
    vals = None
    if m:
        try:
            vals = tuple(float(v) for v in m.group(2).split(","))
        except ValueError:
            vals = None
    if not m or vals is None or len(vals) != 3 or not np.all(np.isfinite(vals)):
        raise ValueError(f"load: expected FACE=FX,FY,FZ (three numbers), got {text!r}")
    return m.group(1), vals


def _check_faces(mesh, faces, what):
    known = [k for k in mesh.face_sets if k != "surface"]
    for f in faces:
        if f not in mesh.face_sets:
            raise ValueError(f"{what}: no face named {f!r}; the mesh has {', '.join(known) or 'none'}")


def face_nodal_loads(mesh, face, force):
    """Consistent nodal loads of `force` spread uniformly (by area) over `face`.

    Parameters
    ----------
    mesh : TetMesh
    face : str
        A name of ``mesh.face_sets``.
    force : (3,) float
        The total force.

    Returns
    -------
    nodes : (k,) int
        Node indices (0-based).
    loads : (k, 3) float
        Force on each node; ``loads.sum(axis=0) == force``.
    """
    from .model import _side_nodes

    _check_faces(mesh, [face], "load")
    force = np.asarray(force, dtype=np.float64).reshape(3)
    sel = np.asarray(mesh.face_sets[face])
    tri = _side_nodes(np.asarray(mesh.tets), np.asarray(mesh.boundary_element)[sel],
                      np.asarray(mesh.boundary_side)[sel])
    p = np.asarray(mesh.points, dtype=np.float64)
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    total = float(area.sum())
    if not total > 0:
        raise ValueError(f"load: face {face!r} has no area")
    share = area / total  # fraction of the force on each triangle
    # Quadratic triangles: nothing on the corners, a third on each mid-edge node.
    carry = tri[:, 3:] if tri.shape[1] == 6 else tri
    w = np.repeat(share / 3.0, 3)
    nodes, inv = np.unique(carry.reshape(-1), return_inverse=True)
    frac = np.bincount(inv.reshape(-1), weights=w, minlength=nodes.size)
    return nodes, frac[:, None] * force[None, :]


def static_deck_text(mesh, *, material, fix=(), loads=(), heading="implicad linear-static analysis"):
    """The text of a linear-static CalculiX / Abaqus deck and the set-name mapping.

    Parameters
    ----------
    mesh : TetMesh
    material : Material or str
        See `parse_material`.
    fix : sequence of str
        Faces clamped in x, y and z.
    loads : sequence of (str, (3,) float)
        Faces and the total force on each.
    heading : str

    Returns
    -------
    text : str
    names : dict
        Face name -> node-set name in the deck (``box_0.-x`` -> ``BOX_0_MX``).
    """
    material = parse_material(material)
    fix = list(fix)
    loads = [(f, tuple(float(v) for v in vec)) for f, vec in loads]
    _check_faces(mesh, fix, "fix")
    _check_faces(mesh, [f for f, _ in loads], "load")
    if not fix:
        raise ValueError("fix: expected at least one clamped face (the static problem is singular otherwise)")
    regions = [k for k in mesh.face_sets if k != "surface"]
    names = abaqus_names(regions)
    n_nodes = len(mesh.points)
    total = np.zeros((n_nodes, 3))
    for face, vec in loads:
        nodes, f = face_nodal_loads(mesh, face, vec)
        np.add.at(total, nodes, f)
    out = [f"*HEADING\n{heading}", inp_mesh_text(mesh, names).rstrip("\n")]
    mat = material.name.upper()
    out.append(f"*MATERIAL, NAME={mat}\n*ELASTIC\n{material.E:.13g}, {material.nu:.13g}")
    if material.rho > 0:
        out.append(f"*DENSITY\n{material.rho:.13g}")
    out.append(f"*SOLID SECTION, ELSET={ELEMENT_SET}, MATERIAL={mat}")
    out.append("*STEP\n*STATIC")
    out.append("*BOUNDARY\n" + "\n".join(f"{names[f]}, 1, 3, 0." for f in fix))
    nz = np.nonzero(np.abs(total) > 0)
    if nz[0].size:
        scale = float(np.abs(total).max())
        vals = number_text(total[nz], scale * 1e-3)
        lines = np.char.add(np.char.add(np.char.add((nz[0] + 1).astype(str), ", "),
                                        np.char.add((nz[1] + 1).astype(str), ", ")), vals)
        out.append("*CLOAD\n" + "\n".join(lines.tolist()))
    out.append("*NODE FILE\nU, RF\n*EL FILE\nS\n*END STEP")
    return "\n".join(out) + "\n", names


def write_static_deck(mesh, path, *, material, fix=(), loads=()) -> dict:
    """Write a ready-to-run linear-static deck (see `static_deck_text`) atomically.

    Returns
    -------
    dict
        Face name -> node-set name in the deck.

    Examples
    --------
    >>> from implicit import box
    >>> from spatial.fea import tet_mesh
    >>> m = tet_mesh(box((100, 10, 10), center=(50, 0, 0)), size=5, order=2)   # doctest: +SKIP
    >>> write_static_deck(m, "beam.inp", material="steel", fix=["box_0.-x"],
    ...                   loads=[("box_0.+x", (0, 0, -1000))])["box_0.-x"]    # doctest: +SKIP
    'BOX_0_MX'
    """
    text, names = static_deck_text(mesh, material=material, fix=fix, loads=loads)

    def write(tmp):
        with open(tmp, "w", encoding="ascii") as fh:
            fh.write(text)

    atomic_write(path, write)
    return names
