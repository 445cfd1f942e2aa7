"""From a camera image to a :class:`Mask`: :func:`mask_from_image`."""

from __future__ import annotations

import math
import os

import numpy as np
from scipy import ndimage

from ._conventions import DEFAULT_RESOLUTION
from ._errors import ImageError
from ._mask import Mask
from ._regions import EIGHT_CONNECTED

__all__ = ["mask_from_image", "otsu_threshold"]

#: Luma weights of red, green and blue (ITU-R BT.601), for colour images.
LUMA_WEIGHTS = (0.299, 0.587, 0.114)
#: Bins of the grey-level histogram of Otsu's method.
OTSU_BINS = 256
#: Speckled: the largest component holds less than this share of the foreground pixels.
MIN_LARGEST_SHARE = 0.5
#: Several objects: the second component is at least this fraction of the largest.
MAX_SECOND_RATIO = 0.5
OBJECTS = ("auto", "bright", "dark")


def otsu_threshold(grey) -> float:
    """Otsu's threshold of a grey image: the level that best splits its histogram in two.

    Parameters
    ----------
    grey : array_like, shape (H, W)
        Finite grey levels, not all equal.

    Returns
    -------
    float
        ``t`` maximising the between-class variance of ``grey < t`` and
        ``grey >= t`` over a 256-bin histogram (a bin edge; the middle one
        when a gap between the two modes makes several splits equal).

    Raises
    ------
    ValueError
        If ``grey`` is constant.

    Examples
    --------
    >>> img = np.zeros((4, 4)); img[1:3, 1:3] = 200.0
    >>> t = otsu_threshold(img)
    >>> 0 < t < 200
    True
    """
    g = np.asarray(grey, dtype=float)
    lo, hi = float(g.min()), float(g.max())
    if not hi > lo:
        raise ValueError(f"grey must not be constant to be thresholded, got all pixels = {lo:g}")
    hist, edges = np.histogram(g, bins=OTSU_BINS, range=(lo, hi))
    centres = 0.5 * (edges[:-1] + edges[1:])
    w0 = np.cumsum(hist)[:-1].astype(float)
    w1 = g.size - w0
    s0 = np.cumsum(hist * centres)[:-1]
    m0 = s0 / np.maximum(w0, 1)
    m1 = (np.sum(hist * centres) - s0) / np.maximum(w1, 1)
    between = np.where((w0 > 0) & (w1 > 0), w0 * w1 * (m0 - m1) ** 2, -1.0)
    best = np.flatnonzero(between >= between.max() * (1 - 1e-12))
    # a gap between the two modes makes a plateau of equal splits: take its middle
    return float(edges[int(best[len(best) // 2]) + 1])


def _read(path) -> np.ndarray:
    try:
        import cv2
    except ImportError as e:
        raise ImportError(
            "reading an image file needs opencv: pip install comcore[sim] "
            "(or pass the image as an array)"
        ) from e
    image = cv2.imread(os.fspath(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise ValueError(
            f"image could not be read from {os.fspath(path)!r} (missing or not an image file)"
        )
    if image.ndim == 3 and image.shape[2] in (3, 4):
        image = image[..., [2, 1, 0]]  # opencv reads BGR(A): to RGB, alpha dropped
    return image


def _grey(image) -> np.ndarray:
    """A float grey image (H, W) from a grey, RGB or RGBA array."""
    if isinstance(image, Mask):
        return image.data.astype(float)
    arr = np.asarray(image)
    if arr.dtype == bool:
        arr = arr.astype(float)
    if arr.dtype.kind not in "iuf":
        raise TypeError(
            f"image must be a numeric (uint8, uint16, float or bool) array or a path, "
            f"got dtype {arr.dtype}"
        )
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = arr[..., 0]
    if arr.ndim == 3 and arr.shape[2] in (3, 4):
        arr = arr[..., :3].astype(float) @ np.asarray(LUMA_WEIGHTS)
    if arr.ndim != 2:
        raise ValueError(
            f"image must be grey (H, W) or colour (H, W, 3) / (H, W, 4), got shape {arr.shape}"
        )
    if min(arr.shape) < 3:
        raise ValueError(f"image must be at least 3 x 3 pixels, got shape {arr.shape}")
    arr = arr.astype(float)
    if not np.isfinite(arr).all():
        raise ValueError("image must hold finite values, got NaN or inf")
    return arr


def _touches(region: np.ndarray) -> list[str]:
    edges = {"top": region[0], "bottom": region[-1], "left": region[:, 0], "right": region[:, -1]}
    return [side for side, edge in edges.items() if edge.any()]


def _components(foreground: np.ndarray):
    labels, _ = ndimage.label(foreground, structure=EIGHT_CONNECTED)
    sizes = np.bincount(labels.ravel())[1:]
    order = np.argsort(-sizes, kind="stable")
    return labels, sizes[order], order + 1


def _largest(foreground: np.ndarray) -> np.ndarray:
    labels, _, ids = _components(foreground)
    return labels == ids[0]


def mask_from_image(
    image,
    *,
    threshold=None,
    object="auto",
    fill_holes: bool = True,
    resolution: float = DEFAULT_RESOLUTION,
) -> Mask:
    """Turn a camera image of one object on a table into a :class:`Mask`.

    Parameters
    ----------
    image : array_like or str or os.PathLike
        A grey image (H, W) or a colour one (H, W, 3) / (H, W, 4), RGB(A)
        order (alpha ignored), of uint8, uint16, float or bool values; or the
        path of an image file, read with opencv (``pip install comcore[sim]``;
        its BGR order is handled).
    threshold : float, optional
        Grey level (in the image's own units) splitting object from table:
        pixels ``>= threshold`` are bright. Default: Otsu's threshold
        (:func:`otsu_threshold`). Colour images are first turned grey
        (BT.601 luma).
    object : {"auto", "bright", "dark"}, optional
        Whether the object is brighter or darker than the table. ``"auto"``
        picks the side whose largest region does not touch the image border
        (the table surrounds the object); when both or neither do, the side
        with fewer pixels (the object is the minority).
    fill_holes : bool, optional
        Fill holes inside the object (``scipy.ndimage.binary_fill_holes``);
        a footprint has none.
    resolution : float, optional
        Metres per pixel of the table plane (the camera calibration).

    Returns
    -------
    Mask
        The largest 8-connected region of the object's side.

    Raises
    ------
    comcore.ImageError
        (a ``ValueError``) for an image that does not show one whole object,
        saying what was seen: a constant image (all dark or all bright), no
        pixel on the object's side of the threshold, a speckled result (the
        largest region holds less than half the object side's pixels),
        several objects of similar size, or an object touching the image
        border (part of it may be out of view).
    ValueError
        For a bad shape, NaN or inf, an unknown ``object`` or a path that
        cannot be read.
    TypeError
        For a non-numeric image or threshold.
    ImportError
        For a path when opencv is not installed.

    Examples
    --------
    A dark object on a bright table, as a camera would give it (uint8):

    >>> import numpy as np, comcore
    >>> img = np.full((40, 60), 200, np.uint8)
    >>> img[10:30, 15:45] = 30
    >>> mask = comcore.mask_from_image(img)
    >>> mask.area_px, mask.centroid
    (600, (29.5, 19.5))
    >>> comcore.mask_from_image(np.zeros((40, 60), np.uint8))
    Traceback (most recent call last):
    ...
    comcore._errors.ImageError: image is constant (every pixel is 0): all dark or all bright...
    """
    if isinstance(image, (str, os.PathLike)):
        image = _read(image)
    grey = _grey(image)
    if object not in OBJECTS:
        raise ValueError(f"object must be one of {', '.join(map(repr, OBJECTS))}, got {object!r}")
    lo, hi = float(grey.min()), float(grey.max())
    if lo == hi:
        raise ImageError(
            f"image is constant (every pixel is {lo:g}): all dark or all bright, no object to see"
        )
    if threshold is None:
        t = otsu_threshold(grey)
    else:
        if isinstance(threshold, bool) or not isinstance(
            threshold, (int, float, np.integer, np.floating)
        ):
            raise TypeError(f"threshold must be a number or None, got {type(threshold).__name__}")
        t = float(threshold)
        if not math.isfinite(t):
            raise ValueError(f"threshold must be finite, got {t}")
    bright = grey >= t
    sides = {"bright": bright, "dark": ~bright}
    if object == "auto":
        object = _auto_side(sides)
    foreground = sides[object]
    if not foreground.any():
        raise ImageError(
            f"no {object} pixel at threshold {t:g} (the image spans {lo:g} to {hi:g}): "
            "empty result; give a threshold inside that range or the other object side"
        )
    labels, sizes, ids = _components(foreground)
    total = int(sizes.sum())
    if sizes[0] < MIN_LARGEST_SHARE * total:
        raise ImageError(
            f"speckled result: the {object} side at threshold {t:g} is {len(sizes)} regions, the "
            f"largest only {sizes[0]} of its {total} pixels ({100 * sizes[0] / total:.0f} %); "
            "check the lighting and the threshold, or smooth the image"
        )
    if len(sizes) > 1 and sizes[1] >= MAX_SECOND_RATIO * sizes[0]:
        raise ImageError(
            f"several objects of similar size on the {object} side at threshold {t:g}: the "
            f"largest regions have {sizes[0]} and {sizes[1]} pixels; show one object at a time"
        )
    region = labels == ids[0]
    if fill_holes:
        region = ndimage.binary_fill_holes(region)
    touching = _touches(region)
    if touching:
        raise ImageError(
            f"the object ({object} side, {int(region.sum())} pixels) touches the image border "
            f"({', '.join(touching)}): part of it may be out of view; move the camera or the object"
        )
    return Mask(region, resolution=resolution)


def _auto_side(sides: dict[str, np.ndarray]) -> str:
    """The side that is the object: its largest region is off the border, else the minority."""
    inside = [name for name, fg in sides.items() if fg.any() and not _touches(_largest(fg))]
    if len(inside) == 1:
        return inside[0]
    return min(sides, key=lambda name: int(sides[name].sum()))
