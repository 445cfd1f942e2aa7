"""The README's links into docs/ resolve (mkdocs checks the docs' own links, not the README's)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#+ (.*)$", re.M)


def slug(heading: str) -> str:
    """The anchor mkdocs gives a heading (Python-Markdown's toc slugify, code marks dropped)."""
    text = re.sub(r"[`*]", "", heading)
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def broken_links(page: Path) -> list[str]:
    out = []
    for target in LINK.findall(page.read_text(encoding="utf-8")):
        if re.match(r"^[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        file = (page.parent / path).resolve()
        if not file.is_file():
            out.append(f"{target}: no such file")
        elif anchor and anchor not in {slug(h) for h in HEADING.findall(file.read_text("utf-8"))}:
            out.append(f"{target}: no such heading")
    return out


def test_the_readme_links_resolve():
    assert not broken_links(ROOT / "README.md")


def test_a_broken_link_is_found(tmp_path):
    (tmp_path / "a.md").write_text("# A page\n\n## The loop: `next_push`\n")
    page = tmp_path / "README.md"
    page.write_text("[ok](a.md#the-loop-next_push) [gone](b.md) [anchor](a.md#nope) [web](https://x.org)")
    assert broken_links(page) == ["b.md: no such file", "a.md#nope: no such heading"]


@pytest.mark.parametrize(
    ("heading", "anchor"),
    [
        ("What the status says, and what to do next", "what-the-status-says-and-what-to-do-next"),
        ("In the realism table: `comcore bench --conditions mujoco` (200 trials)",
         "in-the-realism-table-comcore-bench-conditions-mujoco-200-trials"),
    ],
)
def test_the_slug_is_mkdocs_own(heading, anchor):
    assert slug(heading) == anchor
    toc = pytest.importorskip("markdown.extensions.toc")
    assert toc.slugify(re.sub(r"[`*]", "", heading), "-") == anchor
