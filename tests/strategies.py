"""Hypothesis strategies shared by the property tests: polygons, masks, pushes, CoMs."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

import comcore
from comcore.geometry import rasterise_polygon


@st.composite
def star_polygons(draw, min_vertices=3, max_vertices=9, size=40.0):
    """Star-shaped polygons (convex or concave) around (size, size), in pixels."""
    k = draw(st.integers(min_vertices, max_vertices))
    angles = np.sort(draw(st.lists(st.floats(0, 2 * np.pi), min_size=k, max_size=k, unique=True)))
    radii = np.array(draw(st.lists(st.floats(0.45 * size, size), min_size=k, max_size=k)))
    center = size + 8.0
    return np.column_stack([center + radii * np.cos(angles), center + radii * np.sin(angles)])


@st.composite
def masks(draw, size=24.0):
    """Masks of star-shaped polygons with at least 200 pixels in one piece."""
    poly = draw(star_polygons(size=size))
    side = int(2 * size + 17)
    img = rasterise_polygon(poly, (side, side))
    img = comcore.geometry.largest_component(img)
    from hypothesis import assume

    assume(img.sum() >= 200)
    return comcore.Mask(img, resolution=0.0025)


seeds = st.integers(0, 2**32 - 1)
friction = st.floats(0.0, 2.0)
angles = st.floats(-np.pi, np.pi, allow_nan=False)
unit_vectors = angles.map(lambda a: np.array([np.cos(a), np.sin(a)]))
points = st.tuples(st.floats(-50, 50), st.floats(-50, 50)).map(np.array)


# -- rigid motions of rendered polygons (measure_motion) ---------------------------------------
small_rotations = st.floats(-0.6, 0.6, allow_nan=False)
small_shifts = st.floats(-6.0, 6.0, allow_nan=False)


@st.composite
def moved_polygon_masks(draw, size=22.0):
    """``(before, after, truth)``: a star polygon rendered, then moved rigidly and rendered again.

    ``truth`` is the :class:`comcore.Motion` in the one convention: a rotation about
    ``before``'s area centroid, then the displacement of that material point.
    """
    from hypothesis import assume

    poly = draw(star_polygons(size=size))
    side = int(2 * size + 40)
    poly = poly + 12.0  # room for the motion inside the image
    before_img = rasterise_polygon(poly, (side, side))
    assume(before_img.sum() >= 300 and comcore.geometry.largest_component(before_img).sum() == before_img.sum())
    before = comcore.Mask(before_img, resolution=0.0025)
    truth = comcore.Motion(draw(small_rotations), draw(small_shifts), draw(small_shifts))
    moved = comcore.apply_motion(poly, truth.theta, (truth.tx, truth.ty), before.centroid)
    after_img = rasterise_polygon(moved, (side, side))
    assume(comcore.geometry.largest_component(after_img).sum() == after_img.sum())
    for img in (before_img, after_img):
        assume(not (img[0].any() or img[-1].any() or img[:, 0].any() or img[:, -1].any()))
    return before, comcore.Mask(after_img, resolution=0.0025), truth
