"""The :class:`Mask` type: a boolean object image with a resolution."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, partial

import numpy as np
from scipy import ndimage

from ._checks import check_points, is_ragged
from ._neighbourhood import (
    LocalArrays,
    Window,
    filter_halo,
    margin_px,
    padded_crop,
    true_pixels,
)
from .conventions import DEFAULT_RESOLUTION, check_image_size, check_plausible

__all__ = ["Mask"]

#: Gaussian sigma (pixels) of the smoothing used to estimate outline normals.
NORMAL_SMOOTHING_PX = 2.0
#: Padding of the smoothed mask, and how far its gradient reaches from a cut edge.
_NORMAL_PAD = int(4 * NORMAL_SMOOTHING_PX) + 2
_NORMAL_HALO = filter_halo(NORMAL_SMOOTHING_PX)


def _as_bool_image(data) -> np.ndarray:
    if isinstance(data, Mask):
        return data.data
    try:
        arr = np.asarray(data)
    except Exception as e:
        if is_ragged(e):
            raise TypeError(
                "mask data must be a 2-D (H, W) array, got ragged rows (nested lists of "
                "different lengths)"
            ) from e
        raise TypeError(f"mask data must be array_like, got {type(data).__name__}") from e
    if arr.ndim != 2:
        raise ValueError(
            f"mask data must be a 2-D (H, W) array, got {arr.ndim}-D shape {arr.shape}"
        )
    if arr.size == 0:
        raise ValueError(f"mask data must not be empty, got shape {arr.shape}")
    check_image_size(arr.shape, "mask data")
    if arr.dtype == bool:
        return arr.copy()
    if arr.dtype.kind not in "iuf":
        raise TypeError(
            f"mask data must be boolean-like (bool or 0/1 numbers), got dtype {arr.dtype}"
        )
    if arr.dtype.kind == "f" and not np.isfinite(arr).all():
        raise ValueError("mask data must not contain NaN or inf")
    if not np.isin(arr, (0, 1)).all():
        lo, hi = arr.min(), arr.max()
        raise ValueError(
            "mask data must be boolean-like: only 0 and 1 allowed for numeric arrays, got values "
            f"from {lo:g} to {hi:g}; for a camera image (e.g. 0/255 from cv2.imread) use "
            "comcore.mask_from_image(image), which thresholds it"
        )
    return arr.astype(bool)


def _outside(data: np.ndarray, window: Window) -> tuple[np.ndarray]:
    """The distance to the nearest object pixel on a window holding the object."""
    return (ndimage.distance_transform_edt(~window.crop(data)),)


def _inward(data: np.ndarray, window: Window) -> tuple[np.ndarray, np.ndarray]:
    """The smoothed indicator's gradient ``(d/dx, d/dy)`` on a window of the padded image."""
    smooth = ndimage.gaussian_filter(
        padded_crop(data, _NORMAL_PAD, window).astype(float), NORMAL_SMOOTHING_PX, mode="constant"
    )
    gy, gx = np.gradient(smooth)
    return gx, gy


@dataclass(frozen=True, eq=False)
class Mask:
    """An object's footprint as seen by the camera.

    Parameters
    ----------
    data : array_like of bool, shape (H, W)
        ``True`` where the object is, indexed ``[row, col]``. Copied and made
        read-only; numeric arrays may hold only 0 and 1.
    resolution : float, optional
        Metres per pixel (like a ROS ``OccupancyGrid``), default 2.5 mm; values
        outside ``comcore.conventions.PLAUSIBLE["resolution"]`` (10 micrometres to 5 cm a
        pixel) are refused with a guess at the unit they were typed in.

    Examples
    --------
    >>> import numpy as np
    >>> m = Mask(np.pad(np.ones((4, 6), bool), 2), resolution=0.01)
    >>> m.shape, m.area_px, round(m.area_m2, 6)
    ((8, 10), 24, 0.0024)
    >>> m.centroid
    (4.5, 3.5)
    >>> Mask(np.zeros((3, 3)))
    Traceback (most recent call last):
    ...
    ValueError: mask must contain at least one object pixel, got an all-False image
    >>> Mask(np.ones((3, 3)), resolution=2.5)
    Traceback (most recent call last):
    ...
    ValueError: resolution 2.5 m per pixel is implausible (expected 1e-05 to 0.05 m per pixel): did you mean millimetres, 0.0025?
    """  # noqa: E501

    data: np.ndarray
    resolution: float = DEFAULT_RESOLUTION

    def __post_init__(self):
        data = _as_bool_image(self.data)
        if not data.any():
            raise ValueError("mask must contain at least one object pixel, got an all-False image")
        data.setflags(write=False)
        object.__setattr__(self, "data", data)
        res = self.resolution
        if isinstance(res, bool) or not isinstance(res, (int, float, np.integer, np.floating)):
            raise TypeError(
                f"resolution must be a positive number (metres per pixel), got {type(res).__name__}"
            )
        res = float(res)
        if not math.isfinite(res) or res <= 0:
            raise ValueError(
                f"resolution must be a positive finite number (metres per pixel), got {res}"
            )
        # before anything is sized by it: 2.5 (millimetres typed as metres) would make every
        # length in metres a thousand times too short in pixels
        object.__setattr__(self, "resolution", check_plausible(res, "resolution", "resolution"))

    # -- basic measures -------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of the image."""
        return self.data.shape  # type: ignore[return-value]

    @cached_property
    def _box(self) -> Window:
        """The object's bounding box (:mod:`comcore._neighbourhood`)."""
        return Window.around(self.data, 0)

    @cached_property
    def pixels(self) -> np.ndarray:
        """Centres ``(x, y)`` of the object's pixels, shape (m, 2), row-major order."""
        out = true_pixels(self.data, self._box)  # every object pixel is in the box
        out.setflags(write=False)
        return out

    @property
    def area_px(self) -> int:
        """Area in pixels."""
        return int(self.pixels.shape[0])

    @property
    def area_m2(self) -> float:
        """Area in square metres."""
        return self.area_px * self.resolution**2

    @cached_property
    def centroid(self) -> tuple[float, float]:
        """Area centroid ``(x, y)`` in pixels."""
        c = self.pixels.mean(axis=0)
        return (float(c[0]), float(c[1]))

    @property
    def centroid_m(self) -> tuple[float, float]:
        """Area centroid in metres in the mask frame."""
        return self.to_metres(self.centroid)

    @cached_property
    def boundary(self) -> np.ndarray:
        """Object pixels with a 4-neighbour outside the object (bool image, read-only)."""
        window = self._box.grown_by(1)  # background all round, or the image's own border
        part = window.crop(self.data)
        out = np.zeros(self.shape, bool)
        window.crop(out)[...] = part & ~ndimage.binary_erosion(part, border_value=0)
        out.setflags(write=False)
        return out

    def to_metres(self, points_px):
        """Pixel coordinates to metres in the mask frame (same axes, scaled).

        Parameters
        ----------
        points_px : array_like, shape (2,) or (..., 2)
            Finite pixel coordinates ``(x, y)``.

        Returns
        -------
        tuple of float or numpy.ndarray
            A tuple for a single point and an array otherwise.

        Raises
        ------
        ValueError
            If the coordinates do not come in ``(x, y)`` pairs, or hold NaN or
            inf (an estimate gone wrong upstream: refused here, not scaled).

        Examples
        --------
        >>> m = Mask(np.ones((3, 3), bool), resolution=0.002)
        >>> m.to_metres((10.0, 5.0))
        (0.02, 0.01)
        >>> m.to_metres((float("nan"), 5.0))
        Traceback (most recent call last):
        ...
        ValueError: points_px must be finite pixel coordinates (x, y), got (nan, 5.0)
        """
        try:
            p = np.asarray(points_px, dtype=float)
        except (TypeError, ValueError) as e:
            raise ValueError(f"points_px must be pixel coordinates (x, y): {e}") from e
        if p.ndim == 0 or p.shape[-1] != 2:
            raise ValueError(
                f"points_px must be pixel coordinates (x, y), shape (2,) or (n, 2), got shape "
                f"{p.shape}"
            )
        bad = ~np.isfinite(p).all(axis=-1)
        if bad.any():
            x, y = p.reshape(-1, 2)[int(np.flatnonzero(bad.reshape(-1))[0])]
            raise ValueError(f"points_px must be finite pixel coordinates (x, y), got ({x}, {y})")
        p = p * self.resolution
        return (float(p[0]), float(p[1])) if p.shape == (2,) else p

    def contains(self, points) -> np.ndarray:
        """Whether points ``(x, y)`` fall on object pixels (nearest pixel).

        Parameters
        ----------
        points : array_like, shape (n, 2) or (2,)
            Finite pixel coordinates ``(x, y)``.

        Returns
        -------
        numpy.ndarray of bool, shape (n,)

        Raises
        ------
        ValueError
            If ``points`` is not of shape (n, 2) or holds NaN or inf.

        Examples
        --------
        >>> m = Mask(np.pad(np.ones((2, 2), bool), 1))
        >>> m.contains([[1.0, 1.0], [0.4, 1.0], [-7.0, 30.0]]).tolist()
        [True, False, False]
        """
        return self._contains(check_points(points))

    def _contains(self, p: np.ndarray) -> np.ndarray:
        """Unvalidated core of :meth:`contains`: ``p`` is a finite (n, 2) array."""
        cols = np.floor(p[:, 0] + 0.5).astype(np.int64)
        rows = np.floor(p[:, 1] + 0.5).astype(np.int64)
        h, w = self.shape
        inside = (rows >= 0) & (rows < h) & (cols >= 0) & (cols < w)
        out = np.zeros(len(p), dtype=bool)
        out[inside] = self.data[rows[inside], cols[inside]]
        return out

    @cached_property
    def _outside_distance(self) -> LocalArrays:
        """Distance (pixels) from each pixel centre to the nearest object pixel centre.

        On the object's neighbourhood (:mod:`comcore._neighbourhood`), grown when asked elsewhere.
        """
        margin = margin_px(self.resolution)
        return LocalArrays(self._box.grown_by(margin), partial(_outside, self.data), 0, margin)

    def distance_to_object(self, points) -> np.ndarray:
        """Distance in pixels from points ``(x, y)`` to the nearest object pixel centre.

        Points off the image get the distance at the nearest image pixel plus
        the distance to that pixel (an upper bound within one pixel).

        Parameters
        ----------
        points : array_like, shape (n, 2) or (2,)
            Finite pixel coordinates ``(x, y)``.

        Returns
        -------
        numpy.ndarray, shape (n,)

        Raises
        ------
        ValueError
            If ``points`` is not of shape (n, 2) or holds NaN or inf.

        Examples
        --------
        >>> m = Mask(np.pad(np.ones((2, 2), bool), 1))
        >>> m.distance_to_object([[1.0, 1.0], [1.0, -1.0]]).tolist()
        [0.0, 2.0]
        """
        p = check_points(points)
        h, w = self.shape
        col = np.clip(np.floor(p[:, 0] + 0.5), 0, w - 1)
        row = np.clip(np.floor(p[:, 1] + 0.5), 0, h - 1)
        off = np.hypot(p[:, 0] - col, p[:, 1] - row)
        return self._outside_distance.at(row.astype(int), col.astype(int))[0] + np.where(
            (col == np.floor(p[:, 0] + 0.5)) & (row == np.floor(p[:, 1] + 0.5)), 0.0, off
        )

    @cached_property
    def _inward_field(self) -> LocalArrays:
        """Gradient (d/dx, d/dy) of the smoothed indicator, padded: points into the object.

        On the object's neighbourhood (:mod:`comcore._neighbourhood`), grown when asked elsewhere.
        """
        margin = margin_px(self.resolution)
        return LocalArrays(
            self._box.grown_by(margin + _NORMAL_HALO, _NORMAL_PAD),
            partial(_inward, self.data), _NORMAL_HALO, margin,
        )

    def inward_normals(self, points) -> np.ndarray:
        """Unit inward normals of the outline near points ``(x, y)``, shape (n, 2).

        Estimated from the gradient of the mask smoothed with a Gaussian of
        ``NORMAL_SMOOTHING_PX`` pixels, interpolated at the (sub-pixel) points:
        robust to the staircase of a pixel outline. Where the gradient vanishes
        (deep inside or far outside the object) the normal is ``(0, 0)``.

        Raises
        ------
        ValueError
            If ``points`` is not of shape (n, 2) or (2,), or holds NaN or inf.
        """
        p = check_points(points)
        nx, ny = self._inward_field.interpolate(
            p[:, 1] + _NORMAL_PAD, p[:, 0] + _NORMAL_PAD, "constant"
        )
        v = np.column_stack([nx, ny])
        norm = np.hypot(nx, ny)
        good = norm > 1e-9
        v[good] /= norm[good, None]
        v[~good] = 0.0
        return v

    # -- a printable, rebuildable form ----------------------------------------------
    def to_rle(self) -> str:
        """The image as run lengths: alternating runs of False and True pixels, row-major.

        The first run counts the leading False pixels (0 if the image starts with the
        object); the trailing False run is left out. :meth:`from_rle` rebuilds the image.

        Examples
        --------
        >>> import numpy as np
        >>> Mask(np.array([[0, 1, 1], [0, 0, 1]])).to_rle()
        '1 2 2 1'
        """
        flat = np.concatenate([[False], self.data.ravel(), [False]])
        edges = np.flatnonzero(flat[1:] != flat[:-1])  # starts of True runs, then their ends
        runs = np.diff(np.concatenate([[0], edges]))
        return " ".join(str(int(r)) for r in runs)

    @classmethod
    def from_rle(
        cls, shape, rle: str, resolution: float = DEFAULT_RESOLUTION, *,
        area_px: int | None = None, centroid=None,
    ) -> Mask:
        """A mask rebuilt from :meth:`to_rle`'s run lengths (the form its repr prints).

        Parameters
        ----------
        shape : tuple of int, (H, W)
            The image's size.
        rle : str
            Run lengths separated by spaces: alternating False and True runs, row-major,
            starting with a False run (which may be 0); the last False run may be left out.
        resolution : float, optional
            Metres per pixel, as :class:`Mask` takes it.
        area_px : int, optional
            If given, the rebuilt mask must have this many object pixels.
        centroid : (float, float), optional
            If given, the rebuilt centroid ``(x, y)`` must match it to 0.01 pixel.

        Returns
        -------
        Mask

        Raises
        ------
        ValueError
            If the runs do not fit ``shape``, or ``area_px``/``centroid`` disagree with them
            (the printed form was edited or cut).

        Examples
        --------
        >>> import numpy as np
        >>> m = Mask(np.pad(np.ones((2, 3), bool), 1), resolution=0.01)
        >>> m
        Mask.from_rle((4, 5), '6 3 2 3', resolution=0.01, area_px=6, centroid=(2.0, 1.5))
        >>> np.array_equal(eval(repr(m)).data, m.data)
        True
        """
        try:
            h, w = (int(v) for v in shape)
        except (TypeError, ValueError) as e:
            raise ValueError(f"shape must be two integers (H, W), got {shape!r}") from e
        if h <= 0 or w <= 0:
            raise ValueError(f"shape must be two positive integers (H, W), got {shape!r}")
        check_image_size((h, w), "shape")
        if not isinstance(rle, str):
            raise TypeError(f"rle must be a string of run lengths, got {type(rle).__name__}")
        try:
            runs = np.array([int(v) for v in rle.split()], dtype=np.int64)
        except ValueError as e:
            raise ValueError(
                f"rle must hold non-negative integers separated by spaces, got {rle[:40]!r}"
            ) from e
        if (runs < 0).any() or runs.sum() > h * w:
            raise ValueError(
                f"rle must hold non-negative run lengths adding up to at most {h} * {w} = "
                f"{h * w} pixels, got runs adding up to {int(runs.sum())}"
            )
        flat = np.repeat(np.arange(len(runs)) % 2 == 1, runs)
        mask = cls(np.pad(flat, (0, h * w - flat.size)).reshape(h, w), resolution)
        if area_px is not None and mask.area_px != area_px:
            raise ValueError(f"area_px {area_px} disagrees with the runs' {mask.area_px} pixels")
        if centroid is not None and not np.allclose(mask.centroid, centroid, rtol=0, atol=0.01):
            raise ValueError(
                f"centroid {tuple(centroid)} disagrees with the runs' centroid {mask.centroid}"
            )
        return mask

    def _repr_pretty_(self, printer, cycle) -> None:
        """Print as :meth:`__repr__` in IPython and hypothesis (not field by field)."""
        printer.text(repr(self))

    def __repr__(self) -> str:
        cx, cy = self.centroid
        return (
            f"Mask.from_rle({self.shape}, {self.to_rle()!r}, resolution={self.resolution!r}, "
            f"area_px={self.area_px}, centroid=({round(cx, 2)!r}, {round(cy, 2)!r}))"
        )
