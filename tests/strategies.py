"""Hypothesis strategies shared by the property tests: the ones comcore ships.

The suite draws the same objects a user's tests draw from :mod:`comcore.testing.strategies`.
"""

from comcore.testing.strategies import (  # noqa: F401
    angles,
    coms,
    friction,
    friction_ranges,
    masks,
    masks_with_pushes,
    motions,
    moved_polygon_masks,
    outlines,
    points,
    pushes,
    seeds,
    small_rotations,
    small_shifts,
    star_polygons,
    unit_vectors,
)
