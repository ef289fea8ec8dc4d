"""The house rules of docs/ARCHITECTURE.md, checked on the source itself.

Every import of every module, lazy ones inside functions included, is read with
`ast`; the graph must have no circle, no package may import one above it
(parametric <- implicit <- spatial), and inside `spatial` a room imports only from
its own room or rooms below it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("parametric", "implicit", "spatial")
PACKAGE_RANK = {"parametric": 0, "implicit": 1, "spatial": 2}

#: Rooms of `spatial`, bottom to top (docs/ARCHITECTURE.md). A module may import from a room
#: of lower or equal rank; the package's own `__init__` sits above every room.
ROOM_RANK = {
    "files": 0,
    "cells": 1,
    "meshing": 2,
    "analysis": 3,
    "convert": 4,
    "fea": 5,
    "drafting": 6, "manufacturing": 6, "inspection": 6, "distributed": 6,
    "compare": 7,
    "cli": 8,
}
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join(parts)] = path
    return found


MODULES = _modules()


def _imports(name: str, path: Path) -> set[str]:
    """The project modules that module `name` imports (anywhere in its body)."""
    is_package = path.name == "__init__.py"
    here = name.split(".") if is_package else name.split(".")[:-1]
    targets = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                targets.add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[:len(here) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            for alias in node.names:
                child = f"{module}.{alias.name}"
                # `from pkg import mod` imports the submodule; `from pkg import name` the package.
                targets.add(child if child in MODULES else module)
    targets |= _lazy_targets(here, path)
    return {t for t in targets if t in MODULES and t != name}


def _lazy_targets(here: list[str], path: Path) -> set[str]:
    """The modules a package's table of lazy names (``_LAZY = {name: (".room", attribute)}``,
    `spatial.files.lazy`) imports on first use: edges of the graph like any import."""
    targets = set()
    for node in ast.parse(path.read_text(), str(path)).body:
        if not (isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict)
                and any(isinstance(t, ast.Name) and t.id == "_LAZY" for t in node.targets)):
            continue
        for value in node.value.values:
            where = value.elts[0].value if isinstance(value, ast.Tuple) else value.value
            level = len(where) - len(where.lstrip("."))
            base = here[:len(here) - level + 1] if level else []
            targets.add(".".join(base + [where.lstrip(".")]))
    return targets


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _room(name: str):
    parts = name.split(".")
    if parts[0] != "spatial":
        return None
    if len(parts) == 1:
        return "__top__"
    return parts[1] if parts[1] in ROOM_RANK else "__loose__"


def test_every_spatial_module_lives_in_a_room():
    loose = [name for name in MODULES if _room(name) == "__loose__"]
    assert not loose, f"modules of spatial outside every room: {loose}"


def test_no_upward_imports():
    bad = []
    for name, targets in GRAPH.items():
        for target in targets:
            if PACKAGE_RANK[target.split(".")[0]] > PACKAGE_RANK[name.split(".")[0]]:
                bad.append(f"{name} -> {target} (package above)")
                continue
            room, target_room = _room(name), _room(target)
            if room is None or target_room is None or room == "__top__":
                continue
            if target_room == "__top__" or ROOM_RANK[target_room] > ROOM_RANK[room]:
                bad.append(f"{name} -> {target} (room above)")
    assert not bad, "upward imports:\n" + "\n".join(sorted(bad))


def test_application_rooms_do_not_import_each_other():
    apps = {room for room, rank in ROOM_RANK.items() if rank == 6}
    bad = [f"{n} -> {t}" for n, ts in GRAPH.items() for t in ts
           if _room(n) in apps and _room(t) in apps and _room(n) != _room(t)]
    assert not bad, bad


def _cycles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    counter = 0
    for root in GRAPH:
        if root in index:
            continue
        work = [(root, iter(sorted(GRAPH[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(GRAPH[child]))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_import_circles():
    assert _cycles() == []


def test_the_cycle_finder_finds_a_circle(monkeypatch):
    monkeypatch.setitem(GRAPH, "spatial.files", GRAPH["spatial.files"] | {"spatial.cli"})
    monkeypatch.setitem(GRAPH, "spatial.cli", GRAPH["spatial.cli"] | {"spatial.files"})
    assert any("spatial.cli" in c and "spatial.files" in c for c in _cycles())


@pytest.mark.parametrize("name", sorted(MODULES))
def test_source_files_stay_small(name):
    lines = MODULES[name].read_text().count("\n")
    assert lines <= MAX_LINES, f"{MODULES[name].relative_to(ROOT)} has {lines} lines (at most {MAX_LINES})"


def test_rooms_say_what_they_hold():
    for room in ROOM_RANK:
        init = ROOT / "spatial" / room / "__init__.py"
        if not init.exists():
            continue
        doc = ast.get_docstring(ast.parse(init.read_text()))
        assert doc and len(doc) > 40, f"spatial/{room}/__init__.py needs a docstring saying what the room holds"


def test_evaluator_not_imported_by_nodes_at_module_level():
    for name, path in MODULES.items():
        if not name.startswith("implicit.") or name.startswith("implicit.evaluate"):
            continue
        tree = ast.parse(path.read_text())
        for node in tree.body:
            if isinstance(node, ast.ImportFrom) and node.module and "evaluate" in node.module.split("."):
                pytest.fail(f"{name} imports the evaluator at module level")


def test_lazy_tables_are_edges_of_the_graph():
    assert {"spatial.fea", "spatial.compare.report", "spatial.cli"} <= GRAPH["spatial"]


def test_public_names_of_spatial_kept():
    import spatial

    for name in ("mesh", "mass_properties", "MassProperties", "check", "topology", "Octree", "OccupancyGrid",
                 "save_mesh", "load_mesh", "mesh_to_solid", "save_vdb", "load_vdb", "Section", "check_assembly",
                 "surface_for_fea", "tet_mesh", "write_fea", "fit_star_surface", "loft_sections", "FULL", "EMPTY",
                 "BOUNDARY"):
        assert hasattr(spatial, name), name
