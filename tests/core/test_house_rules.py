"""The house rules a newcomer relies on, checked on the sources.

A library function takes at most 6 positional parameters (keyword-only beyond), its body and
its docstring fit on a screen (60 lines each), each ``DEFAULT_*`` is assigned in one module,
``import comcore`` stays light, and the docs stay a size a person reads.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.source  # reads the packages' source files

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("comcore", "predictors", "simulators")
#: The most positional parameters a function takes (``self`` and ``cls`` aside).
MAX_POSITIONAL = 6
#: The most lines of a function's body (after its docstring) and of a docstring.
MAX_LINES = 60
#: The most comcore modules ``import comcore`` loads, and the application layers it must not.
MAX_IMPORTED = 45
APPLICATION = ("goal", "recordings", "ros", "plot", "cli", "bench", "testing")
#: The docs' size: in all, and per tutorial or how-to page.
MAX_DOCS_WORDS = 45_000
MAX_PAGE_WORDS = 1_500


def functions(root: Path, packages=PACKAGES):
    """(module path, function node) for every function of the packages."""
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in ast.walk(tree):
                if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    yield path.relative_to(root).as_posix(), node


def positional(node) -> int:
    names = [a.arg for a in node.args.posonlyargs + node.args.args]
    return len([n for n in names if n not in ("self", "cls")])


def body_and_docstring_lines(node) -> tuple[int, int]:
    body, doc = node.body, 0
    if ast.get_docstring(node, clean=False) is not None:
        doc = body[0].end_lineno - body[0].lineno + 1
        if len(body) == 1:
            return 0, doc
        body = body[1:]
    return node.end_lineno - body[0].lineno + 1, doc


def broken_rules(root: Path, packages=PACKAGES) -> dict[str, list[str]]:
    out = {"positional": [], "body": [], "docstring": []}
    for module, node in functions(root, packages):
        where = f"{module}:{node.lineno} {node.name}"
        if positional(node) > MAX_POSITIONAL:
            out["positional"].append(f"{where} ({positional(node)})")
        body, doc = body_and_docstring_lines(node)
        if body > MAX_LINES:
            out["body"].append(f"{where} ({body} lines)")
        if doc > MAX_LINES:
            out["docstring"].append(f"{where} ({doc} lines)")
    return out


def test_no_function_takes_more_than_6_positional_parameters():
    found = broken_rules(ROOT)["positional"]
    assert not found, f"make the parameters past the 6th keyword-only: {found}"


def test_no_function_body_is_over_60_lines():
    found = broken_rules(ROOT)["body"]
    assert not found, f"split these functions: {found}"


def test_no_docstring_is_over_60_lines():
    found = broken_rules(ROOT)["docstring"]
    assert not found, f"say what these do, in fewer lines: {found}"


def long_module_and_class_docstrings(root: Path, packages=PACKAGES) -> list[str]:
    out = []
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in [tree, *(n for n in ast.walk(tree) if isinstance(n, ast.ClassDef))]:
                first = node.body[0] if node.body else None
                if ast.get_docstring(node, clean=False) is None:
                    continue
                lines = first.end_lineno - first.lineno + 1
                if lines > MAX_LINES:
                    out.append(f"{path.relative_to(root)} {getattr(node, 'name', '(module)')}")
    return out


def test_no_module_or_class_docstring_is_over_60_lines():
    found = long_module_and_class_docstrings(ROOT)
    assert not found, f"say what these hold, in fewer lines: {found}"


def test_the_rules_find_what_they_look_for(tmp_path):
    (tmp_path / "pkg").mkdir()
    doc = '    """' + "\n".join(["A docstring."] + ["    more"] * MAX_LINES) + '\n    """\n'
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_LINES))
    (tmp_path / "pkg" / "m.py").write_text(
        f"def ok(a, b, c, d, e, f, *, g=1):\n    return a\n\n\n"
        f"class C:\n    def many(self, a, b, c, d, e, f, g):\n        return a\n\n\n"
        f"def long():\n{body}\n    return x0\n\n\n"
        f"def wordy():\n{doc}    return 1\n"
    )
    found = broken_rules(tmp_path, ["pkg"])
    assert found == {
        "positional": ["pkg/m.py:6 many (7)"],
        "body": ["pkg/m.py:10 long (61 lines)"],
        "docstring": [f"pkg/m.py:{14 + MAX_LINES} wordy ({MAX_LINES + 2} lines)"],
    }


def test_each_default_is_assigned_in_one_module():
    where: dict[str, set[str]] = {}
    pattern = re.compile(r"^(DEFAULT_[A-Z0-9_]+)\s*(?::[^=]+)?=", re.M)
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            for name in pattern.findall(path.read_text(encoding="utf-8")):
                where.setdefault(name, set()).add(path.relative_to(ROOT).as_posix())
    twice = {name: sorted(paths) for name, paths in where.items() if len(paths) > 1}
    assert where, "no DEFAULT_ found: the scan is broken"
    assert not twice, f"import these defaults from the one module that assigns them: {twice}"


def test_import_comcore_stays_light():
    code = "import sys, comcore; print('\\n'.join(m for m in sys.modules if m.startswith('comcore')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = out.stdout.split()
    assert len(loaded) <= MAX_IMPORTED, f"{len(loaded)} modules: {loaded}"
    heavy = [m for m in loaded if m.split(".")[1:2] and m.split(".")[1] in APPLICATION]
    assert not heavy, f"loaded on first use only: {heavy}"


def docs_pages():
    return sorted((ROOT / "docs").rglob("*.md"))


def test_the_docs_stay_a_size_a_person_reads():
    words = {p.relative_to(ROOT).as_posix(): len(p.read_text().split()) for p in docs_pages()}
    assert words, "no docs found"
    assert sum(words.values()) <= MAX_DOCS_WORDS, sum(words.values())
    long = {p: n for p, n in words.items()
            if p.startswith(("docs/tutorials/", "docs/how-to/")) and n > MAX_PAGE_WORDS}
    assert not long, f"split or tighten these pages: {long}"
