"""Every code fence in README.md and docs/**/*.md opens and closes cleanly.

A fence left open, or a closing fence with text after it on the same line (```` ``` Reading````),
turns the rest of the page into code while ``mkdocs build --strict`` still passes.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [*sorted((ROOT / "docs").rglob("*.md")), ROOT / "README.md"]
FENCE = re.compile(r"^[ \t]*(`{3,}|~{3,})(.*)$")
INFO = re.compile(r"^[ \t]*\{?[\w#.+ -]*\}?[ \t]*$")  # python, {.python}, or nothing


def fence_faults(text: str) -> list[str]:
    """The fence faults of one page's ``text``, as ``"line N: what"`` strings."""
    faults = []
    open_at, opener = 0, ""
    for n, line in enumerate(text.splitlines(), start=1):
        m = FENCE.match(line)
        if m is None:
            continue
        mark, rest = m.groups()
        if not open_at:
            if not INFO.match(rest) or len(rest.split()) > 1:
                faults.append(f"line {n}: text after an opening fence: {line.strip()!r}")
            open_at, opener = n, mark
        elif mark[0] == opener[0] and len(mark) >= len(opener):
            if rest.strip():
                faults.append(f"line {n}: text after a closing fence: {line.strip()!r}")
            open_at, opener = 0, ""
    if open_at:
        faults.append(f"line {open_at}: a fence opened here is never closed")
    return faults


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_fences_open_and_close_cleanly(page):
    assert not fence_faults(page.read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("```python\nx = 1\n``` Reading `done`,\nmore\n```\n", "line 3: text after a closing"),
        ("text\n```python\nx = 1\n", "line 2: a fence opened here is never closed"),
        ("```python\nx = 1\n```\n\n```bash\nls\n", "line 5: a fence opened here is never"),
        ("``` Reading `done`, the status\n", "line 1: text after an opening fence"),
    ],
)
def test_a_fence_fault_is_found(text, fault):
    faults = fence_faults(text)
    assert faults and faults[0].startswith(fault), faults


@pytest.mark.parametrize(
    "text",
    ["```python\nx = 1\n```\n", "```\nplain\n```\n\n~~~text\n```\n~~~\n", "  ```bash\n  ls\n  ```\n"],
)
def test_clean_fences_pass(text):
    assert fence_faults(text) == []
