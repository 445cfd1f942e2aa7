"""The table's light under a camera, fitted on a coarse grid: what ``mask_from_image`` takes off.

1. **Coarse grid** (:class:`Grid`). Block means of ``f x f`` pixels, ``f``
   chosen so that the frame's short side has at most :data:`COARSE_SIDE`
   cells (1 on small images): the light is smooth, and averaging cuts the
   noise by ``f``. The frame's cost is this one pass over its pixels.
2. **A quadratic surface** in x and y (:class:`Quadratic`), fitted robustly
   (trimmed least squares) first to the cells of the window's rim (the table
   surrounds the object, so the rim is table whatever the object's size),
   then to every cell it explains: a gradient, vignetting and any light a
   quadratic describes.
3. **What the quadratic leaves** (:func:`smooth_leftover`: a shadow's soft
   edge, uneven vignetting) on the table cells, carried under the object
   from the nearest table cells and smoothed (a Gaussian of
   :data:`SMOOTH_SHARE` of the frame's short side).

On an exactly flat table (a drawn image) every step is exact: the model is
the table's grey level, with no rounding.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__ = ["Grid", "Quadratic", "smooth_leftover", "spread"]

#: At most this many coarse cells along the short side of the frame.
COARSE_SIDE = 160
#: Cells further than this many standard deviations from the fit are left out of the next fit.
TRIM = 3.0
#: The quadratic is fitted to at most this many cells (evenly strided).
FIT_CELLS = 4000
#: Rounds of the trimmed fit.
FIT_ROUNDS = 4
#: Gaussian sigma of the smoothing of the quadratic's leftovers, as a share of the short side.
SMOOTH_SHARE = 0.02
#: MAD to standard deviation, for a normal distribution.
MAD_TO_SIGMA = 1.4826


def _block_sums(a: np.ndarray, f: int) -> np.ndarray:
    """Sums over ``f x f`` blocks (the last row and column of blocks may be partial)."""
    h, w = a.shape
    rows = a[: h - h % f].reshape(h // f, f, w).sum(axis=1)
    if h % f:
        rows = np.vstack([rows, a[h - h % f :].sum(axis=0, keepdims=True)])
    out = rows[:, : w - w % f].reshape(len(rows), w // f, f).sum(axis=2)
    if w % f:
        out = np.hstack([out, rows[:, w - w % f :].sum(axis=1, keepdims=True)])
    return out


class Grid:
    """A window of the image on the coarse grid: block means, which blocks count, the rim.

    ``values`` (H, W) floats, ``valid`` the pixels to look at (None: all),
    ``frame_side`` the short side of the whole frame (sets the block size, so
    that a region of interest changes where to look, not the grid).
    """

    def __init__(self, values: np.ndarray, valid: np.ndarray | None, frame_side: int):
        h, w = values.shape
        self.shape = (h, w)
        self.frame_side = frame_side
        self.f = f = min(-(-frame_side // COARSE_SIDE), max(min(h, w) // 8, 1))
        if f == 1:
            self.means = np.where(valid, values, 0.0) if valid is not None else values
            share = np.ones(values.shape) if valid is None else valid.astype(float)
        else:
            counts = np.full((-(-h // f), -(-w // f)), float(f * f))
            if h % f or w % f:
                counts = _block_sums(np.ones((h, w)), f)
            if valid is None:
                self.means, share = _block_sums(values, f) / counts, np.ones(counts.shape)
            else:
                weight = _block_sums(valid.astype(float), f)
                self.means = _block_sums(np.where(valid, values, 0.0), f) / np.maximum(weight, 1)
                share = weight / counts
        self.cells = share >= 0.5
        if not self.cells.any():  # a region of interest thinner than a block
            self.cells = share > 0
        rows, cols = np.mgrid[0 : self.cells.shape[0], 0 : self.cells.shape[1]]
        self.x, self.y = cols * f + (f - 1) / 2, rows * f + (f - 1) / 2  # block centres, px
        edge = np.zeros_like(self.cells)
        edge[[0, -1], :] = True
        edge[:, [0, -1]] = True
        inside = ndimage.binary_erosion(self.cells, border_value=1)
        self.rim = self.cells & (edge | ~inside)
        """Cells on the window's edge or beside a cell outside the region of interest."""

    def pixels(self, cells: np.ndarray, rows: slice, cols: slice) -> np.ndarray:
        """Which pixels of the window's ``[rows, cols]`` lie in the marked cells."""
        f = self.f
        return cells[np.ix_(np.arange(rows.start, rows.stop) // f,
                            np.arange(cols.start, cols.stop) // f)]

    def at_pixels(self, cell_values: np.ndarray, rows: slice, cols: slice) -> np.ndarray:
        """Cell values interpolated (bilinear between cell centres) at the window's pixels."""
        f = self.f
        yy, xx = np.mgrid[rows, cols]
        return ndimage.map_coordinates(
            cell_values, [(yy - (f - 1) / 2) / f, (xx - (f - 1) / 2) / f], order=1, mode="nearest"
        )


def spread(values: np.ndarray, floor: float) -> float:
    """Robust standard deviation (MAD) of ``values``, at least ``floor``."""
    if values.size == 0:
        return floor
    return max(MAD_TO_SIGMA * float(np.median(np.abs(values - np.median(values)))), floor)


class Quadratic:
    """A quadratic surface over a window of ``shape`` (coordinates scaled to about [-1, 1])."""

    def __init__(self, shape: tuple[int, int]):
        h, w = shape
        self.centre = ((w - 1) / 2, (h - 1) / 2)
        self.scale = max(h, w) / 2
        self.coef = np.zeros(6)

    def _terms(self, xs, ys) -> np.ndarray:
        u = (np.asarray(xs, float) - self.centre[0]) / self.scale
        v = (np.asarray(ys, float) - self.centre[1]) / self.scale
        return np.stack([np.ones_like(u), u, v, u * u, v * v, u * v], axis=-1)

    def fit(self, xs, ys, values, floor: float) -> float:
        """Trimmed least squares on at most :data:`FIT_CELLS` points; their spread (std).

        Starts from the median level; a constant ``values`` gives exactly that level.
        """
        stride = -(-len(values) // FIT_CELLS)
        xs, ys, values = xs[::stride], ys[::stride], values[::stride]
        level = float(np.median(values))
        self.coef = np.array([level, 0, 0, 0, 0, 0], float)
        scatter = spread(values, floor)
        if np.ptp(values) == 0:  # a flat synthetic table: nothing to fit, and no rounding
            return floor
        a = self._terms(xs, ys)
        for _ in range(FIT_ROUNDS):
            keep = np.abs(values - a @ self.coef) <= TRIM * scatter
            if keep.sum() < 12:
                break
            normal = a[keep].T @ a[keep]
            if np.linalg.cond(normal) > 1e12:  # too few places to fit a surface: a level
                self.coef = np.array([np.median(values[keep]), 0, 0, 0, 0, 0], float)
            else:
                self.coef = np.linalg.solve(normal, a[keep].T @ values[keep])
            scatter = spread((values - a @ self.coef)[keep], floor)
        return scatter

    def at(self, xs, ys) -> np.ndarray:
        """The surface at points (any equal shapes)."""
        return self._terms(xs, ys) @ self.coef


def smooth_leftover(residual: np.ndarray, table: np.ndarray, sigma: float) -> np.ndarray:
    """What the quadratic leaves on the table cells, smoothed, carried under the rest.

    The cells that are not ``table`` (the object and its edge) take the
    value of the nearest table cell, then everything is smoothed by a
    Gaussian of ``sigma`` cells: the table's light under the object, from
    all round it. Exactly zero where the table is flat.
    """
    if not table.any() or not residual[table].any():
        return np.zeros_like(residual)
    filled = residual
    if not table.all():
        # the nearest table cell of each other one, in their bounding box grown by 2 cells
        # (outside it every cell is table)
        rows, cols = np.nonzero(~table)
        box = (
            slice(max(rows.min() - 2, 0), rows.max() + 3),
            slice(max(cols.min() - 2, 0), cols.max() + 3),
        )
        _, (near_rows, near_cols) = ndimage.distance_transform_edt(~table[box], return_indices=True)
        filled = residual.copy()
        filled[box] = residual[box][near_rows, near_cols]
    return ndimage.gaussian_filter(filled, max(sigma, 1.0), mode="nearest")
