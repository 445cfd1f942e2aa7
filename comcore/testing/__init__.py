"""Tools for testing code built on comcore: hypothesis strategies that draw its objects.

:mod:`comcore.testing.strategies` draws masks (convex, concave, with holes), outlines, pushes
that meet the object, CoMs inside it, friction values and ranges, and rigid motions, the same
objects comcore's own property tests draw. It needs hypothesis (``pip install comcore[test]``);
``import comcore`` never loads it. May import the base modules and :mod:`comcore.geometry`.
"""

from .._lazy import lazy_exports

__all__ = ["strategies"]

# The strategies (and so hypothesis) load on first use.
__getattr__, __dir__ = lazy_exports(__name__, {"strategies": "strategies"})
