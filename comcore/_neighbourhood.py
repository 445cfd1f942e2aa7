"""The object's neighbourhood: per-mask fields computed on a window of the image, not the frame.

A camera over a table sees a small object in a wide frame (0.2 % of 1280 x 720
pixels), and the fields a mask carries (distance transforms, smoothed outlines,
the limit-surface model's pressure table) cost as much as the frame is large.
What uses them asks about the object's neighbourhood only: the outline, the
pushes' paths from their start to their end, the CoM hypotheses. So each field
is computed on a :class:`Window`: the object's bounding box grown by a margin
(:data:`NEIGHBOURHOOD_MARGIN_M`, which covers a push's standoff, its travel and
the pusher), clipped to the image.

The results are those of the whole image, not an approximation: a
:class:`LocalArrays` knows how far inside its window the values are exact
(``halo``: what a filter's support reaches, measured from an edge of the
window that cuts the image; an edge on the image's own border is exact to the
edge) and, when it is asked about a pixel outside that exact part, computes
again on a window grown to cover it (at worst the whole image, as before).
Coordinates stay those of the whole image for the caller: indices are shifted
by the window's origin on the way in, and results on the way out.

Choice (written down here): the margin is a cost trade, never a result. A
distance transform is exact anywhere on a window that holds every object
pixel; a Gaussian of ``sigma`` truncated at ``4 sigma`` (scipy's default) and a
central difference are exact ``ceil(4 sigma) + 1`` pixels from a cut edge.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

__all__ = [
    "NEIGHBOURHOOD_MARGIN_M",
    "LocalArrays",
    "Window",
    "filter_halo",
    "margin_px",
    "padded_crop",
    "true_pixels",
]

#: Margin (metres) of the window around the object: a push's standoff (1.2 cm by
#: default), the pusher's radius and its travel past the outline (3 cm) fit in it.
NEIGHBOURHOOD_MARGIN_M = 0.05


def margin_px(resolution: float, margin_m: float | None = None) -> int:
    """The margin in whole pixels at ``resolution`` metres per pixel (at least one).

    ``margin_m`` defaults to :data:`NEIGHBOURHOOD_MARGIN_M`, read when called.

    Examples
    --------
    >>> margin_px(0.001), margin_px(0.0025), margin_px(0.001, 0.003)
    (50, 20, 3)
    """
    margin_m = NEIGHBOURHOOD_MARGIN_M if margin_m is None else margin_m
    return max(1, math.ceil(margin_m / resolution - 1e-9))


def filter_halo(sigma: float, differences: int = 1) -> int:
    """Pixels from a cut edge that a Gaussian of ``sigma`` (then central differences) reach.

    scipy's ``gaussian_filter`` has a radius of ``int(4 * sigma + 0.5)``; each
    ``np.gradient`` adds one pixel.

    Examples
    --------
    >>> filter_halo(1.0), filter_halo(2.0), filter_halo(1.5, differences=0)
    (5, 9, 6)
    """
    return int(4.0 * sigma + 0.5) + differences


@dataclass(frozen=True)
class Window:
    """A box ``[lo[0], hi[0]) x [lo[1], hi[1])`` of an array's first two axes.

    Attributes
    ----------
    lo, hi : tuple of int
        First index in, first index past, per axis (rows then columns of an image).
    shape : tuple of int
        The whole array's first two axes; ``0 <= lo < hi <= shape``.

    Examples
    --------
    >>> image = np.zeros((10, 20), bool); image[4:6, 8:11] = True
    >>> w = Window.around(image, 2)
    >>> w.lo, w.hi, w.crop(image).shape
    ((2, 6), (8, 13), (6, 7))
    >>> w.grown([0], [5], margin=1).lo
    (0, 4)
    """

    lo: tuple[int, int]
    hi: tuple[int, int]
    shape: tuple[int, int]

    @classmethod
    def around(cls, image: np.ndarray, margin: int, pad: int = 0) -> Window:
        """The bounding box of ``image``'s true values grown by ``margin``, clipped to it.

        With ``pad``, on ``np.pad(image, pad)`` (its shape and indices). An
        image without a true value gives the whole image.
        """
        shape = (int(image.shape[0]), int(image.shape[1]))
        rows = np.flatnonzero(image.any(axis=1))
        cols = np.flatnonzero(image.any(axis=0))
        if not len(rows):
            return cls((0, 0), shape, shape).grown_by(0, pad)
        return cls((rows[0], cols[0]), (rows[-1] + 1, cols[-1] + 1), shape).grown_by(margin, pad)

    def grown_by(self, margin: int, pad: int = 0) -> Window:
        """The box grown by ``margin`` on the array padded by ``pad`` (its indices), clipped."""
        shape = (self.shape[0] + 2 * pad, self.shape[1] + 2 * pad)
        lo = (self.lo[0] + pad, self.lo[1] + pad)
        hi = (self.hi[0] + pad, self.hi[1] + pad)
        if self.lo == (0, 0) and self.hi == self.shape:  # the whole image: the whole padded one
            lo, hi = (0, 0), shape
        return Window.box(shape, lo, hi, margin)

    @classmethod
    def box(cls, shape, lo, hi, margin: int = 0) -> Window:
        """The box ``[lo, hi)`` grown by ``margin``, clipped to ``shape``."""
        shape = (int(shape[0]), int(shape[1]))
        low = tuple(max(0, int(lo[k]) - margin) for k in (0, 1))
        high = tuple(min(shape[k], int(hi[k]) + margin) for k in (0, 1))
        return cls(low, high, shape)  # type: ignore[arg-type]

    @property
    def whole(self) -> bool:
        """Whether the window is the whole array."""
        return self.lo == (0, 0) and self.hi == self.shape

    def crop(self, array: np.ndarray) -> np.ndarray:
        """The window's part of ``array`` (a view)."""
        return array[self.lo[0] : self.hi[0], self.lo[1] : self.hi[1]]

    def exact(self, halo: int) -> tuple[tuple[int, int], tuple[int, int]]:
        """``(lo, hi)`` of the part ``halo`` pixels inside every edge that cuts the array."""
        lo = tuple(self.lo[k] + (halo if self.lo[k] > 0 else 0) for k in (0, 1))
        hi = tuple(self.hi[k] - (halo if self.hi[k] < self.shape[k] else 0) for k in (0, 1))
        return lo, hi  # type: ignore[return-value]

    def covers(self, index0, index1, halo: int = 0) -> bool:
        """Whether every index pair (in the array's range) lies in the exact part."""
        (lo0, lo1), (hi0, hi1) = self.exact(halo)
        i, j = np.asarray(index0), np.asarray(index1)
        if i.size == 0:
            return True
        return bool(i.min() >= lo0 and i.max() < hi0 and j.min() >= lo1 and j.max() < hi1)

    def grown(self, index0, index1, margin: int, halo: int = 0) -> Window:
        """The smallest window holding this one and the indices ``margin + halo`` inside it."""
        i, j = np.asarray(index0), np.asarray(index1)
        reach = margin + halo
        lo = (min(self.lo[0], int(i.min()) - reach), min(self.lo[1], int(j.min()) - reach))
        hi = (max(self.hi[0], int(i.max()) + 1 + reach), max(self.hi[1], int(j.max()) + 1 + reach))
        return Window.box(self.shape, lo, hi)


def true_pixels(image: np.ndarray, window: Window) -> np.ndarray:
    """Centres ``(x, y)`` of ``image``'s true pixels in ``window``, whole-image coordinates.

    Row-major, as ``comcore.conventions.pixel_centres(image)``: the same array when the
    window holds every true pixel, at the window's cost.

    Examples
    --------
    >>> image = np.zeros((6, 8), bool); image[2, 5] = image[3, 4] = True
    >>> true_pixels(image, Window((2, 4), (4, 6), (6, 8))).tolist()
    [[5.0, 2.0], [4.0, 3.0]]
    """
    rows, cols = np.nonzero(window.crop(image))
    return np.column_stack([cols + window.lo[1], rows + window.lo[0]]).astype(float)


def padded_crop(data: np.ndarray, pad: int, window: Window) -> np.ndarray:
    """The window's part of ``np.pad(data, pad)`` (zeros around), without padding the whole.

    ``window`` is on the padded image's shape.

    Examples
    --------
    >>> data = np.arange(1, 7).reshape(2, 3)
    >>> padded_crop(data, 1, Window((0, 2), (3, 5), (4, 5))).tolist()
    [[0, 0, 0], [2, 3, 0], [5, 6, 0]]
    """
    out = np.zeros((window.hi[0] - window.lo[0], window.hi[1] - window.lo[1]), data.dtype)
    src, dst = [], []
    for k in (0, 1):
        a = max(window.lo[k] - pad, 0)
        b = min(window.hi[k] - pad, data.shape[k])
        src.append(slice(a, max(a, b)))
        dst.append(slice(a + pad - window.lo[k], max(a, b) + pad - window.lo[k]))
    out[dst[0], dst[1]] = data[src[0], src[1]]
    return out


class LocalArrays:
    """Arrays over a whole image computed on a window of it, exact, grown when asked outside.

    Parameters
    ----------
    window : Window
        Where to compute first (the object's neighbourhood).
    make : callable
        ``make(window)`` returns a tuple of arrays whose first two axes are the
        window's: the whole image's arrays, cut to the window, wherever they
        are exact (``halo`` from the window's cut edges).
    halo : int
        How far inside a cut edge the arrays are not yet exact.
    margin : int
        Extra pixels taken beyond the asked ones when the window grows.

    Examples
    --------
    A distance transform, exact anywhere on a window that holds the object:

    >>> from scipy import ndimage
    >>> image = np.zeros((40, 60), bool); image[10:14, 20:25] = True
    >>> local = LocalArrays(
    ...     Window.around(image, 3), lambda w: (ndimage.distance_transform_edt(~w.crop(image)),)
    ... )
    >>> local.window.lo, local.window.hi
    ((7, 17), (17, 28))
    >>> float(local.at([12], [30])[0][0]), local.window.hi  # outside: the window grows
    (6.0, (17, 31))
    >>> bool(local.at([39], [0])[0][0] == ndimage.distance_transform_edt(~image)[39, 0])
    True
    """

    def __init__(
        self, window: Window, make: Callable[[Window], tuple], halo: int = 0, margin: int = 0
    ):
        self._make, self.halo, self.margin = make, int(halo), int(margin)
        self._state = (window, tuple(make(window)))  # replaced whole: a reader sees one pair

    @property
    def window(self) -> Window:
        """Where the arrays are computed now."""
        return self._state[0]

    def local(self, index0, index1) -> tuple[tuple[np.ndarray, ...], tuple[int, int]]:
        """The arrays, once they hold the index pairs exactly, and their window's origin ``lo``.

        The window is grown (and the arrays computed again) unless it holds them.
        """
        window, arrays = self._state
        if not window.covers(index0, index1, self.halo):
            window = window.grown(index0, index1, self.margin, self.halo)
            self._state = window, arrays = window, tuple(self._make(window))
        return arrays, window.lo

    def at(self, index0, index1) -> tuple[np.ndarray, ...]:
        """Each array at whole-image indices (integer arrays of one shape, in range)."""
        i, j = np.asarray(index0, dtype=np.intp), np.asarray(index1, dtype=np.intp)
        arrays, (i0, j0) = self.local(i, j)
        return tuple(a[i - i0, j - j0] for a in arrays)

    def interpolate(
        self, coord0, coord1, mode: str = "nearest", cval: float = 0.0, count: int | None = None
    ) -> tuple[np.ndarray, ...]:
        """``scipy.ndimage.map_coordinates(array, [coord0, coord1], order=1)`` of each array.

        The same numbers as on the whole image: the window is grown to hold
        both neighbours of every finite point (clipped to the image, as
        ``mode="nearest"`` clamps them; beyond the image's border ``"constant"``
        gives ``cval`` on the window as on the image, since the window then
        reaches that border), and the coordinates are shifted by its origin, an
        integer (exact in floating point). ``coord0``, ``coord1``: 1-D, one length.
        ``count``: only the first ``count`` arrays (default all).
        """
        c0, c1 = np.asarray(coord0, dtype=float), np.asarray(coord1, dtype=float)
        finite = np.isfinite(c0) & np.isfinite(c1)
        shape = self.window.shape
        f0 = np.floor(np.clip(c0[finite], -1.0, shape[0]))
        f1 = np.floor(np.clip(c1[finite], -1.0, shape[1]))
        i = np.clip(np.concatenate([f0, f0 + 1]), 0, shape[0] - 1).astype(np.intp)
        j = np.clip(np.concatenate([f1, f1 + 1]), 0, shape[1] - 1).astype(np.intp)
        arrays, (i0, j0) = self.local(i, j)
        coords = np.vstack([c0 - i0, c1 - j0])
        return tuple(
            ndimage.map_coordinates(a, coords, order=1, mode=mode, cval=cval)
            for a in arrays[:count]
        )
