"""Every docs page the code, the tests and the benchmarks cite exists (pages moved once)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.source  # reads the packages' source files

ROOT = Path(__file__).resolve().parents[2]
CITED = re.compile(r"(?<![\w/])docs/[\w./-]+?\.(?:md|png|py)\b")


def cited_paths() -> dict[str, set[str]]:
    files = subprocess.run(
        ["git", "ls-files", "comcore", "predictors", "simulators", "benchmarks", "tests", "README.md"],
        cwd=ROOT, capture_output=True, text=True, check=True,
    ).stdout.split()  # fmt: skip
    found: dict[str, set[str]] = {}
    for name in files:
        path = ROOT / name
        if path.suffix not in {".py", ".md", ".sh"} or not path.is_file():
            continue
        for cited in CITED.findall(path.read_text(encoding="utf-8")):
            found.setdefault(cited, set()).add(name)
    return found


def test_the_walk_finds_citations():
    found = cited_paths()
    assert "docs/explanation/conventions.md" in found  # the walk reads the packages' text


def test_every_cited_docs_page_exists():
    missing = {p: sorted(f) for p, f in cited_paths().items() if not (ROOT / p).exists()}
    assert not missing, f"cited docs pages that do not exist: {missing}"
