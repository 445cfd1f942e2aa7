"""Tools for testing code built on comcore: hypothesis strategies that draw its objects.

:mod:`comcore.testing.strategies` draws masks (convex, concave, with holes), outlines, pushes
that meet the object, CoMs inside it, friction values and ranges, and rigid motions, the same
objects comcore's own property tests draw. It needs hypothesis (``pip install comcore[test]``);
``import comcore`` never loads it. May import the base modules and :mod:`comcore.geometry`.
"""

import importlib

__all__ = ["strategies"]


def __getattr__(name: str):
    """Load :mod:`comcore.testing.strategies` (and so hypothesis) on first use."""
    if name == "strategies":
        return importlib.import_module(f"{__name__}.strategies")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
