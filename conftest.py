"""Doctests whose examples need an optional extra: skipped, with the reason, where it is missing.

pytest runs the examples in the packages' docstrings (``--doctest-modules``). In
a core-only install (``pip install comcore[test]``: numpy, scipy and the test
tools) the modules below cannot run theirs (some cannot even be imported); their
doctests are then reported as skipped, naming the extra, instead of failing.
Tests in ``tests/`` skip themselves (``pytest.importorskip``); every skip that comes
from a missing module is reported with the extra that installs it
(:func:`with_extra`), so a core-only run says what to ``pip install``.
"""

from __future__ import annotations

import importlib.util
import re
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
    "real": ("h5py",),
    "bench": ("tqdm", "dask", "distributed", "pyarrow"),
    "docs": ("mkdocs", "mkdocstrings"),
}
#: The extra that installs each module a test may skip on (the simulators need ``sim``).
EXTRA_OF = {
    module: extra for extra, modules in EXTRA_MODULES.items() for module in modules
} | {"simulators": "sim", "predictors": "sim", "markdown": "docs"}
_NOT_IMPORTED = re.compile(r"could not import '([\w.]+)'")
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


def with_extra(reason: str) -> str:
    """A skip's ``reason`` with the ``pip install comcore[extra]`` that removes it, if known.

    >>> with_extra("Skipped: could not import 'shapely': No module named 'shapely'")
    "Skipped: could not import 'shapely': No module named 'shapely': pip install comcore[sim]"
    >>> with_extra("needs a display")
    'needs a display'
    """
    found = _NOT_IMPORTED.search(reason)
    if found is None or "pip install" in reason:
        return reason
    extra = EXTRA_OF.get(found.group(1).split(".")[0])
    return reason if extra is None else f"{reason}: pip install comcore[{extra}]"


def _name_the_extra(report) -> None:
    """Rewrite a skipped report's reason with :func:`with_extra`."""
    if report.skipped and isinstance(report.longrepr, tuple) and len(report.longrepr) == 3:
        path, line, reason = report.longrepr
        report.longrepr = (path, line, with_extra(str(reason)))


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    """A test's skip names the extra to install."""
    report = yield
    _name_the_extra(report)
    return report


@pytest.hookimpl(wrapper=True)
def pytest_make_collect_report(collector):
    """A module's skip at collection (``importorskip`` at its top) names the extra too."""
    report = yield
    _name_the_extra(report)
    return report


def pytest_collection_modifyitems(config, items):
    """Skip the tests that read the packages' sources where they are not beside the tests.

    CI runs the tests against the installed wheel from a copy of the repository without
    the packages' folders (``.ci/run``); the static checks of the sources (marked
    ``source``) run in the checkout's job.
    """
    if (ROOT / "comcore").is_dir():
        return
    skip = pytest.mark.skip(reason="reads the packages' sources: run it from a checkout")
    for item in items:
        if "source" in item.keywords:
            item.add_marker(skip)
