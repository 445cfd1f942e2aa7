"""Doctests whose examples need an optional extra: skipped, with the reason, where it is missing.

pytest runs the examples in the packages' docstrings (``--doctest-modules``). In
a core-only install (``pip install comcore[test]``: numpy, scipy and the test
tools) the modules below cannot run theirs (some cannot even be imported); their
doctests are then reported as skipped, naming the extra, instead of failing.
Tests in ``tests/`` skip themselves (``pytest.importorskip``).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent
#: What each extra brings that the examples import.
EXTRA_MODULES = {
    "sim": ("shapely", "trimesh", "pymunk", "cv2"),
    "anp": ("torch",),
    "plot": ("matplotlib",),
    "mujoco": ("mujoco",),
    "ros": ("rosbags",),
}
#: Modules (or folders) whose doctests need an extra, from the repository root.
DOCTESTS_NEED = {
    "comcore/plot": "plot",
    "comcore/recordings/bag.py": "ros",
    "comcore/bench/__init__.py": "sim",
    "comcore/camera/_tags.py": "sim",
    "predictors/anp": "anp",
    "predictors/oracle.py": "sim",
    "simulators": "sim",
    "simulators/mujoco/_robot.py": "mujoco",
}


def missing_extra(path: Path) -> str | None:
    """Why the doctests of ``path`` cannot run here (an extra is missing), or ``None``."""
    try:
        rel = path.resolve().relative_to(ROOT).as_posix()
    except ValueError:
        return None
    for prefix, extra in DOCTESTS_NEED.items():
        if rel == prefix or rel.startswith(prefix + "/"):
            gone = [m for m in EXTRA_MODULES[extra] if importlib.util.find_spec(m) is None]
            if gone:
                need = ", ".join(gone)
                return f"the examples of {prefix} need {need}: pip install comcore[{extra}]"
    return None


class SkippedDoctests(pytest.File):
    """Stands for a module's doctests that cannot run here; collecting it skips them."""

    def __init__(self, *, reason: str, **kwargs):
        super().__init__(**kwargs)
        self.reason = reason

    def collect(self):
        """Skip, saying which extra is missing."""
        pytest.skip(self.reason)


@pytest.hookimpl(wrapper=True)
def pytest_collect_file(file_path, parent):
    """A module's doctests, or their skip where an extra they need is missing.

    The packages' modules are collected only for their doctests (no test files
    among them), so whatever was collected from one of them is replaced.
    """
    collected = yield
    reason = missing_extra(file_path) if file_path.suffix == ".py" else None
    if reason is None or not collected:
        return collected
    return [SkippedDoctests.from_parent(parent, path=file_path, reason=reason)]
