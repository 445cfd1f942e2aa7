"""Optional dependencies of the simulators, imported only when used."""

from __future__ import annotations

import importlib

__all__ = ["require_pymunk", "require_shapely", "require_trimesh"]


def _require(module: str, extra: str = "sim"):
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(f"the simulators need {module!r}: pip install comcore[{extra}]") from e


def require_pymunk():
    """Return the ``pymunk`` module or raise an ImportError naming the extra."""
    return _require("pymunk")


def require_shapely():
    """Return the ``shapely`` module or raise an ImportError naming the extra."""
    return _require("shapely")


def require_trimesh():
    """Return the ``trimesh`` module or raise an ImportError naming the extra."""
    return _require("trimesh")
