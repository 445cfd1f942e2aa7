"""Skips for tests that need an optional extra (the core-only CI job runs without them).

``pytest.importorskip("simulators")`` never skips: the package imports without its
extras and fails only when a simulator is built. Use :func:`require_simulators`.
"""

from __future__ import annotations

import pytest


def require_simulators():
    """The ``simulators`` package, or a skip when the sim extra (shapely, trimesh) is missing."""
    pytest.importorskip("shapely")
    pytest.importorskip("trimesh")
    import simulators

    return simulators
