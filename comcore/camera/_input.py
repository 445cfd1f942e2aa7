"""What :func:`comcore.mask_from_image` reads: images and paths, the background, the ROI.

Each input is checked here and turned into what the thresholding works on: a float grey
image and half its grey step (the least difference worth believing in), the background
image of the empty table, and the box of the region of interest.
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np

from .._checks import check_point
from .._mask import Mask

__all__ = [
    "LUMA_WEIGHTS",
    "MAX_BACKGROUND_FRAMES",
    "Background",
    "Look",
    "check_background",
    "grey_image",
    "look_window",
    "read_image",
    "roi_window",
]

#: Luma weights of red, green and blue (ITU-R BT.601), for colour images.
LUMA_WEIGHTS = (0.299, 0.587, 0.114)


def read_image(path) -> np.ndarray:
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


def _float_step(grey: np.ndarray) -> float:
    """Half the step of a float image of 8 or 16 bits (k / 255), else a millionth of its range.

    (matplotlib reads a PNG as floats k / 255.)
    """
    for levels in (255, 65535):
        scaled = grey * levels
        if np.all(np.abs(scaled - np.rint(scaled)) < 1e-3):
            return 0.5 / levels
    return 1e-6 * max(float(np.ptp(grey)), 1e-300)


def grey_image(image, name: str = "image") -> tuple[np.ndarray, float]:
    """A float grey image (H, W) from a grey, RGB or RGBA array, and half its step.

    Half a grey level for integer (and bool) images: the least difference
    worth believing in (:func:`_float_step` for float images).
    """
    if isinstance(image, Mask):
        return image.data.astype(float), 0.5
    arr = np.asarray(image)
    if arr.dtype == bool:
        arr = arr.astype(np.uint8)
    if arr.dtype.kind not in "iuf":
        raise TypeError(
            f"{name} must be a numeric (uint8, uint16, float or bool) array or a path, "
            f"got dtype {arr.dtype}"
        )
    integer = arr.dtype.kind in "iu"
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = arr[..., 0]
    if arr.ndim == 3 and arr.shape[2] in (3, 4):
        arr = arr[..., :3].astype(float) @ np.asarray(LUMA_WEIGHTS)
    if arr.ndim != 2:
        raise ValueError(
            f"{name} must be grey (H, W) or colour (H, W, 3) / (H, W, 4), got shape {arr.shape}"
        )
    if min(arr.shape) < 3:
        raise ValueError(f"{name} must be at least 3 x 3 pixels, got shape {arr.shape}")
    arr = arr.astype(float)
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must hold finite values, got NaN or inf")
    return arr, 0.5 if integer else _float_step(arr)


def roi_window(roi, shape: tuple[int, int]) -> tuple[tuple[slice, slice], np.ndarray | None]:
    """The bounding box of the region of interest and its pixels in that box (None: all)."""
    h, w = shape
    if roi is None:
        return (slice(0, h), slice(0, w)), None
    arr = np.asarray(roi)
    if arr.dtype == bool:
        if arr.shape != shape:
            raise ValueError(
                f"roi as a boolean image must have the image's shape {shape}, got {arr.shape}"
            )
        rows, cols = np.nonzero(arr)
        if rows.size == 0:
            raise ValueError("roi holds no pixel (an all-False image): nothing to look at")
        box = (slice(rows[0], rows[-1] + 1), slice(cols.min(), cols.max() + 1))
        valid = arr[box]
        return box, None if valid.all() else valid
    if arr.shape != (4,) or arr.dtype.kind not in "iuf" or not np.isfinite(arr).all():
        raise ValueError(
            "roi must be a box (x0, y0, x1, y1) in pixels (columns x0..x1-1, rows y0..y1-1) "
            f"or a boolean image of the image's shape, got {roi!r}"
        )
    x0, y0, x1, y1 = (round(float(v)) for v in arr)
    x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, w), min(y1, h)
    if x1 - x0 < 3 or y1 - y0 < 3:
        raise ValueError(
            f"roi {tuple(arr.tolist())} leaves less than 3 x 3 pixels of the {w} x {h} image "
            "(x0, y0, x1, y1 are columns and rows, x first)"
        )
    return (slice(y0, y1), slice(x0, x1)), None


#: At most this many frames of the empty table in ``background``.
MAX_BACKGROUND_FRAMES = 64


class Background(NamedTuple):
    """The empty table from one or more frames: what the image is compared with."""

    mean: np.ndarray
    """Each pixel's mean grey level over the frames (H, W)."""
    spread: np.ndarray | None
    """Each pixel's standard deviation over the frames (H, W); None for one frame."""
    count: int
    """How many frames."""
    floor: float
    """Half the frames' grey step: the least difference believed."""


def _frames(background, shape) -> list:
    """The frames of ``background``: one image, a sequence of them, or a stack (N, H, W[, C])."""
    if isinstance(background, (str, os.PathLike)):
        return [read_image(background)]
    if isinstance(background, (list, tuple)):
        frames = [read_image(f) if isinstance(f, (str, os.PathLike)) else f for f in background]
    else:
        arr = np.asarray(background)
        stack = arr.ndim == 4 or (arr.ndim == 3 and arr.shape[1:] == tuple(shape))
        frames = list(arr) if stack else [background]
    if not frames:
        raise ValueError("background holds no frame: give an image of the empty table, or several")
    if len(frames) > MAX_BACKGROUND_FRAMES:
        raise ValueError(
            f"background may hold at most {MAX_BACKGROUND_FRAMES} frames of the empty table, "
            f"got {len(frames)} (a video? take a few frames of it)"
        )
    return frames


def check_background(background, shape) -> Background:
    """The empty table from one frame or several (a sequence or a stack ``(N, H, W[, C])``)."""
    greys, floor = [], 0.0
    for k, frame in enumerate(_frames(background, shape)):
        name = "background" if k == 0 else f"background frame {k}"
        grey, step = grey_image(frame, name)
        if grey.shape != tuple(shape):
            raise ValueError(
                f"{name} must be an image of the empty table from the same camera, with the "
                f"image's shape {tuple(shape)}, got {grey.shape}"
            )
        greys.append(grey)
        floor = max(floor, step)
    if len(greys) == 1:
        return Background(greys[0], None, 1, floor)
    stack = np.stack(greys)
    return Background(stack.mean(axis=0), stack.std(axis=0, ddof=1), len(greys), floor)


class Look(NamedTuple):
    """Where :func:`comcore.mask_from_image` looks."""

    box: tuple[slice, slice]
    """The window: rows and columns of the image."""
    valid: np.ndarray | None
    """The window's pixels to look at (None: all)."""
    robot: np.ndarray | None
    """The robot's pixels in the window, or None."""
    point: tuple[float, float] | None
    """The pixel ``(x, y)`` on the object, in the window, or None."""


def look_window(roi, robot_mask, point, shape: tuple[int, int]) -> Look:
    """The region of interest less the robot's pixels, and the point in it."""
    box, valid = roi_window(roi, shape)
    robot = None
    if robot_mask is not None:
        arm = np.asarray(robot_mask)
        if arm.dtype != bool or arm.shape != shape:
            raise ValueError(
                f"robot_mask must be a boolean image of the image's shape {shape} (True on the "
                f"robot), got dtype {arm.dtype}, shape {arm.shape}"
            )
        robot = arm[box]
        valid = ~robot if valid is None else valid & ~robot
        if not valid.any():
            raise ValueError("robot_mask covers every pixel where to look: nothing left to see")
    if point is not None:
        x, y = check_point(point, "point")
        rows, cols = box
        if not (cols.start <= x < cols.stop and rows.start <= y < rows.stop):
            raise ValueError(
                f"point ({x:g}, {y:g}) must be a pixel (x, y) = (column, row) inside the image "
                f"and roi (columns {cols.start}..{cols.stop - 1}, "
                f"rows {rows.start}..{rows.stop - 1})"
            )
        point = (x - cols.start, y - rows.start)
    return Look(box, valid, robot, point)
