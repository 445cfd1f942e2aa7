"""Honest imports: no import cycle among the packages' modules, function-local imports included.

A cycle held apart by an import inside a function still ties the modules together
(each needs the other loaded to work) and breaks as soon as someone moves the
import to the top. The graph is read statically, with ``ast``, from every
``import`` statement of every module, wherever it stands.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

pytestmark = pytest.mark.source  # reads the packages' source files

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("comcore", "simulators", "predictors")


def module_files(root: Path, packages) -> dict[str, Path]:
    """``{dotted module name: file}`` of every module of ``packages`` under ``root``."""
    out = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            out[".".join(parts)] = path
    return out


def imported_modules(name: str, path: Path, modules) -> set[str]:
    """The modules among ``modules`` that ``name``'s import statements load, anywhere in it."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            # `from pkg import mod` loads the module pkg.mod; `from mod import name` loads mod
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base
                       for a in node.names]  # fmt: skip
        else:
            continue
        for target in targets:
            while target and target not in modules:  # `import a.b.c` of a non-module: its parent
                target = target.rpartition(".")[0]
            if target:
                found.add(target)
    found.discard(name)
    return found


def import_graph(root: Path, packages) -> dict[str, set[str]]:
    modules = module_files(root, packages)
    return {name: imported_modules(name, path, modules) for name, path in modules.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_module_of_the_packages_is_in_an_import_cycle():
    graph = import_graph(ROOT, PACKAGES)
    assert len(graph) > 60  # the walk found the packages
    assert "comcore._checks" in graph["comcore._mask"]  # and reads their imports
    found = cycles(graph)
    assert not found, "import cycles (function-local imports included):\n" + "\n".join(
        " <-> ".join(c) for c in found
    )


@pytest.mark.parametrize("local", [False, True])
def test_a_cycle_is_found_even_through_a_function_local_import(tmp_path, local):
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from ._a import f\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "_a.py").write_text("from .sub import _b\n\ndef f():\n    return _b.g()\n")
    back = "from .. import _a" if not local else "def g():\n    from .._a import f\n    return f"
    (pkg / "sub" / "_b.py").write_text(back + "\n")
    assert cycles(import_graph(tmp_path, ["pkg"])) == [["pkg._a", "pkg.sub._b"]]


def test_a_package_importing_its_modules_is_no_cycle(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from ._a import f\nfrom . import _b\n")
    (pkg / "_a.py").write_text("import numpy\nfrom ._b import g\n")
    (pkg / "_b.py").write_text("import os.path\n")
    graph = import_graph(tmp_path, ["pkg"])
    assert graph == {"pkg": {"pkg._a", "pkg._b"}, "pkg._a": {"pkg._b"}, "pkg._b": set()}
    assert cycles(graph) == []


#: The layers of comcore, lowest first. A module may import the modules of its own layer's
#: subpackage and of the layers below it, never above, and never a peer of its own layer.
#: ``comcore`` here is the base: the top-level modules (types, mask, errors, conventions,
#: checks); the package's ``__init__`` is the facade over all of them and is left out.
LAYERS = (
    ("comcore",),
    ("comcore.geometry",),
    ("comcore.vt", "comcore.testing"),
    ("comcore.motion", "comcore.camera", "comcore.recordings", "comcore.paper"),
    ("comcore.active", "comcore.ros"),
    ("comcore.goal",),
    ("comcore.plot",),
    ("comcore.cli", "comcore.bench", "comcore.__main__"),
)
#: Only the application layer (the last) may import these packages.
APPLICATION_ONLY = ("simulators", "predictors")


def subpackage(module: str) -> str:
    """The subpackage of LAYERS that ``module`` belongs to (``comcore`` for the base)."""
    for layer in LAYERS:
        for pkg in layer:
            if module == pkg or module.startswith(pkg + "."):
                if pkg != "comcore":
                    return pkg
    return "comcore" if module.startswith("comcore") else module.partition(".")[0]


def layer_of(module: str) -> int:
    pkg = subpackage(module)
    return next(i for i, layer in enumerate(LAYERS) if pkg in layer)


def layer_violations(graph: dict[str, set[str]]) -> list[str]:
    out = []
    for name, targets in sorted(graph.items()):
        if not name.startswith("comcore") or name == "comcore":
            continue
        here, pkg = layer_of(name), subpackage(name)
        for target in sorted(targets):
            if target.partition(".")[0] in APPLICATION_ONLY:
                if here != len(LAYERS) - 1:
                    out.append(f"{name} imports {target} (only the application layer may)")
                continue
            if not target.startswith("comcore") or (target == "comcore" and here == len(LAYERS) - 1):
                continue
            if target == "comcore":
                out.append(f"{name} imports the facade comcore (import the module instead)")
                continue
            there, other = layer_of(target), subpackage(target)
            peer = there == here and other != pkg and here != len(LAYERS) - 1
            if there > here or peer:
                out.append(f"{name} (layer {here}) imports {target} (layer {there})")
    return out


def test_no_module_of_comcore_imports_against_the_layers():
    graph = import_graph(ROOT, PACKAGES)
    assert "comcore.vt._voting" in graph["comcore.paper._progressive"]  # the walk reads imports
    found = layer_violations(graph)
    assert not found, "imports against the layers:\n" + "\n".join(found)


def test_a_low_layer_importing_a_high_one_is_found():
    graph = {
        "comcore.geometry._contacts": {"comcore.active._session"},
        "comcore.camera._image": {"comcore.motion._pressure"},
        "comcore.vt._voting": {"simulators._robot"},
        "comcore.cli.estimate": {"simulators._robot", "comcore.goal._session"},
        "comcore.goal._session": {"comcore.active._grid", "comcore._mask"},
    }
    assert layer_violations(graph) == [
        "comcore.camera._image (layer 3) imports comcore.motion._pressure (layer 3)",
        "comcore.geometry._contacts (layer 1) imports comcore.active._session (layer 4)",
        "comcore.vt._voting imports simulators._robot (only the application layer may)",
    ]


def test_every_module_of_comcore_is_in_a_layer():
    for name in module_files(ROOT, ["comcore"]):
        layer_of(name)  # StopIteration if a new subpackage is missing from LAYERS


#: A family: three or more modules in one folder whose names share a prefix (``_goal_costs``,
#: ``_goal_planner``, ``_goal_session``): a subpackage waiting to be made.
FAMILY_SIZE = 3


def prefix_families(root: Path, packages) -> dict[str, list[str]]:
    found = {}
    for package in packages:
        for folder in sorted({p.parent for p in (root / package).rglob("*.py")}):
            stems = [p.stem.lstrip("_") for p in folder.glob("*.py") if p.stem != "__init__"]
            by_prefix = {}
            for stem in stems:
                if "_" in stem:
                    by_prefix.setdefault(stem.split("_")[0], []).append(stem)
            for prefix, names in by_prefix.items():
                if len(names) >= FAMILY_SIZE:
                    found[f"{folder.relative_to(root)}/_{prefix}_*"] = sorted(names)
    return found


def test_no_folder_of_the_packages_holds_a_prefix_family():
    found = prefix_families(ROOT, PACKAGES)
    assert not found, f"make these families subpackages: {found}"


def test_a_prefix_family_is_found(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    for stem in ("__init__", "_goal_costs", "_goal_planner", "_goal_session", "_grid", "_gold"):
        (pkg / f"{stem}.py").write_text("")
    assert prefix_families(tmp_path, ["pkg"]) == {
        "pkg/_goal_*": ["goal_costs", "goal_planner", "goal_session"]
    }


#: At most 12 modules directly in comcore/: the base types; everything else in a subpackage.
MAX_TOP_MODULES = 12
def test_comcore_keeps_at_most_12_modules_at_its_top():
    top = sorted(p.name for p in (ROOT / "comcore").glob("*.py"))
    assert len(top) <= MAX_TOP_MODULES, top


#: The public names predictors and simulators may use: nothing private of comcore.
def private_uses(root: Path, packages) -> list[str]:
    out = []
    for name, path in module_files(root, packages).items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            mods = []
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                mods = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            for mod in mods:
                if mod.startswith("comcore") and any(p.startswith("_") for p in mod.split(".")):
                    out.append(f"{name}: {mod}")
    return out


def test_predictors_and_simulators_use_only_public_names_of_comcore():
    assert not private_uses(ROOT, ["predictors", "simulators"])
