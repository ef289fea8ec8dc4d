"""The examples gallery: every script's main() runs at a small size and writes its picture."""

import importlib
import os
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples")
SCRIPTS = ["hermite_curve", "bezier_properties", "bspline_local_control", "nurbs_circle", "exact_conics",
           "coons_patch", "bicubic_patch", "bezier_bspline_surfaces", "block_cylinder_booleans", "csg_tree",
           "seven_schemes", "wireframe_vs_solid", "cells_vs_occupancy", "assembly_interference",
           "instancing_family", "euler_poincare"]
#: Pictures written besides the script's own.
EXTRA = {"wireframe_vs_solid": ["wireframe_ambiguity"], "instancing_family": ["part_library"]}


@pytest.fixture(scope="module", autouse=True)
def _on_path():
    sys.path.insert(0, EXAMPLES)
    yield
    sys.path.remove(EXAMPLES)


@pytest.mark.parametrize("name", SCRIPTS)
def test_gallery_script_writes_its_picture(name, tmp_path):
    module = importlib.import_module(name)
    path = module.main(out_dir=tmp_path, small=True)
    assert os.path.basename(path) == f"{name}.png"
    for picture in [name] + EXTRA.get(name, []):
        f = tmp_path / f"{picture}.png"
        assert f.stat().st_size > 5_000, picture
        assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_every_script_is_in_the_readme_with_its_picture():
    text = open(os.path.join(EXAMPLES, "README.md"), encoding="utf-8").read()
    for name in SCRIPTS + [p for extra in EXTRA.values() for p in extra]:
        assert f"pictures/{name}.png" in text, name
    for name in SCRIPTS:
        assert os.path.exists(os.path.join(EXAMPLES, f"{name}.py"))
