"""Hypothesis strategies for property tests of comcore: masks, outlines, pushes, CoMs, motions.

Every strategy draws plain comcore values (:class:`comcore.Mask`, :class:`comcore.Action`,
:class:`comcore.Motion`, numpy arrays), so a falsifying example prints in a form that rebuilds
it (a mask prints as ``Mask.from_rle(...)``). Randomness outside hypothesis (the push sampler)
is seeded from a drawn integer, so every example replays exactly.

Examples
--------
>>> from hypothesis import given, settings
>>> from comcore.testing import strategies as cst
>>> @settings(max_examples=5, deadline=None)
... @given(cst.masks_with_pushes())
... def test_the_push_starts_off_the_object(mask_and_push):
...     mask, push = mask_and_push
...     assert not mask.contains([push.start])[0]
>>> test_the_push_starts_off_the_object()
"""

from __future__ import annotations

try:
    from hypothesis import assume
    from hypothesis import strategies as st
except ImportError as e:  # pragma: no cover - depends on the environment
    raise ImportError(
        "comcore.testing.strategies needs hypothesis: pip install comcore[test]"
    ) from e

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._types import Action, Motion
from ..conventions import DEFAULT_RESOLUTION, apply_motion
from ..geometry import largest_component, rasterise_polygon, sample_pushes

__all__ = [
    "angles",
    "coms",
    "friction",
    "friction_ranges",
    "masks",
    "masks_with_pushes",
    "motions",
    "moved_polygon_masks",
    "outlines",
    "points",
    "pushes",
    "seeds",
    "small_rotations",
    "small_shifts",
    "star_polygons",
    "unit_vectors",
]

#: Seeds for numpy Generators (``numpy.random.default_rng(seed)``).
seeds = st.integers(0, 2**32 - 1)
#: Friction coefficients, 0 (frictionless) to 2.
friction = st.floats(0.0, 2.0)
#: Angles in radians, ``[-pi, pi]``.
angles = st.floats(-np.pi, np.pi, allow_nan=False)
#: Unit vectors ``(x, y)``, shape (2,).
unit_vectors = angles.map(lambda a: np.array([np.cos(a), np.sin(a)]))
#: Points ``(x, y)`` in pixels, shape (2,), within 50 px of the origin.
points = st.tuples(st.floats(-50, 50), st.floats(-50, 50)).map(np.array)
#: Rotations in radians small enough for a push (about 34 degrees at most).
small_rotations = st.floats(-0.6, 0.6, allow_nan=False)
#: Translations in pixels, up to 6.
small_shifts = st.floats(-6.0, 6.0, allow_nan=False)


@st.composite
def friction_ranges(draw, max_mu: float = 2.0):
    """Friction ranges ``(lo, hi)`` with ``0 <= lo <= hi <= max_mu``."""
    lo, hi = sorted((draw(st.floats(0.0, max_mu)), draw(st.floats(0.0, max_mu))))
    return (lo, hi)


@st.composite
def star_polygons(draw, min_vertices=3, max_vertices=9, size=40.0, convex=None):
    """Star-shaped polygons around ``(size + 8, size + 8)``, vertices in pixels, shape (k, 2).

    ``convex=True`` puts every vertex on one circle (a convex polygon); ``False`` draws radii
    from ``0.45 * size`` to ``size`` and keeps only polygons with a reflex vertex (concave);
    ``None`` draws either.
    """
    k = draw(st.integers(max(min_vertices, 3 if convex is not False else 4), max_vertices))
    angles_ = np.sort(draw(st.lists(st.floats(0, 2 * np.pi), min_size=k, max_size=k, unique=True)))
    if convex:
        radii = np.full(k, draw(st.floats(0.45 * size, size)))
    else:
        radii = np.array(draw(st.lists(st.floats(0.45 * size, size), min_size=k, max_size=k)))
    center = size + 8.0
    poly = np.column_stack([center + radii * np.cos(angles_), center + radii * np.sin(angles_)])
    if convex is False:
        assume(_is_concave(poly))
    return poly


def _is_concave(poly: np.ndarray) -> bool:
    """Whether a simple polygon's turns change sign (a reflex vertex)."""
    edges = np.roll(poly, -1, axis=0) - poly
    following = np.roll(edges, -1, axis=0)
    turns = edges[:, 0] * following[:, 1] - edges[:, 1] * following[:, 0]
    return bool((turns > 1e-9).any() and (turns < -1e-9).any())


@st.composite
def outlines(draw, size=0.1, convex=None):
    """Object outlines in metres, shape (k, 2), centred on the origin, up to ``size`` across.

    Star-shaped polygons (see :func:`star_polygons`) for
    :func:`comcore.geometry.mask_from_outline` or a simulator's ``from_polygon``.
    """
    poly = draw(star_polygons(size=1.0, convex=convex))
    return (poly - 9.0) * (size / 2)


@st.composite
def masks(draw, size=24.0, holes=False, convex=None, resolution=DEFAULT_RESOLUTION):
    """Masks of star-shaped polygons with at least 200 pixels in one piece.

    Parameters
    ----------
    size : float, optional
        The polygon's largest radius, pixels; the image is ``2 * size + 17`` pixels square.
    holes : bool or None, optional
        ``True``: a round hole inside, enclosed by the object; ``False`` (default): none;
        ``None``: either.
    convex : bool or None, optional
        As :func:`star_polygons` takes it (before any hole is cut).
    resolution : float, optional
        Metres per pixel of the drawn masks.
    """
    poly = draw(star_polygons(size=size, convex=convex))
    side = int(2 * size + 17)
    img = largest_component(rasterise_polygon(poly, (side, side)))
    if holes is None:
        holes = draw(st.booleans())
    if holes:
        radius = draw(st.floats(0.08 * size, 0.25 * size))
        rows, cols = np.mgrid[:side, :side]
        img = img & (np.hypot(cols - (size + 8.0), rows - (size + 8.0)) > radius)
        img = largest_component(img)
        assume(ndimage.binary_fill_holes(img).sum() > img.sum())  # the hole is enclosed
    assume(img.sum() >= 200)
    return Mask(img, resolution=resolution)


@st.composite
def pushes(draw, mask: Mask, max_cone: float = 1.2):
    """Pushes on ``mask``: :class:`comcore.Action` values that start off the object.

    Each starts outside the object and outside any hole, and meets the outer outline (drawn
    by :func:`comcore.geometry.sample_pushes` from a drawn seed).
    """
    cone = draw(st.floats(0.0, max_cone))
    candidates = sample_pushes(mask, 8, cone=cone, rng=draw(seeds))
    filled = ndimage.binary_fill_holes(mask.data)
    h, w = mask.shape
    for row in candidates:
        col, r = int(np.floor(row[0] + 0.5)), int(np.floor(row[1] + 0.5))
        inside_image = 0 <= r < h and 0 <= col < w
        if not (inside_image and filled[r, col]):
            return Action(*row)
    assume(False)  # pragma: no cover - every candidate started in a hole
    return None  # pragma: no cover


@st.composite
def masks_with_pushes(draw, holes=False, convex=None, max_cone: float = 1.2):
    """``(mask, push)``: a drawn mask (:func:`masks`) and a push on it (:func:`pushes`)."""
    mask = draw(masks(holes=holes, convex=convex))
    return mask, draw(pushes(mask, max_cone=max_cone))


@st.composite
def coms(draw, mask: Mask):
    """Centres of mass inside ``mask``: ``(x, y)`` in pixels, shape (2,).

    Each lies within an object pixel (its centre moved by less than half a pixel).
    """
    x, y = mask.pixels[draw(st.integers(0, mask.area_px - 1))]
    dx, dy = draw(st.floats(-0.49, 0.49)), draw(st.floats(-0.49, 0.49))
    return np.array([x + dx, y + dy])


@st.composite
def motions(draw, max_theta: float = 0.6, max_shift: float = 6.0):
    """Rigid motions :class:`comcore.Motion` (radians, pixels) of the size a push makes."""
    theta = draw(st.floats(-max_theta, max_theta, allow_nan=False))
    tx = draw(st.floats(-max_shift, max_shift, allow_nan=False))
    ty = draw(st.floats(-max_shift, max_shift, allow_nan=False))
    return Motion(theta, tx, ty)


@st.composite
def moved_polygon_masks(draw, size=22.0):
    """``(before, after, truth)``: a star polygon rendered, then moved rigidly and rendered again.

    ``truth`` is the :class:`comcore.Motion` in the one convention: a rotation about
    ``before``'s area centroid, then the displacement of that material point.
    """
    poly = draw(star_polygons(size=size)) + 12.0  # room for the motion inside the image
    side = int(2 * size + 40)
    before_img = rasterise_polygon(poly, (side, side))
    assume(before_img.sum() >= 300 and largest_component(before_img).sum() == before_img.sum())
    before = Mask(before_img, resolution=DEFAULT_RESOLUTION)
    truth = Motion(draw(small_rotations), draw(small_shifts), draw(small_shifts))
    moved = apply_motion(poly, truth.theta, (truth.tx, truth.ty), before.centroid)
    after_img = rasterise_polygon(moved, (side, side))
    assume(largest_component(after_img).sum() == after_img.sum())
    for img in (before_img, after_img):
        assume(not (img[0].any() or img[-1].any() or img[:, 0].any() or img[:, -1].any()))
    return before, Mask(after_img, resolution=DEFAULT_RESOLUTION), truth
