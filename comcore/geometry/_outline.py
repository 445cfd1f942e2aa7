"""An object's outline in metres: its mask, the pixel frame it is drawn in, distances to it.

A recorded object is known by its outline in its own frame (metres, ``x``
right and ``y`` up as seen from above, like a robot's or a motion-capture
system's frame). :func:`mask_from_outline` draws it as a :class:`Mask`; the
pixel frame is the simulators' (``simulators.PushSimulator.to_pixels``): pixel
``(0, 0)`` has its centre at ``(x_min - margin + res / 2, y_max + margin -
res / 2)`` and the pixel ``y`` axis points down, so ``theta > 0``
counter-clockwise seen from above is counter-clockwise on screen.
"""

from __future__ import annotations

import math

import numpy as np

from .._mask import Mask
from .._validation import _as_float_rows, check_positive
from ..conventions import DEFAULT_RESOLUTION
from ._raster import rasterise_polygon

__all__ = [
    "DEFAULT_MARGIN_M",
    "OutlineFrame",
    "check_outline",
    "mask_from_outline",
    "outline_signed_distance",
]

#: Empty border (metres) around the outline in its mask, as in the simulators.
DEFAULT_MARGIN_M = 0.02


def check_outline(outline, name: str = "outline") -> np.ndarray:
    """Validate a polygon (metres) into a read-only (k, 2) array, closing point dropped.

    Either orientation is accepted. Raises ValueError for fewer than three
    distinct vertices or a zero area, TypeError for non-numbers.

    Examples
    --------
    >>> check_outline([(0, 0), (0.1, 0), (0.2, 0), (0, 0)])
    Traceback (most recent call last):
    ...
    ValueError: outline must have a non-zero area (a polygon of at least 3 vertices, metres)
    """
    pts = np.array(_as_float_rows(outline, 2, name, tuple()))  # type: ignore[arg-type]
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    nxt = np.roll(pts, -1, axis=0)
    area = 0.5 * float(np.sum(pts[:, 0] * nxt[:, 1] - nxt[:, 0] * pts[:, 1]))
    if len(pts) < 3 or not abs(area) > 0:
        raise ValueError(
            f"{name} must have a non-zero area (a polygon of at least 3 vertices, metres)"
        )
    pts.setflags(write=False)
    return pts


class OutlineFrame:
    """The pixel frame an outline's mask is drawn in (see :func:`mask_from_outline`).

    Parameters
    ----------
    outline : numpy.ndarray, shape (k, 2)
        Checked outline, metres.
    resolution, margin : float
        Metres per pixel; empty border in metres.
    """

    def __init__(self, outline: np.ndarray, resolution: float, margin: float):
        x_min, y_min = outline.min(axis=0)
        x_max, y_max = outline.max(axis=0)
        half = 0.5 * resolution
        self.origin = np.array([x_min - margin + half, y_max + margin - half])
        self.resolution = resolution
        self.shape = (
            math.ceil((y_max - y_min + 2 * margin) / resolution - 1e-9),
            math.ceil((x_max - x_min + 2 * margin) / resolution - 1e-9),
        )

    def pixels_from_object(self, points_m: np.ndarray) -> np.ndarray:
        """Object-frame metres (``y`` up) to pixels (``y`` down), (n, 2)."""
        p = np.asarray(points_m, dtype=float).reshape(-1, 2)
        return np.column_stack([p[:, 0] - self.origin[0], self.origin[1] - p[:, 1]]) / (
            self.resolution
        )

    def object_from_pixels(self, points_px: np.ndarray) -> np.ndarray:
        """Pixels to object-frame metres; the inverse of :meth:`pixels_from_object`."""
        p = np.asarray(points_px, dtype=float).reshape(-1, 2) * self.resolution
        return np.column_stack([p[:, 0] + self.origin[0], self.origin[1] - p[:, 1]])


def mask_from_outline(
    outline, resolution: float = DEFAULT_RESOLUTION, margin: float = DEFAULT_MARGIN_M
) -> Mask:
    """The mask of an outline given in metres: pixels whose centre lies inside it.

    Parameters
    ----------
    outline : array_like, shape (k, 2)
        Polygon vertices in metres in the object's frame, ``x`` right and
        ``y`` up seen from above (either orientation; a closing vertex equal
        to the first is allowed).
    resolution : float, optional
        Metres per pixel (default 2.5 mm).
    margin : float, optional
        Empty border around the outline, metres (default 2 cm).

    Returns
    -------
    Mask
        Pixel ``(0, 0)`` has its centre at ``(x_min - margin + resolution / 2,
        y_max + margin - resolution / 2)``; pixel ``y`` points down (the
        object frame's ``y`` up). The same frame and mask as
        ``simulators.PushSimulator.from_polygon(outline, resolution=...,
        margin=...)``.

    Raises
    ------
    ValueError
        If the outline is not a polygon of non-zero area, ``resolution`` is
        not > 0, ``margin`` is negative, or no pixel centre falls inside.

    Examples
    --------
    A 2 x 1 cm plate at 2.5 mm per pixel with a 5 mm margin:

    >>> m = mask_from_outline([(0, 0), (0.02, 0), (0.02, 0.01), (0, 0.01)], 0.0025, 0.005)
    >>> m.shape, m.area_px
    ((8, 12), 32)
    """
    poly = check_outline(outline)
    resolution = check_positive(resolution, "resolution")
    margin = check_positive(margin, "margin", allow_zero=True)
    frame = OutlineFrame(poly, resolution, margin)
    inside = rasterise_polygon(frame.pixels_from_object(poly), frame.shape)
    if not inside.any():
        raise ValueError(
            f"resolution {resolution:g} m per pixel is too coarse for this outline: no pixel "
            "centre falls inside it"
        )
    return Mask(inside, resolution=resolution)


def outline_signed_distance(outline: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Distance (metres) from points to a checked outline's edges, negative inside, (n,)."""
    a = outline[None]
    ab = np.roll(outline, -1, axis=0)[None] - a
    rel = points[:, None, :] - a
    t = np.clip((rel * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    d = np.hypot(rel[..., 0] - t * ab[..., 0], rel[..., 1] - t * ab[..., 1]).min(axis=1)
    b = np.roll(outline, -1, axis=0)
    crosses = (a[..., 1] > points[:, None, 1]) != (b[None, :, 1] > points[:, None, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[..., 0] + (points[:, None, 1] - a[..., 1]) * ab[..., 0] / ab[..., 1]
    inside = np.count_nonzero(crosses & (x_at > points[:, None, 0]), axis=1) % 2 == 1
    return np.where(inside, -d, d)
