"""Polygons to pixel images: which pixel centres lie inside (numpy only).

The pixel frame is comcore's (:mod:`comcore.conventions`): pixel ``(row, col)``
has its centre at ``(x, y) = (col, row)``. The simulator renders its masks
from the exact outline with shapely; this is the light core's rasteriser, for
tests, benchmarks and data generators that draw polygons without the
simulator.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_points
from ..conventions import check_image_size

__all__ = ["rasterise_polygon"]


def _image_shape(shape) -> tuple[int, int]:
    try:
        h, w = shape
    except (TypeError, ValueError):
        raise TypeError(f"shape must be (rows, cols), got {shape!r}") from None
    for v in (h, w):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise TypeError(f"shape must be two integers (rows, cols), got {shape!r}")
        if v < 0:
            raise ValueError(f"shape must be two integers >= 0 (rows, cols), got {shape!r}")
    check_image_size((h, w), "shape")
    return int(h), int(w)


def rasterise_polygon(vertices, shape) -> np.ndarray:
    """Which pixel centres of an image lie inside a polygon (even-odd rule).

    A pixel is inside when a ray from its centre towards ``+x`` crosses the
    outline an odd number of times (an edge counts when its end points lie on
    either side of the centre's row, ``y0 > y`` differing from ``y1 > y``).
    Self-intersecting outlines follow the even-odd rule. Only the polygon's
    bounding box is computed; the rest of the image is outside.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        The outline ``(x, y)`` in pixels, k >= 3, in either orientation (closed
        implicitly: the last vertex joins the first).
    shape : (int, int)
        ``(rows, cols)`` of the image.

    Returns
    -------
    numpy.ndarray of bool, shape ``shape``

    Raises
    ------
    ValueError
        If ``vertices`` is not of shape (k, 2) with k >= 3, or not finite; or
        ``shape`` holds a negative size.
    TypeError
        If ``shape`` is not two integers.

    Examples
    --------
    >>> import comcore
    >>> comcore.geometry.rasterise_polygon([(0.5, 0.5), (3.5, 0.5), (0.5, 3.5)], (4, 5)).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 1, 1, 0, 0],
           [0, 1, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    v = check_points(vertices, "vertices")
    if len(v) < 3:
        raise ValueError(f"vertices must hold at least 3 points, got {len(v)}")
    h, w = _image_shape(shape)
    out = np.zeros((h, w), bool)
    lo = np.maximum(np.floor(v.min(axis=0)).astype(int), 0)
    hi = np.minimum(np.ceil(v.max(axis=0)).astype(int), (w - 1, h - 1))
    if (hi < lo).any():
        return out
    ys, xs = np.mgrid[lo[1] : hi[1] + 1, lo[0] : hi[0] + 1].astype(float)
    inside = np.zeros(xs.shape, bool)
    for (a, b), (c, d) in zip(v, np.roll(v, -1, axis=0)):
        crosses = (b > ys) != (d > ys)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = a + (ys - b) * (c - a) / (d - b)
        inside ^= crosses & (xs < x_at)
    out[lo[1] : hi[1] + 1, lo[0] : hi[0] + 1] = inside
    return out
