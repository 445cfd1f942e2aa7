"""The reference documents every public name once.

docs/reference/*.md hold mkdocstrings directives (``::: comcore.geometry`` with an explicit
``members:`` list, or ``::: simulators.MujocoRobot`` for one object). Every name in the
``__all__`` of each public namespace must be documented by exactly one directive entry,
across all the pages: a name re-exported by several namespaces (``comcore.sample_pushes`` is
``comcore.geometry.sample_pushes``) is the same object and is documented once, where it is
defined. Read statically from the pages; the objects are imported to tell re-exports apart.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import pytest

from tests.docs.test_docs import missing_extra

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "docs" / "reference"

#: The namespaces whose ``__all__`` the reference documents.
PUBLIC = (
    "comcore",
    "comcore.checks",
    "comcore.conventions",
    "comcore.geometry",
    "comcore.vt",
    "comcore.paper",
    "comcore.motion",
    "comcore.camera",
    "comcore.recordings",
    "comcore.recordings.mit_push",
    "comcore.recordings.bag",
    "comcore.active",
    "comcore.goal",
    "comcore.ros",
    "comcore.plot",
    "comcore.testing.strategies",
    "predictors",
    "predictors.oracle",
    "predictors.ellipsoid",
    "predictors.anp",
    "simulators",
)
#: Public-looking modules with an ``__all__`` that the reference leaves out, and why.
NOT_REFERENCED = {
    "comcore.testing": "its one name is the strategies module, documented by its members",
    "comcore.cli": "the command line: documented by `comcore --help` and the how-to pages",
    "comcore.cli.demo": "a subcommand",
    "comcore.cli.estimate": "a subcommand",
    "comcore.bench": "the benchmark harness: docs/how-to/benchmark.md",
    "comcore.bench.command": "a subcommand",
    "predictors.anp.data": "the ANP's training data (python -m predictors.anp.train)",
    "predictors.anp.evaluate": "a script",
    "predictors.anp.features": "the ANP's internals",
    "predictors.anp.model": "re-exported by predictors.anp, documented there",
    "predictors.anp.predictor": "re-exported by predictors.anp, documented there",
    "predictors.anp.shapes": "the ANP's training shapes",
    "predictors.anp.train": "a script",
    "simulators.tag_frames": "the frame renderer of the tag tests, benchmark and how-to",
}
PACKAGES = ("comcore", "predictors", "simulators")

DIRECTIVE = re.compile(r"^::: *(\S+)[ \t]*\n((?:[ \t]+.*\n|[ \t]*\n)*)", re.M)
PRIMITIVE = (int, float, str, bytes, bool, tuple, frozenset, type(None))


def entries(text: str) -> list[tuple[str, str]]:
    """The ``(dotted path, kind)`` each directive of a page documents.

    ``::: pkg`` with ``members: [a, b]`` gives ``(pkg.a, "member")`` and ``(pkg.b, "member")``;
    with ``members: false``, ``(pkg, "docstring")``: the module's own docstring only. A
    directive without a ``members`` option gives ``(path, "bare")``: one object, or, for a
    module, whatever griffe finds in it, which :func:`documented` refuses.
    """
    out = []
    for m in DIRECTIVE.finditer(text):
        target, options = m.group(1), m.group(2)
        lines = options.splitlines()
        members = None
        for i, line in enumerate(lines):
            key = re.match(r"^(\s*)members:\s*(.*)$", line)
            if key:
                indent, rest = len(key.group(1)), key.group(2).strip()
                if rest in ("false", "False", "[]"):
                    members = []
                elif rest.startswith("["):
                    members = [n.strip() for n in rest.strip("[]").split(",") if n.strip()]
                else:
                    members = []
                    for item in lines[i + 1 :]:
                        item_m = re.match(r"^(\s*)- *(\S+)\s*$", item)
                        if not item_m or len(item_m.group(1)) <= indent - 1:
                            break
                        members.append(item_m.group(2))
                break
        if members is None:
            out.append((target, "bare"))
        elif not members:
            out.append((target, "docstring"))
        else:
            out.extend((f"{target}.{name}", "member") for name in members)
    return out


def resolve(path: str):
    """The object a dotted path names: the longest importable module, then attributes."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError as e:
            if e.name and ".".join(parts[:cut]).startswith(e.name):
                continue  # not a module: an attribute of a shorter one
            raise
        for attr in parts[cut:]:
            obj = getattr(obj, attr)
        return obj
    raise ModuleNotFoundError(path)



def obj_name_of(path: str) -> str:
    return path.rpartition(".")[2]


def documented(pages: dict[str, str]) -> list[tuple[str, str, object]]:
    """``(page, path, object)`` for every object the pages' directives document."""
    out = []
    for page, text in sorted(pages.items()):
        for path, kind in entries(text):
            if kind == "docstring":
                continue
            out.append((page, path, checked(page, path, kind, resolve(path))))
    return out


def checked(page: str, path: str, kind: str, obj):
    """``obj``, unless a bare directive names a module (it would document all it finds)."""
    if kind == "bare" and inspect.ismodule(obj):
        raise AssertionError(f"{page}: `::: {path}` needs an explicit members: list")
    return obj


def problems(module: str, names, docs: list[tuple[str, str, object]]) -> list[str]:
    """What is wrong with the documentation of ``module``'s ``names``: missing or repeated."""
    mod = importlib.import_module(module)
    out = []
    for name in names:
        obj = getattr(mod, name)
        where = [
            f"{page}: {path}"
            for page, path, found in docs
            if (found is obj and not isinstance(obj, PRIMITIVE))
            or (isinstance(obj, PRIMITIVE) and found is obj and obj_name_of(path) == name)
        ]
        if len(where) != 1:
            out.append(f"{module}.{name} is documented {len(where)} times: {where}")
    return out


def reference_pages() -> dict[str, str]:
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(REFERENCE.glob("*.md"))}


def import_or_skip(module: str):
    try:
        return importlib.import_module(module)
    except ImportError as e:
        extra = missing_extra(e)
        if extra is None:
            raise
        pytest.skip(f"{module} needs {extra} (an optional extra)")


def resolvable_docs() -> list[tuple[str, str, object]]:
    """The pages' documented objects; entries whose module needs a missing extra are left out."""
    out = []
    for page, text in reference_pages().items():
        for path, kind in entries(text):
            if kind == "docstring":
                continue
            try:
                out.append((page, path, checked(page, path, kind, resolve(path))))
            except ImportError as e:
                if missing_extra(e) is None:
                    raise
    return out


@pytest.mark.parametrize("module", PUBLIC)
def test_every_public_name_is_documented_exactly_once(module):
    mod = import_or_skip(module)
    try:
        found = problems(module, mod.__all__, resolvable_docs())
    except ImportError as e:  # a lazily imported name needs an extra
        if missing_extra(e) is None:
            raise
        pytest.skip(f"{module} needs {missing_extra(e)} (an optional extra)")
    assert not found, "\n".join(found)


def test_every_directive_names_something_that_exists():
    for page, text in reference_pages().items():
        for path, _ in entries(text):
            try:
                resolve(path)
            except ImportError as e:
                if missing_extra(e) is None:
                    raise
            except AttributeError as e:
                pytest.fail(f"{page}: `{path}` does not exist ({e})")


def public_modules_with_all(root: Path) -> set[str]:
    """Every module of the packages with no underscore in its path that sets ``__all__``."""
    out = set()
    for package in PACKAGES:
        for path in (root / package).rglob("*.py"):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            if any(p.startswith("_") for p in parts):
                continue
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in tree.body:
                targets = node.targets if isinstance(node, ast.Assign) else []
                if any(isinstance(t, ast.Name) and t.id == "__all__" for t in targets):
                    out.add(".".join(parts))
    return out


@pytest.mark.source
def test_every_public_module_is_in_the_reference_or_left_out_with_a_reason():
    found = public_modules_with_all(ROOT)
    assert "comcore.geometry" in found and "comcore.recordings.mit_push" in found
    unlisted = found - set(PUBLIC) - set(NOT_REFERENCED)
    assert not unlisted, f"public modules neither in PUBLIC nor in NOT_REFERENCED: {unlisted}"


PAGE_OK = """
::: comcore.geometry
    options:
      members:
        - sample_pushes
        - contacts
"""


def test_a_name_documented_twice_or_not_at_all_is_found():
    twice = {"a.md": PAGE_OK, "b.md": "::: comcore.sample_pushes\n"}
    docs = documented(twice)
    assert [path for _, path, _ in docs] == [
        "comcore.geometry.sample_pushes",
        "comcore.geometry.contacts",
        "comcore.sample_pushes",
    ]
    found = problems("comcore.geometry", ["sample_pushes", "contacts", "split_by_line"], docs)
    assert found == [
        "comcore.geometry.sample_pushes is documented 2 times: "
        "['a.md: comcore.geometry.sample_pushes', 'b.md: comcore.sample_pushes']",
        "comcore.geometry.split_by_line is documented 0 times: []",
    ]
    # a re-export is the same object: documenting it where it is defined counts for both
    assert problems("comcore", ["sample_pushes"], documented({"a.md": PAGE_OK})) == []


def test_a_module_directive_without_a_members_list_is_refused():
    assert entries("::: comcore.vt\n") == [("comcore.vt", "bare")]
    assert entries("::: predictors\n    options:\n      members: false\n") == [
        ("predictors", "docstring")
    ]
    with pytest.raises(AssertionError, match="explicit members"):
        documented({"a.md": "::: comcore.vt\n"})


def test_two_constants_with_the_same_value_are_told_apart_by_name():
    # comcore.conventions' tolerances are floats; a float of the same value elsewhere must
    # not count as documenting them
    docs = [("a.md", "comcore.conventions.LENGTH_EPS", resolve("comcore.conventions.LENGTH_EPS"))]
    assert problems("comcore.conventions", ["LENGTH_EPS"], docs) == []
    assert problems("comcore.conventions", ["ANGLE_EPS"], docs) == [
        "comcore.conventions.ANGLE_EPS is documented 0 times: []"
    ]
