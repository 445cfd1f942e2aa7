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

ROOT = Path(__file__).resolve().parents[1]
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


#: The house rule (docs/architecture.md, issue 19): a module a newcomer opens fits in one read.
MAX_MODULE_LINES = 400


def test_no_module_of_comcore_is_over_400_lines():
    long = {
        str(path.relative_to(ROOT)): n
        for path in sorted((ROOT / "comcore").rglob("*.py"))
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert not long, f"split these modules (over {MAX_MODULE_LINES} lines): {long}"
