"""Every ```python block in docs/**/*.md and README.md runs ON ITS OWN, in a fresh namespace.

A reader copies one block; it must carry its own imports and data. A block that needs an
optional extra which is not installed is skipped, never one with a bad import.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [*sorted((ROOT / "docs").rglob("*.md")), ROOT / "README.md"]
BLOCK = re.compile(r"```python\n(.*?)```", re.S)

#: Top-level modules of the optional extras in pyproject.toml ([sim], [anp], [plot], [bench],
#: [real], [ros], [mujoco]), and ROS 2's own (rclpy, geometry_msgs: not on PyPI).
#: A block may be skipped only when one of these is missing; any other missing module (a
#: misspelled import, a renamed comcore module) fails the test.
OPTIONAL_MODULES = frozenset(
    {
        "torch",  # [anp]
        "pymunk",  # [sim]
        "trimesh",
        "shapely",
        "cv2",
        "networkx",
        "lxml",
        "svg",  # svg.path
        "matplotlib",  # [plot]
        "dask",  # [bench]
        "distributed",
        "tqdm",
        "pyarrow",
        "h5py",  # [real]
        "mujoco",  # [mujoco]
        "rosbags",  # [ros]
        "rclpy",  # ROS 2's own (not on PyPI): its blocks run only where ROS 2 is installed
        "geometry_msgs",
    }
)


def blocks(page: Path) -> list[str]:
    return BLOCK.findall(page.read_text(encoding="utf-8"))


def missing_extra(error: BaseException) -> str | None:
    """The optional module whose absence caused ``error``, or None.

    Follows the explicit causes: comcore wraps a missing extra in an ImportError that names
    the ``pip install`` (``raise ImportError(...) from e``). An error merely raised while an
    optional import's failure was being handled (``__context__``) does not count.
    """
    seen: set[int] = set()
    e: BaseException | None = error
    while e is not None and id(e) not in seen:
        seen.add(id(e))
        if isinstance(e, ModuleNotFoundError) and e.name:
            if e.name.split(".")[0] in OPTIONAL_MODULES:
                return e.name
        e = e.__cause__
    return None


def run_block(block: str, label: str, namespace: dict | None = None) -> None:
    """Run one block in a fresh namespace (or ``namespace``).

    Skips the test if the block needs an optional extra that is not installed.
    """
    scope = namespace if namespace is not None else {"__name__": "docs_block"}
    try:
        exec(compile(block, label, "exec"), scope)
    except ImportError as e:
        module = missing_extra(e)
        if module is None:
            raise
        pytest.skip(f"{label} needs {module} (an optional extra)")


def run_blocks(code: list[str], name: str) -> None:
    """Run the blocks in order, each in a fresh namespace."""
    for i, block in enumerate(code):
        run_block(block, f"{name}[block {i}]")


def all_blocks():
    return [
        pytest.param(page, i, id=f"{page.relative_to(ROOT).as_posix()}[{i}]")
        for page in PAGES
        if page.exists()
        for i in range(len(blocks(page)))
    ]


@pytest.mark.parametrize(("page", "index"), all_blocks())
def test_each_code_block_runs_on_its_own(page, index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run_block(blocks(page)[index], f"{page.name}[block {index}]")


def test_blocks_do_not_share_a_namespace():
    with pytest.raises(NameError, match="'mask' is not defined"):
        run_blocks(["mask = 1", "print(mask)"], "page.md")


WRAPPED_EXTRA = """
try:
    raise ModuleNotFoundError("No module named 'pymunk'", name="pymunk")
except ImportError as e:
    raise ImportError("the simulators need 'pymunk': pip install comcore[sim]") from e
"""


@pytest.mark.parametrize(
    "block",
    [
        "raise ModuleNotFoundError('No module named torch', name='torch')",
        "raise ModuleNotFoundError('No module named cv2.aruco', name='cv2.aruco')",
        WRAPPED_EXTRA,
    ],
)
def test_a_block_needing_a_missing_extra_is_skipped(block):
    with pytest.raises(pytest.skip.Exception, match="needs"):
        run_blocks([block], "page.md")


@pytest.mark.parametrize(
    "block",
    [
        "import comcroe",  # a misspelled import
        "import comcore.no_such_module",
        "import torchvision_not_an_extra",
        "raise ImportError('cannot import name X')",
        # a misspelled import in the fallback for a missing extra is still a failure
        "try:\n    raise ModuleNotFoundError(name='tqdm')\nexcept ImportError:\n    import comcroe",
    ],
)
def test_a_block_with_a_bad_import_fails(block):
    try:
        run_blocks([block], "page.md")
    except pytest.skip.Exception as e:  # a skip would hide the error: the old behaviour
        pytest.fail(f"skipped instead of failing: {e}")
    except ImportError:
        return
    pytest.fail("the bad import raised nothing")
