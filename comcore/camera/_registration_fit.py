"""The two pieces of :func:`comcore.measure_motion`'s fit: the masks' fields and the problem.

:class:`_Fields` holds one mask on the cropped window, smoothed (and its gradient, for
the mask sampled into); :class:`_Problem` is the fine least-squares fit of ``before``'s
outline band into ``after``'s smoothed image, with its outline residual, the information
on theta and the rotation's visibility. The procedure and its constants are in
:mod:`comcore.camera._registration`.
"""

from __future__ import annotations

import copy
import math
from functools import cached_property

import numpy as np
from scipy import ndimage, optimize

from ..conventions import rotation_matrix

#: Gaussian sigma (pixels) of the smoothing of both masks for the fine fit.
SMOOTHING_PX = 1.5
#: Fewer sub-pixel outline points than this (a tiny or thin object): the pixel-edge midpoints.
MIN_OUTLINE_POINTS = 8
#: The fine fit's tolerances on the cost, the step and the gradient (least_squares' defaults).
FIT_TOL = 1e-8


class _Fields:
    """One mask on the cropped window, smoothed.

    For the mask sampled into (``full``) also the smoothed image's gradient,
    their cubic-spline coefficients and a signed distance.
    """

    def __init__(self, data: np.ndarray, full: bool = True):
        img = data.astype(float)
        self.data = data
        if not full:
            self.smooth = ndimage.gaussian_filter(img, SMOOTHING_PX, mode="constant")
            return
        # ndimage.gaussian_filter filters axis 0 then axis 1: the smoothed image and its
        # x derivative share the pass along the rows' axis (the same numbers, one pass less)
        down = ndimage.gaussian_filter1d(img, SMOOTHING_PX, axis=0, mode="constant")
        self.smooth = ndimage.gaussian_filter1d(down, SMOOTHING_PX, axis=1, mode="constant")
        grad_x = ndimage.gaussian_filter1d(down, SMOOTHING_PX, axis=1, order=1, mode="constant")
        grad_y = ndimage.gaussian_filter(img, SMOOTHING_PX, order=(1, 0), mode="constant")
        self.images = {1: [self.smooth, grad_x, grad_y]}
        self.images[3] = [ndimage.spline_filter(a, 3, mode="nearest") for a in self.images[1]]

    @cached_property
    def signed(self) -> np.ndarray:
        """Signed distance (px, > 0 outside) on the window, when first asked for.

        A fit started near the motion (a frame of a push) samples it only at outline
        points far from after's outline, if any: its two distance transforms are then
        not paid.
        """
        outside = ndimage.distance_transform_edt(~self.data)
        inside = ndimage.distance_transform_edt(self.data)
        # zero on the pixel edges between object and background, +-0.5 at the pixels beside them
        return np.where(self.data, 0.5 - inside, outside - 0.5)

    def signed_at(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (px, > 0 outside) at points (..., 2), bilinear."""
        return ndimage.map_coordinates(
            self.signed, [points[..., 1], points[..., 0]], order=1, mode="nearest"
        )

    def _sample(self, which: slice, points: np.ndarray, order: int) -> list[np.ndarray]:
        coords = [points[:, 1], points[:, 0]]
        return [
            ndimage.map_coordinates(a, coords, order=order, mode="nearest", prefilter=False)
            for a in self.images[order][which]
        ]

    def smooth_at(self, points: np.ndarray, order: int = 3) -> np.ndarray:
        """Smoothed image at points (n, 2): cubic splines (order 3) or bilinear (1)."""
        return self._sample(slice(0, 1), points, order)[0]

    def gradient_at(self, points: np.ndarray, order: int = 3) -> list[np.ndarray]:
        """Gradient (d/dx, d/dy) of the smoothed image at points (n, 2)."""
        return self._sample(slice(1, 3), points, order)

    def smooth_and_gradient_at(self, points: np.ndarray, order: int = 3) -> list[np.ndarray]:
        """Smoothed image and its gradient at points (n, 2)."""
        return self._sample(slice(0, 3), points, order)


def _edge_midpoints(data: np.ndarray) -> np.ndarray:
    """Midpoints ``(x, y)`` of the pixel edges between object and background pixels."""
    rows, cols = np.nonzero(data[:, 1:] != data[:, :-1])
    across = np.column_stack([cols + 0.5, rows])
    rows, cols = np.nonzero(data[1:, :] != data[:-1, :])
    down = np.column_stack([cols, rows + 0.5])
    return np.vstack([across, down]).astype(float)


def _level_points(smooth: np.ndarray) -> np.ndarray:
    """Sub-pixel crossings ``(x, y)`` of a smoothed mask's 0.5 level, along rows and columns."""
    f = smooth - 0.5
    out = []
    for a, b, along_x in ((f[:, :-1], f[:, 1:], True), (f[:-1, :], f[1:, :], False)):
        rows, cols = np.nonzero((a > 0) != (b > 0))
        fa, fb = a[rows, cols], b[rows, cols]
        step = fa / (fa - fb)
        if along_x:
            out.append(np.column_stack([cols + step, rows]))
        else:
            out.append(np.column_stack([cols, rows + step]))
    return np.vstack(out)


def _centroid(data: np.ndarray) -> np.ndarray:
    """Area centroid ``(x, y)`` of a bool image's true pixels (``Mask.centroid`` of a crop)."""
    rows, cols = np.nonzero(data)
    return np.array([cols.mean(), rows.mean()])


class _Problem:
    """The fine least-squares problem: before's band sampled in after's smoothed image."""

    def __init__(
        self,
        fields_before: _Fields,
        fields_after: _Fields,
        centre: np.ndarray,
        stride: int = 1,
        order: int = 3,
    ):
        self.after = fields_after
        self.centre = centre
        self.order = order
        band = (fields_before.smooth > 0.01) & (fields_before.smooth < 0.99)
        rows, cols = np.nonzero(band)
        rows, cols = rows[::stride], cols[::stride]
        self.relative = np.column_stack([cols, rows]).astype(float) - centre
        self.values = fields_before.smooth[rows, cols]
        outline = _level_points(fields_before.smooth)
        # an object thinner than the smoothing has (almost) no 0.5 level: its pixel edges,
        # and distances from the signed distance transform alone
        self.thin = len(outline) < MIN_OUTLINE_POINTS
        self.outline = _edge_midpoints(fields_before.data) if self.thin else outline
        self._last: dict = {}

    def strided(self, stride: int, order: int) -> _Problem:
        """The same problem on every ``stride``-th band pixel, sampled at spline ``order``.

        What ``_Problem(..., stride=stride, order=order)`` builds, without finding the
        band and the outline again.
        """
        out = copy.copy(self)
        out.order = order
        out.relative = np.ascontiguousarray(self.relative[::stride])
        out.values = np.ascontiguousarray(self.values[::stride])
        out._last = {}
        return out

    def _remembered(self, name: str, x, compute) -> np.ndarray:
        """``compute(x)``, or what it gave for the same ``x`` just before (read-only)."""
        key = np.asarray(x, dtype=float).tobytes()
        last = self._last.get(name)
        if last is None or last[0] != key:
            last = (key, compute(x))
            self._last[name] = last
        return last[1]

    def moved(self, points_relative, x) -> np.ndarray:
        return points_relative @ rotation_matrix(x[0]).T + self.centre + x[1:]

    def residuals(self, x) -> np.ndarray:
        return self._remembered("residuals", x, self._residuals)

    def _residuals(self, x) -> np.ndarray:
        return self.after.smooth_at(self.moved(self.relative, x), self.order) - self.values

    def jacobian(self, x) -> np.ndarray:
        return self._remembered("jacobian", x, self._jacobian)

    def _jacobian(self, x) -> np.ndarray:
        gx, gy = self.after.gradient_at(self.moved(self.relative, x), self.order)
        turn = self.relative @ rotation_matrix(x[0] + math.pi / 2).T  # d(moved)/d(theta)
        return np.column_stack([gx * turn[:, 0] + gy * turn[:, 1], gx, gy])

    def fit(self, x0, scale) -> np.ndarray:
        """Levenberg-Marquardt (MINPACK's lmder) from ``x0``, theta scaled by ``scale`` (px).

        ``optimize.leastsq`` with ``optimize.least_squares(method="lm")``'s defaults: the
        same iterations and the same result, with less of least_squares' overhead (its
        Jacobian at the solution); the evaluations at ``x0`` it checks are remembered.
        """
        x_scale = np.array([1.0 / scale, 1.0, 1.0])
        if len(self.values) < len(x_scale):  # least_squares says why lm cannot fit it
            return optimize.least_squares(
                self.residuals, x0, jac=self.jacobian, method="lm", x_scale=x_scale
            ).x
        return optimize.leastsq(
            self.residuals, np.asarray(x0, dtype=float), Dfun=self.jacobian, full_output=True,
            ftol=FIT_TOL, xtol=FIT_TOL, gtol=FIT_TOL, maxfev=100 * len(x_scale), diag=1 / x_scale,
        )[0]  # fmt: skip

    def outline_rms(self, x) -> float:
        """RMS distance (px) of before's moved outline to after's outline."""
        q = self.moved(self.outline - self.centre, x)
        if self.thin:
            return float(np.sqrt(np.mean(self.after.signed_at(q) ** 2)))
        value, gx, gy = self.after.smooth_and_gradient_at(q)
        dist = (value - 0.5) / np.maximum(np.hypot(gx, gy), 1e-6)  # first order near the outline
        far = np.abs(value - 0.5) > 0.4
        if far.any():  # (the signed distance is computed only where it is needed)
            dist[far] = self.after.signed_at(q[far])
        return float(np.sqrt(np.mean(dist**2)))

    def theta_information(self, x) -> float:
        """Information on theta (px^2 per rad^2) of the outline points, translation eliminated.

        The sum over before's outline points of the squared normal
        displacement per radian, less what a translation explains.
        """
        q = self.moved(self.outline - self.centre, x)
        gx, gy = self.after.gradient_at(q)
        norm = np.maximum(np.hypot(gx, gy), 1e-12)
        normals = np.column_stack([gx, gy]) / norm[:, None]
        turn = (self.outline - self.centre) @ rotation_matrix(x[0] + math.pi / 2).T
        jac = np.column_stack([np.sum(normals * turn, axis=1), normals])
        info = jac.T @ jac
        if np.linalg.cond(info[1:, 1:]) > 1e12:
            return 0.0
        return float(max(info[0, 0] - info[0, 1:] @ np.linalg.solve(info[1:, 1:], info[1:, 0]), 0))

    def visibility(self, x) -> float:
        """How much of the outline's motion under a rotation is across it (0: a disc, 1 at most).

        The Gauss-Newton information on theta once the translation is
        eliminated, as a lever arm (px), divided by the outline's RMS radius.
        """
        jac = self.jacobian(x)
        info = jac.T @ jac
        translation = info[1:, 1:]
        if np.linalg.cond(translation) > 1e12:
            return 0.0
        schur = info[0, 0] - info[0, 1:] @ np.linalg.solve(translation, info[1:, 0])
        lever = math.sqrt(max(schur, 0.0) / (0.5 * np.trace(translation)))
        weights = jac[:, 1] ** 2 + jac[:, 2] ** 2
        radius = math.sqrt(np.sum(weights * np.sum(self.relative**2, axis=1)) / np.sum(weights))
        return lever / radius if radius > 0 else 0.0
