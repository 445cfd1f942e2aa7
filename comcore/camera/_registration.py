"""Rigid registration of two masks of one fixed camera: :func:`measure_motion`.

How it works
------------
1. **Moments.** The rotation is about ``before``'s area centroid, so the
   translation is the centroid's displacement whatever the rotation:
   ``after.centroid - before.centroid`` starts every fit.
2. **Coarse scan.** Every rotation on a 2-degree grid is scored by the mean
   squared signed distance (``scipy.ndimage.distance_transform_edt``, clipped)
   of ``after``'s outline, sampled at ``before``'s pixel-edge midpoints moved by
   the candidate motion. Its local minima are the candidates: the principal
   axis and its flip, and every rotation under which a symmetric outline
   matches itself.
3. **Fine fit.** Both masks are smoothed with a Gaussian of
   :data:`SMOOTHING_PX` pixels (rotation-equivariant, so the two outlines stay
   comparable); the motion minimises the squared difference of the smoothed
   images over the outline band of ``before`` (Levenberg-Marquardt,
   ``scipy.optimize.leastsq`` with ``least_squares(method="lm")``'s tolerances,
   the analytic Jacobian, cubic-spline sampling): sub-pixel, sub-degree,
   using the whole outline.
4. **Consistent rotations.** A candidate whose outline residual is within
   :func:`_consistency_tolerance` of the best is consistent with the masks. If
   the consistent rotations are evenly spaced by ``2 pi / n`` the outline has an
   ``n``-fold symmetry; ``theta`` is always the consistent rotation of smallest
   magnitude.
5. **Observability.** ``ambiguous`` is set when the rotation cannot be read
   from the outline: (a) it moves the outline along itself: the Gauss-Newton
   information on theta (translation eliminated) as a lever arm, divided by
   the outline's RMS radius, is below :data:`MIN_ROTATION_VISIBILITY` (about
   0 to 1; a rasterised disc scores 0.07 to 0.14 from its pixel staircase
   alone, radius 40 to 6 px, a 1.1:1 ellipse 0.12, a 1.2:1 ellipse 0.20, a
   regular octagon 0.23: ``bench_measure_motion.py --calibrate``);
   or (b) the predicted
   standard deviation of theta, :data:`OUTLINE_NOISE_PX` (scaled up by
   ``residual_px / REFERENCE_RESIDUAL_PX`` when the fit is worse than an exact
   rigid motion's: mask noise) over the square root of that information
   summed over the outline points, exceeds
   :data:`MAX_THETA_STD` (a small object: too few outline pixels); or (c) the
   consistent rotations are not evenly spaced (two different fits explain
   the masks).
"""

from __future__ import annotations

import copy
import math
from functools import cached_property
from typing import NamedTuple

import numpy as np
from scipy import ndimage, optimize

from .._mask import Mask
from .._status import ImageError
from .._types import Motion
from .._validation import check_finite
from ..conventions import rotate_vectors, rotation_matrix

__all__ = [
    "MotionMeasurement",
    "measure_motion",
]

#: Step (radians) of the coarse scan over theta (2 degrees).
SCAN_STEP = math.radians(2.0)
#: Signed distances (pixels) are clipped at this in the coarse cost.
COARSE_CLIP_PX = 8.0
#: At most this many outline points in the coarse cost.
COARSE_POINTS = 200
#: Coarse candidates whose RMS distance exceeds the best one's by more than this are dropped.
COARSE_MARGIN_PX = 0.6
#: At most this many candidates get a fine fit.
MAX_CANDIDATES = 12
#: Fitted rotations closer than this (radians) are one candidate.
SAME_ROTATION = math.radians(1.0)
#: Consistent rotations form an n-fold symmetry when evenly spaced within this (radians).
SPACING_TOLERANCE = math.radians(3.0)
#: Below this visibility (0..1) the rotation is not observable from the outline.
MIN_ROTATION_VISIBILITY = 0.2
#: Effective independent error (px) of one outline point of a binary mask, such that theta
#: errors on random polygons lie within the predicted std as often as a normal error's do
#: (calibrated by ``benchmarks/accuracy/bench_measure_motion.py --calibrate``).
OUTLINE_NOISE_PX = 0.365
#: The 90th percentile of ``residual_px`` over those exact rigid motions: a fit whose residual
#: is larger (mask noise) has its outline noise, and the predicted theta std, scaled up.
REFERENCE_RESIDUAL_PX = 0.225
#: Above this predicted theta std (radians, 1 degree) the rotation is not observable.
MAX_THETA_STD = math.radians(1.0)
#: Candidates are told apart on every QUICK_STRIDE-th band pixel (bilinear sampling); the
#: chosen one is fitted on all of them (cubic splines).
QUICK_STRIDE = 4
#: Pixels of empty border kept around the two objects when the images are cropped.
CROP_PAD_PX = 10


class MotionMeasurement(NamedTuple):
    """What :func:`measure_motion` measured between two masks."""

    motion: Motion
    """``before`` -> ``after``: theta CCW on screen, (tx, ty) of before's area centroid (px)."""
    residual_px: float
    """RMS distance (pixels) between after's outline and before's outline moved by ``motion``."""
    ambiguous: bool
    """True when the rotation is not observable from the outline: theta then means nothing."""
    symmetry: int
    """Order ``n`` of the rotational symmetry detected (1: none); ``|theta| <= pi / n``."""


def _check_pair(before, after) -> None:
    for name, mask in (("before", before), ("after", after)):
        if not isinstance(mask, Mask):
            raise TypeError(f"{name} must be a comcore.Mask, got {type(mask).__name__}")
    if before.shape != after.shape:
        raise ValueError(
            "after must have the shape of before (the same camera), "
            f"got before {before.shape} and after {after.shape}"
        )
    if not math.isclose(before.resolution, after.resolution, rel_tol=1e-9):
        raise ValueError(
            "after must have the resolution of before (the same camera), got before "
            f"{before.resolution:g} and after {after.resolution:g} m per pixel"
        )
    for name, mask in (("before", before), ("after", after)):
        d = mask.data
        edges = {"top": d[0], "bottom": d[-1], "left": d[:, 0], "right": d[:, -1]}
        sides = [side for side, edge in edges.items() if edge.any()]
        if sides:
            raise ImageError(
                f"{name} touches the image border ({', '.join(sides)}): part of the object may be "
                "out of view, so its outline is cut and its motion cannot be measured; keep the "
                "whole object inside the camera image"
            )


def _consistency_tolerance(best_px: float) -> float:
    """How much worse (RMS px) than the best fit a rotation may fit and still be consistent.

    A quarter pixel plus half the best residual: binary masks place an outline
    to about half a pixel, and a shape that matches itself turned (a
    rectangle by pi) fits within a few hundredths of a pixel as well as the
    true rotation on the benchmark objects, while a shape that does not
    misfits by about a pixel or more.
    """
    return 0.25 + 0.5 * best_px


def _wrap(theta):
    return (np.asarray(theta) + np.pi) % (2 * np.pi) - np.pi


def _coarse_candidates(fields_before: _Fields, fields_after: _Fields, centre, t0) -> list[float]:
    """Local minima of the coarse cost over theta, best first, translation fixed at ``t0``."""
    points = _edge_midpoints(fields_before.data)
    if len(points) > COARSE_POINTS:
        points = points[np.linspace(0, len(points) - 1, COARSE_POINTS).astype(int)]
    rel = points - centre
    thetas = np.arange(-np.pi, np.pi, SCAN_STEP)
    moved = rotate_vectors(rel[None], thetas[:, None]) + (centre + t0)  # (thetas, points, 2)
    dist = np.clip(fields_after.signed_at(moved), -COARSE_CLIP_PX, COARSE_CLIP_PX)
    cost = np.mean(dist**2, axis=1)
    left, right = np.roll(cost, 1), np.roll(cost, -1)
    minima = np.flatnonzero((cost <= left) & (cost < right))
    if minima.size == 0:  # a perfectly flat profile
        minima = np.array([int(np.argmin(np.abs(thetas)))])
    minima = minima[np.argsort(cost[minima], kind="stable")]
    best = math.sqrt(cost[minima[0]])
    out = []
    for i in minima:
        if math.sqrt(cost[i]) > best + COARSE_MARGIN_PX or len(out) == MAX_CANDIDATES:
            break
        curvature = left[i] - 2 * cost[i] + right[i]
        shift = 0.5 * (left[i] - right[i]) / curvature * SCAN_STEP if curvature > 0 else 0.0
        out.append(float(thetas[i] + shift))
    return out


def _symmetry_order(angles: np.ndarray) -> int:
    """``n`` if the angles are ``2 pi k / n`` apart (one of each k), else 0."""
    n = len(angles)
    if n == 1:
        return 1
    rel = np.sort((angles - angles[0]) % (2 * np.pi))
    expected = 2 * np.pi * np.arange(n) / n
    return n if np.all(np.abs(rel - expected) <= SPACING_TOLERANCE) else 0


def measure_motion(before: Mask, after: Mask, *, near_theta: float = 0.0) -> MotionMeasurement:
    """Measure the rigid motion of the object between two masks of one fixed camera.

    Parameters
    ----------
    before, after : Mask
        The object before and after the motion, in the same camera (same
        shape and resolution), each wholly in view.
    near_theta : float, optional
        Where several rotations fit (a symmetric outline), the one nearest to
        this (radians), ``|theta - near_theta| <= pi / symmetry``. Default 0: the
        smallest, right for one push; a caller tracking an object against its
        first mask passes its predicted rotation.

    Returns
    -------
    MotionMeasurement
        ``motion`` maps ``before`` onto ``after``:
        ``comcore.apply_motion(before.pixels, theta, (tx, ty), before.centroid)``
        lands on ``after``'s pixels (theta > 0 counter-clockwise on screen, ``(tx,
        ty)`` the shift in pixels of the material point under ``before``'s area
        centroid). ``residual_px``: the RMS distance between the outlines after
        the fit. ``symmetry``: ``n`` when the outline matches itself turned by
        ``2 pi / n`` (a rectangle 2, a square 4). ``ambiguous``: the rotation
        cannot be seen from the outline (a disc, a small regular polygon) or two
        rotations explain the masks; the translation is still valid, ``theta``
        is not, and ``symmetry`` is 1.

    Raises
    ------
    TypeError
        If ``before`` or ``after`` is not a :class:`comcore.Mask`.
    ValueError
        If the masks differ in shape or resolution, or ``near_theta`` is not finite.
    comcore.ImageError
        A ValueError: a mask touches the image border (its outline would be cut).

    Examples
    --------
    An L-shaped object turned by 0.2 rad (from 0.3 to 0.5 rad) and moved:

    >>> import numpy as np, comcore
    >>> yy, xx = np.mgrid[0:80, 0:80].astype(float)
    >>> def l_shape(theta, shift):
    ...     u, v = comcore.conventions.rotate_components(  # the inverse rotation, pixel frame
    ...         xx - 40 - shift, yy - 40, np.cos(theta), np.sin(theta), inverse=True)
    ...     return ((abs(u) < 20) & (abs(v) < 6)) | ((abs(u + 14) < 6) & (abs(v - 10) < 14))
    >>> before = comcore.Mask(l_shape(0.3, 0.0))
    >>> after = comcore.Mask(l_shape(0.5, 3.0))
    >>> m = comcore.measure_motion(before, after)
    >>> round(m.motion.theta, 2), m.ambiguous, m.symmetry, m.residual_px < 0.5
    (0.2, False, 1, True)

    A disc's rotation cannot be seen:

    >>> disc = comcore.Mask(np.hypot(xx - 40, yy - 40) < 15)
    >>> moved = comcore.Mask(np.hypot(xx - 44, yy - 40) < 15)
    >>> m = comcore.measure_motion(disc, moved)
    >>> m.ambiguous, round(m.motion.tx, 1), round(m.motion.ty, 1)
    (True, 4.0, 0.0)
    """
    return _measure(before, after, near_theta)[0]


def _window(before: Mask, after: Mask):
    """The two masks' fields on the window around both objects, and before's centroid there."""
    h, w = before.shape
    # the two objects' bounding boxes, kept by each Mask: no scan of the camera frame
    box_b, box_a = before._box, after._box
    rows = (min(box_b.lo[0], box_a.lo[0]), max(box_b.hi[0], box_a.hi[0]) - 1)
    cols = (min(box_b.lo[1], box_a.lo[1]), max(box_b.hi[1], box_a.hi[1]) - 1)
    r0, r1 = max(rows[0] - CROP_PAD_PX, 0), min(rows[-1] + CROP_PAD_PX + 1, h)
    c0, c1 = max(cols[0] - CROP_PAD_PX, 0), min(cols[-1] + CROP_PAD_PX + 1, w)
    # everything from here on in the window around the two objects, not the camera frame
    crop_before, crop_after = before.data[r0:r1, c0:c1], after.data[r0:r1, c0:c1]
    fields_before = _Fields(crop_before, full=False)
    fields_after = _Fields(crop_after)
    return fields_before, fields_after, _centroid(crop_before)


def _measured(problem: _Problem, chosen, near: float, order: int, max_theta_std: float, fits):
    """The measurement of the fit ``chosen`` and its diagnostics (the observability tests)."""
    visible = problem.visibility(chosen)
    information = problem.theta_information(chosen)
    residual = problem.outline_rms(chosen)
    noise = OUTLINE_NOISE_PX * max(1.0, residual / REFERENCE_RESIDUAL_PX)
    theta_std = noise / math.sqrt(information) if information > 0 else math.inf
    ambiguous = order == 0 or visible < MIN_ROTATION_VISIBILITY or theta_std > max_theta_std
    symmetry = 1 if ambiguous else order
    motion = Motion(near + float(_wrap(chosen[0] - near)), float(chosen[1]), float(chosen[2]))
    diagnostics = {
        "visibility": visible,
        "theta_information": information,
        "theta_std": theta_std,
        "fits": fits,
        "order": order,
    }
    measurement = MotionMeasurement(motion, residual, bool(ambiguous), int(symmetry))
    return measurement, diagnostics


def _measure(
    before: Mask, after: Mask, near_theta=0.0, max_theta_std: float = MAX_THETA_STD
) -> tuple[MotionMeasurement, dict]:
    """:func:`measure_motion` and its diagnostics (visibility, theta information, fits).

    ``max_theta_std`` (radians): above this predicted std the rotation is called
    ambiguous (:data:`MAX_THETA_STD` for :func:`measure_motion`; a session
    tracking an object reads further, ``comcore._session_pose``).
    """
    _check_pair(before, after)
    near = check_finite(near_theta, "near_theta")
    fields_before, fields_after, centre = _window(before, after)
    t0 = _centroid(fields_after.data) - centre

    problem = _Problem(fields_before, fields_after, centre)
    quick = problem.strided(QUICK_STRIDE, order=1)
    radius = max(float(np.sqrt(np.mean(np.sum(problem.relative**2, axis=1)))), 1.0)
    fits: list[tuple[np.ndarray, float]] = []
    for theta0 in _coarse_candidates(fields_before, fields_after, centre, t0):
        x = quick.fit(np.array([theta0, *t0]), radius)
        x[0] = float(_wrap(x[0]))
        if any(abs(_wrap(x[0] - y[0])) < SAME_ROTATION for y, _ in fits):
            continue
        fits.append((x, problem.outline_rms(x)))
    best_rms = min(r for _, r in fits)
    consistent = [x for x, r in fits if r <= best_rms + _consistency_tolerance(best_rms)]
    angles = np.array([x[0] for x in consistent])
    order = _symmetry_order(angles)
    chosen = problem.fit(consistent[int(np.argmin(np.abs(_wrap(angles - near))))], radius)
    return _measured(problem, chosen, near, order, max_theta_std, fits)


def _measure_near(
    before: Mask, after: Mask, guess: Motion, max_theta_std: float, max_residual_px: float
) -> tuple[MotionMeasurement, dict] | None:
    """The motion fitted from ``guess`` alone, or None where that fit is not to be trusted.

    For a frame taken during a push, whose pose lies near one the caller can
    predict (between the poses before and after the push): no coarse scan over
    theta and no other candidates, the fine fit started from ``guess`` (a quick
    fit first, as :func:`_measure` does for each candidate). The fit is trusted
    when its outline residual is at most ``max_residual_px``; the caller then
    registers the mask with :func:`_measure`. ``symmetry`` is 1 (the fit is the
    branch nearest the guess); ``ambiguous`` as :func:`_measure` says it, but for
    a symmetry it cannot see here. Masks checked by the caller.
    """
    fields_before, fields_after, centre = _window(before, after)
    # the guess is a pose of the full image's frame; the window's centre is before's
    # centroid there too, so the motion's parameters are the same in both
    problem = _Problem(fields_before, fields_after, centre)
    quick = problem.strided(QUICK_STRIDE, order=1)
    radius = max(float(np.sqrt(np.mean(np.sum(problem.relative**2, axis=1)))), 1.0)
    x = quick.fit(np.array([guess.theta, guess.tx, guess.ty], dtype=float), radius)
    chosen = problem.fit(x, radius)
    measured = _measured(problem, chosen, float(guess.theta), 1, max_theta_std, [])
    if not measured[0].residual_px <= max_residual_px:
        return None
    return measured


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
        )[0]

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
