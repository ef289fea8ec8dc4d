"""MED files (Salome, Code_Aster): groups of faces and nodes as MED families, read back by h5py and gmsh."""

import warnings

import h5py
import numpy as np
import pytest

from implicit.families import instance
from spatial.fea import tet_mesh, write_fea
from spatial.fea.files import set_name, set_names
from spatial.fea.quality import tet_volumes

STEP = "-0000000000000000001-0000000000000000001"


@pytest.fixture(scope="module", params=[1, 2], ids=["tet4", "tet10"])
def plate(request):
    part = instance("hole_plate", length=40, width=20, thickness=4, hole_diameter=6, rows=1, cols=2, margin=10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return tet_mesh(part, size=3.0, order=request.param, allow_poor=True)


def _groups(f, kind):
    """{family number: [group names]} of the nodes (NOEUD) or elements (ELEME)."""
    out = {}
    for fam in f[f"FAS/mesh/{kind}"].values():
        names = fam["GRO/NOM"][()]
        out[int(fam.attrs["NUM"])] = [bytes(row[row != 0].astype(np.uint8)).decode() for row in names]
    return out


def test_med_holds_every_face_set_as_a_group_with_its_triangles_and_nodes(plate, tmp_path):
    path = tmp_path / "plate.med"
    write_fea(plate, path)
    cell = "T10" if plate.order == 2 else "TE4"
    tri = "TR6" if plate.order == 2 else "TR3"
    with h5py.File(path, "r") as f:
        step = f[f"ENS_MAA/mesh/{STEP}"]
        assert step["NOE/COO"].attrs["NBR"] == len(plate.points)
        assert step[f"MAI/{cell}"]["NOD"].attrs["NBR"] == len(plate.tets)
        assert step[f"MAI/{tri}"]["NOD"].attrs["NBR"] == len(plate.boundary)
        elem_groups = _groups(f, "ELEME")
        node_groups = _groups(f, "NOEUD")
        tri_fam = step[f"MAI/{tri}/FAM"][()]
        node_fam = step["NOE/FAM"][()]
        assert set(step[f"MAI/{cell}/FAM"][()]) == {-1} and elem_groups[-1] == ["volume"]
        assert all(num < 0 for num in elem_groups) and all(num > 0 for num in node_groups)
        for face in ("hole_1.wall", "hole_2.wall", "plate.top", "plate.bottom"):
            g = set_name(face)
            n_tri = sum(int((tri_fam == num).sum()) for num, gs in elem_groups.items() if g in gs)
            n_nodes = sum(int((node_fam == num).sum()) for num, gs in node_groups.items() if g in gs)
            assert n_tri == len(plate.face_sets[face]) > 0
            assert n_nodes == len(plate.node_sets[face]) > 0
        # the corners in MED order: the first three seen from the fourth turn clockwise (negative VTK volume)
        nod = step[f"MAI/{cell}/NOD"][()].reshape(-1, len(plate.tets)).T - 1
        assert np.all(tet_volumes(plate.points, nod[:, :4]) < 0)
        assert sorted(set(nod[:, 4:].reshape(-1).tolist())) == sorted(set(plate.tets[:, 4:].reshape(-1).tolist())) \
            if plate.order == 2 else True
    assert set_names(plate, path)["hole_1.wall"] == "group hole_1_wall"


def _gmsh_read(gmsh, path):
    gmsh.clear()
    gmsh.open(str(path))
    _, tags, _ = gmsh.model.mesh.getElements(3)
    return tags[0], gmsh.model.mesh.getElementQualities(tags[0], "minSICN")


def test_gmsh_opens_the_med_file_with_the_groups_and_the_elements_of_the_msh_file(plate, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    med, msh = tmp_path / "plate.med", tmp_path / "plate.msh"
    write_fea(plate, med)
    write_fea(plate, msh)
    gmsh.initialize(["-nopopup"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        _, sicn_msh = _gmsh_read(gmsh, msh)
        tags, sicn = _gmsh_read(gmsh, med)
        names = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
        assert {"volume", "hole_1_wall", "hole_2_wall", "plate_top", "plate_bottom"} <= set(names)
        d, t = names["hole_1_wall"]
        tris = sum(len(tags) for e in gmsh.model.getEntitiesForPhysicalGroup(d, t)
                   for tags in gmsh.model.mesh.getElements(d, e)[1])
        assert tris == len(plate.face_sets["hole_1.wall"])
        # MED's node order read back by gmsh gives the very elements of the .msh file (an order
        # mistake turns elements inside out or bends them: their SICN would change)
        assert len(sicn) == len(plate.tets)
        np.testing.assert_allclose(np.sort(sicn), np.sort(sicn_msh), atol=1e-9)
        # curved elements too: the Bezier sign test leaves none that gmsh finds folded
        assert sicn.min() > 0
    finally:
        gmsh.finalize()
