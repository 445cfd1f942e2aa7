"""From a camera image to a :class:`Mask`: :func:`mask_from_image`."""

from __future__ import annotations

import math
import os

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._status import ImageError
from ..conventions import DEFAULT_RESOLUTION, check_image_size
from ..geometry._regions import EIGHT_CONNECTED
from ._input import check_background, grey_image, look_window, read_image
from ._object import find_object

__all__ = ["mask_from_image", "otsu_threshold"]

#: Bins of the grey-level histogram of Otsu's method.
OTSU_BINS = 256
#: Speckled: the largest component holds less than this share of the foreground pixels.
MIN_LARGEST_SHARE = 0.5
#: Several objects: the second component is at least this fraction of the largest.
MAX_SECOND_RATIO = 0.5
OBJECTS = ("auto", "bright", "dark")
#: The named thresholds: the fitted table (the default) and one global level.
THRESHOLDS = ("auto", "otsu")


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


def _auto_side(sides: dict[str, np.ndarray]) -> str:
    """The side that is the object: its largest region is off the border, else the minority."""
    inside = [name for name, fg in sides.items() if fg.any() and not _touches(_largest(fg))]
    if len(inside) == 1:
        return inside[0]
    return min(sides, key=lambda name: int(sides[name].sum()))


def _threshold_mode(threshold) -> str | float:
    """``"auto"``, ``"otsu"`` or a finite grey level."""
    if threshold is None or (isinstance(threshold, str) and threshold in THRESHOLDS):
        return "auto" if threshold is None else threshold
    if isinstance(threshold, str):
        raise ValueError(
            f"threshold must be a grey level or one of {', '.join(map(repr, THRESHOLDS))}, "
            f"got {threshold!r}"
        )
    if isinstance(threshold, bool) or not isinstance(
        threshold, (int, float, np.integer, np.floating)
    ):
        raise TypeError(
            f"threshold must be a number, 'auto', 'otsu' or None, got {type(threshold).__name__}"
        )
    t = float(threshold)
    if not math.isfinite(t):
        raise ValueError(f"threshold must be finite, got {t}")
    return t


def _global(values, valid, mode, side: str, *, difference: bool, span: tuple[float, float]):
    """One threshold for the whole window (Otsu's or the caller's): region and side."""
    lo, hi = span
    inside = np.ones(values.shape, bool) if valid is None else valid
    if mode == "otsu":
        t = otsu_threshold(np.abs(values[inside]) if difference else values[inside])
    else:
        t = mode
    if difference:  # a difference from the background of at least t, either way
        sides = {"bright": inside & (values >= t), "dark": inside & (values <= -t)}
    else:
        bright = values >= t
        sides = {"bright": inside & bright, "dark": inside & ~bright}
    if side == "auto":
        side = _auto_side(sides)
    foreground = sides[side]
    if not foreground.any():
        what = "difference from the background" if difference else "image"
        raise ImageError(
            f"no {side} pixel at threshold {t:g} (the {what} spans {lo:g} to {hi:g}): "
            "empty result; give a threshold inside that range or the other object side"
        )
    labels, sizes, ids = _components(foreground)
    total = int(sizes.sum())
    if sizes[0] < MIN_LARGEST_SHARE * total:
        raise ImageError(
            f"speckled result: the {side} side at threshold {t:g} is {len(sizes)} regions, the "
            f"largest only {sizes[0]} of its {total} pixels ({100 * sizes[0] / total:.0f} %); "
            "check the lighting and the threshold, or smooth the image (threshold='auto' fits "
            "uneven light)"
        )
    if len(sizes) > 1 and sizes[1] >= MAX_SECOND_RATIO * sizes[0]:
        raise ImageError(
            f"several objects of similar size on the {side} side at threshold {t:g}: the "
            f"largest regions have {sizes[0]} and {sizes[1]} pixels; show one object at a time"
        )
    return labels == ids[0], side


def _fill_holes(region: np.ndarray) -> np.ndarray:
    """``scipy.ndimage.binary_fill_holes`` on the region's bounding box only (the same result)."""
    rows = np.flatnonzero(region.any(axis=1))
    cols = np.flatnonzero(region.any(axis=0))
    box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
    out = region.copy()
    out[box] = ndimage.binary_fill_holes(region[box])
    return out


def _check_edges(region, valid, box, shape, seen_as: str, one_level: bool) -> None:
    """ImageError if the object touches the image border or the edge of the region of interest."""
    h, w = shape
    rows, cols = box
    at_border = {
        "top": rows.start == 0, "bottom": rows.stop == h,
        "left": cols.start == 0, "right": cols.stop == w,
    }
    touching = _touches(region)
    border = [side for side in touching if at_border[side]]
    if border:
        if one_level:
            hint = "one grey level for the whole image splits an unevenly lit table: "
            hint += "threshold='auto' fits the light"
        else:
            hint = "if it is the robot's arm touching the object, move the arm away or give "
            hint += "robot_mask=; a shadow or the table's edge: give background= (an image of "
            hint += "the empty table) or roi= to leave the border out"
        raise ImageError(
            f"the object ({seen_as}) touches the image border ({', '.join(border)}): part of it "
            f"may be out of view; move the camera or the object ({hint})"
        )
    edge = [side for side in touching if not at_border[side]]
    if valid is not None and (region & ~ndimage.binary_erosion(valid, border_value=1)).any():
        edge.append("its boundary")
    if edge:
        raise ImageError(
            f"the object ({seen_as}) touches the edge of roi ({', '.join(edge)}): part of it "
            "may be outside; give a larger roi"
        )


def _difference_spread(empty, box) -> np.ndarray | None:
    """Each pixel's noise in the image less the mean of the empty table's frames (or None)."""
    if empty is None or empty.spread is None:
        return None
    return empty.spread[box] * math.sqrt(1 + 1 / empty.count)


def mask_from_image(
    image,
    *,
    threshold=None,
    object="auto",
    background=None,
    roi=None,
    fill_holes: bool = True,
    resolution: float = DEFAULT_RESOLUTION,
    point=None,
    robot_mask=None,
) -> Mask:
    """Turn a camera image of one object on a table into a :class:`Mask`.

    Parameters
    ----------
    image : array_like or str or os.PathLike
        Grey (H, W) or RGB(A) (H, W, 3|4), or a file (``pip install comcore[sim]``).
    threshold : None, "auto", "otsu" or float, optional
        ``None``/``"auto"``: the outline is half-way between the table's fitted light and the
        object, pixel by pixel (``comcore.camera._object``); ``"otsu"``: one level for the image
        (:func:`otsu_threshold`); a number: that grey level (with ``background``, that difference).
    object : {"auto", "bright", "dark"}, optional
        Whether the object is brighter or darker than the table.
    background : array_like or str or os.PathLike, or a sequence of them, optional
        The empty table (same camera, arm away): the object is where the image differs from it,
        never at the frame's edge (the arm). Several frames (a sequence or a stack
        ``(N, H, W[, 3])``): their mean, and their spread sets each place's threshold.
    roi : tuple of 4 ints or array_like of bool, optional
        Where to look: a box ``(x0, y0, x1, y1)`` (columns x0..x1-1, rows y0..y1-1) or a boolean
        image. The object must lie inside, off its edge.
    fill_holes : bool, optional
        Fill holes inside the object (default).
    resolution : float, optional
        Metres per pixel of the table plane (tilted camera: :class:`comcore.TableView`).
    point : (float, float), optional
        A pixel ``(x, y)`` on the object: of several, the one nearest it.
    robot_mask : array_like of bool, optional
        The robot's pixels (H, W), left out; the object may not touch them.

    Returns
    -------
    Mask
        The object's 8-connected region, of the image's shape.

    Raises
    ------
    comcore.ImageError
        (a ``ValueError``) for an image without one whole object, with the remedy: none, a constant
        image, a speckled result, several (give ``point`` or ``roi``), low contrast (never a partial
        mask), one touching the border, ``roi``'s edge or the robot.
    ValueError, TypeError, ImportError
        For a bad argument (named); for a path without opencv (``pip install comcore[sim]``).

    Examples
    --------
    >>> import numpy as np, comcore
    >>> img = np.full((40, 60), 200, np.uint8)
    >>> img[10:30, 15:45] = 30
    >>> mask = comcore.mask_from_image(img)
    >>> mask.area_px, mask.centroid
    (600, (29.5, 19.5))
    >>> comcore.mask_from_image(np.linspace(160, 240, 60) * np.ones((40, 1)))  # a lit table
    Traceback (most recent call last):
    ...
    comcore._status.ImageError: no object: the image matches the table...
    """
    if isinstance(image, (str, os.PathLike)):
        image = read_image(image)
    if not isinstance(fill_holes, (bool, np.bool_)):
        raise TypeError(f"fill_holes must be True or False, got {fill_holes!r}")
    if np.ndim(image) >= 2:  # before the float copy: a huge view would ask for gigabytes
        check_image_size(np.shape(image), "image")
    grey, floor = grey_image(image)
    if object not in OBJECTS:
        raise ValueError(f"object must be one of {', '.join(map(repr, OBJECTS))}, got {object!r}")
    mode = _threshold_mode(threshold)
    reference = empty = None
    if background is not None:
        empty = check_background(background, grey.shape)
        reference, floor = empty.mean, max(floor, empty.floor)
    look = look_window(roi, robot_mask, point, grey.shape)
    box, valid = look.box, look.valid
    values = grey[box] if reference is None else grey[box] - reference[box]
    seen = values if valid is None else values[valid]
    lo, hi = float(seen.min()), float(seen.max())
    where = " in roi" if roi is not None else ""
    if lo == hi:
        if reference is not None:
            raise ImageError(
                "no object: the image matches the background image (the empty table) "
                f"everywhere{where}: check that the object is in view"
            )
        raise ImageError(
            f"image is constant{where} (every pixel is {lo:g}): all dark or all bright, "
            "no object to see"
        )
    if mode == "auto":
        found = find_object(
            values, valid, object, floor=floor, frame_side=min(grey.shape),
            reference=None if reference is None else reference[box], point=look.point,
            spread=_difference_spread(empty, box),
        )
        region, object = found.region, found.side
        seen_as = (
            f"{object}, {int(region.sum())} pixels, {found.contrast:.3g} grey levels "
            f"{'brighter' if object == 'bright' else 'darker'} than the table"
        )
    else:
        region, object = _global(
            values, valid, mode, object, difference=reference is not None, span=(lo, hi)
        )
        seen_as = f"{object} side, {int(region.sum())} pixels"
    if fill_holes:
        region = _fill_holes(region)
    if (
        look.robot is not None
        and (ndimage.binary_dilation(region, iterations=2) & look.robot).any()
    ):
        raise ImageError(
            f"the object ({seen_as}) touches the robot (robot_mask): move the arm away from the "
            "object before taking the frame"
        )
    _check_edges(region, valid, box, grey.shape, seen_as, one_level=mode == "otsu")
    full = np.zeros(grey.shape, bool)
    full[box] = region
    return Mask(full, resolution=resolution)
