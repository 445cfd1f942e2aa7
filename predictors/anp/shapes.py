"""Procedurally generated flat objects for training (never the 20 benchmark objects).

All outlines are simple polygons (no self-intersection): star-shaped blobs
(a positive radius function of the polar angle), convex hulls of random
points, and rectilinear L, T, U and plain rectangles. Each is stretched,
turned and scaled to a log-uniform area in :data:`AREA_RANGE_M2`, covering the
sizes of the paper's objects (27 to 150 cm^2).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull

from comcore.checks import check_rng
from comcore.conventions import rotation_matrix
from comcore.geometry import rasterise_polygon

__all__ = ["AREA_RANGE_M2", "polygon_area", "random_polygon", "rasterise"]

#: Areas of the generated objects, square metres (log-uniform).
AREA_RANGE_M2 = (0.0020, 0.0170)
_KINDS = ("blob", "convex", "rectilinear")


def polygon_area(vertices) -> float:
    """Signed shoelace area of a polygon ``(k, 2)`` (positive counter-clockwise, y up)."""
    v = np.asarray(vertices, dtype=float)
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _blob(rng) -> np.ndarray:
    phi = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    r = np.ones_like(phi)
    for k in range(2, 6):
        r += rng.uniform(0, 0.35 / (k - 1)) * np.cos(k * phi + rng.uniform(0, 2 * np.pi))
    r = np.maximum(r, 0.35)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi)])


def _convex(rng) -> np.ndarray:
    points = rng.uniform(-1, 1, size=(int(rng.integers(3, 9)), 2))
    for _ in range(20):
        try:
            hull = ConvexHull(points)
        except Exception:  # degenerate (collinear) draw: try again
            points = rng.uniform(-1, 1, size=points.shape)
            continue
        if hull.volume > 0.3:
            return points[hull.vertices]
        points = rng.uniform(-1, 1, size=points.shape)
    return np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def _rectilinear(rng) -> np.ndarray:
    w, h = rng.uniform(0.3, 0.7, size=2)  # arm width and height, fractions of the unit box
    kind = rng.integers(4)
    if kind == 0:  # rectangle
        return np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    if kind == 1:  # L
        return np.array([[0, 0], [1, 0], [1, h], [w, h], [w, 1], [0, 1]], float)
    if kind == 2:  # T
        a, b = (1 - w) / 2, (1 + w) / 2
        return np.array([[a, 0], [b, 0], [b, h], [1, h], [1, 1], [0, 1], [0, h], [a, h]], float)
    p = w / 2  # U: two posts of width p on a base of height h / 2
    t = h / 2
    return np.array([[0, 0], [1, 0], [1, 1], [1 - p, 1], [1 - p, t], [p, t], [p, 1], [0, 1]], float)


def random_polygon(rng=None, area_range=AREA_RANGE_M2) -> np.ndarray:
    """A random simple polygon, world metres, counter-clockwise, centroid near 0.

    Parameters
    ----------
    rng : None, int or numpy.random.Generator, optional
    area_range : (float, float), optional
        Areas in square metres, drawn log-uniformly.

    Returns
    -------
    numpy.ndarray, shape (k, 2)

    Examples
    --------
    >>> v = random_polygon(0)
    >>> 0.0020 <= polygon_area(v) <= 0.0170
    True
    >>> np.array_equal(v, random_polygon(0))
    True
    """
    rng = check_rng(rng)
    lo, hi = (float(a) for a in area_range)
    if not 0 < lo <= hi:
        raise ValueError(f"area_range must be (lo, hi) with 0 < lo <= hi, got {area_range}")
    kind = _KINDS[int(rng.integers(len(_KINDS)))]
    v = {"blob": _blob, "convex": _convex, "rectilinear": _rectilinear}[kind](rng)
    v = v * np.array([1.0, rng.uniform(0.4, 1.0)])  # elongation up to 2.5 : 1
    v = v @ rotation_matrix(rng.uniform(0, 2 * np.pi))
    if polygon_area(v) < 0:
        v = v[::-1]
    area = np.exp(rng.uniform(np.log(lo), np.log(hi)))
    v = v * np.sqrt(area / polygon_area(v))
    return v - v.mean(axis=0)


def rasterise(vertices_m, resolution: float, margin_px: int = 8) -> np.ndarray:
    """Bool image of a polygon (pixel centres inside, even-odd rule), y flipped to rows.

    The polygon's bounding box is placed ``margin_px`` pixels from each border;
    :func:`comcore.geometry.rasterise_polygon` fills it. Used by the toy data source; the
    simulator has its own rasteriser.
    """
    v = np.asarray(vertices_m, dtype=float) / resolution
    v = np.column_stack([v[:, 0], -v[:, 1]])  # world y up -> pixel y down
    v = v - v.min(axis=0) + margin_px
    w, h = (np.ceil(v.max(axis=0)).astype(int) + margin_px + 1).tolist()
    return rasterise_polygon(v, (h, w))
