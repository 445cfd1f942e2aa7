"""The support of a pushed object: its pressure on the floor and characteristic length.

The ellipsoidal limit surface of :mod:`predictors.ellipsoid._model` needs one
number per CoM hypothesis, the characteristic length ``c``; it depends on how
the object presses on the floor. Here the mask's pixels are gathered into
blocks (:class:`Support`), a pressure consistent with the CoM is spread over
them, and ``c`` is computed for many CoM hypotheses at once.
"""

from __future__ import annotations

import math
import weakref

import numpy as np

from comcore import Mask

__all__ = ["MAX_SUPPORT_POINTS", "Support", "characteristic_length_sq", "support"]

#: Most support points (blocks of pixels) behind the limit surface.
MAX_SUPPORT_POINTS = 400
#: Newton steps, and the cap on one step, of the exponential tilt ("tilted" pressure).
TILT_NEWTON_STEPS = 8
TILT_MAX_STEP = 4.0
#: Largest number of (hypothesis, support point) pairs held in memory at once.
_CHUNK = 2_000_000


class Support:
    """A mask's pixels gathered into square blocks: the support behind the limit surface.

    Attributes
    ----------
    points : numpy.ndarray, shape (k, 2)
        Centroids of the blocks' object pixels.
    counts : numpy.ndarray, shape (k,)
        Object pixels per block.
    spread : numpy.ndarray, shape (k, 3)
        Second moments ``(xx, xy, yy)`` of each block's pixel squares about its centroid.
    """

    def __init__(self, mask: Mask, max_points: int = MAX_SUPPORT_POINTS):
        pix = mask.pixels
        block = max(1, math.ceil(math.sqrt(len(pix) / max_points)))
        cols, rows = (pix[:, 0] // block).astype(np.int64), (pix[:, 1] // block).astype(np.int64)
        _, index = np.unique(rows * (cols.max() + 1) + cols, return_inverse=True)
        counts = np.bincount(index).astype(float)

        def mean(v):
            return np.bincount(index, weights=v) / counts

        x, y = pix[:, 0], pix[:, 1]
        mx, my = mean(x), mean(y)
        self.points = np.column_stack([mx, my])
        self.counts = counts
        # 1/12: the spread of a unit pixel square about its centre.
        self.spread = np.column_stack(
            [mean(x * x) - mx * mx + 1 / 12, mean(x * y) - mx * my, mean(y * y) - my * my + 1 / 12]
        )


_SUPPORTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def support(mask: Mask) -> Support:
    """The (cached) :class:`Support` of an immutable mask."""
    out = _SUPPORTS.get(mask)
    if out is None:
        out = _SUPPORTS[mask] = Support(mask)
    return out


def _tilted_weights(points: np.ndarray, coms: np.ndarray, counts=None) -> np.ndarray:
    """Pressures ``counts * exp(lam . x)`` at points, with weighted mean at each CoM, (n, k).

    ``lam`` solves a convex problem (the log-partition function's gradient is
    the weighted mean) by damped Newton steps from the linear (small-tilt)
    solution, vectorised over CoMs. For a CoM on the outline the tilt
    diverges; the step cap keeps it finite.
    """
    counts = np.ones(len(points)) if counts is None else np.asarray(counts, dtype=float)
    base = counts / counts.sum()
    centre = base @ points
    scale = max(float(np.ptp(points, axis=0).max()), 1.0)
    x = (points - centre) / scale
    feats = np.column_stack([np.ones(len(x)), x, x[:, 0] ** 2, x[:, 0] * x[:, 1], x[:, 1] ** 2])
    feats *= base[:, None]
    target = (coms - centre) / scale
    cov = (x * base[:, None]).T @ x + 1e-12 * np.eye(2)
    lam = np.linalg.solve(cov, target.T).T

    def tilt(lam):
        z = lam[:, :1] * x[:, 0] + lam[:, 1:] * x[:, 1]
        z -= z.max(axis=1, keepdims=True)
        # exp() of very negative numbers gives slow subnormals and adds nothing: clip.
        return np.exp(np.maximum(z, -40.0, out=z), out=z)

    for _ in range(TILT_NEWTON_STEPS):
        sums = tilt(lam) @ feats  # (n, 6): every moment in one product
        mean = sums[:, 1:3] / sums[:, :1]
        hxx = sums[:, 3] / sums[:, 0] - mean[:, 0] ** 2
        hxy = sums[:, 4] / sums[:, 0] - mean[:, 0] * mean[:, 1]
        hyy = sums[:, 5] / sums[:, 0] - mean[:, 1] ** 2
        det = np.maximum(hxx * hyy - hxy**2, 1e-12)
        gx, gy = target[:, 0] - mean[:, 0], target[:, 1] - mean[:, 1]
        step = np.column_stack([(hyy * gx - hxy * gy) / det, (hxx * gy - hxy * gx) / det])
        norm = np.hypot(step[:, 0], step[:, 1])
        lam += step * np.minimum(1.0, TILT_MAX_STEP / np.maximum(norm, 1e-12))[:, None]
    return tilt(lam) * counts


_LENGTHS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def characteristic_length_sq(
    mask: Mask, coms, pressure: str = "uniform", limit_surface: str = "rotation"
) -> np.ndarray:
    """The support's characteristic length ``c`` (squared, pixels^2) for each CoM.

    Values for CoMs on pixel centres are remembered per (immutable) mask and
    model: an active estimator asks about the same pixels push after push and
    for every friction value, and the tilted pressure costs a Newton solve per
    CoM. Other CoMs are computed every time. See :func:`_characteristic_length_sq`.
    """
    coms = np.asarray(coms, dtype=float).reshape(-1, 2)
    shape = mask.shape
    tables = _LENGTHS.setdefault(mask, {})
    table = tables.get((pressure, limit_surface))
    if table is None:
        depth = (3,) if limit_surface == "directional" else ()
        table = tables[(pressure, limit_surface)] = np.full(shape + depth, np.nan)
    ix = np.rint(coms)
    on_grid = (
        (ix == coms).all(axis=1)
        & (ix[:, 0] >= 0)
        & (ix[:, 0] < shape[1])
        & (ix[:, 1] >= 0)
        & (ix[:, 1] < shape[0])
    )
    cols, rows = ix[on_grid].astype(np.intp).T
    out = np.empty((len(coms), *table.shape[2:]))
    out[on_grid] = table[rows, cols]
    todo = ~on_grid
    known = out[on_grid]
    todo[on_grid] = np.isnan(known).any(axis=1) if known.ndim == 2 else np.isnan(known)
    if todo.any():
        out[todo] = _characteristic_length_sq(mask, coms[todo], pressure, limit_surface)
        fresh = todo & on_grid
        if fresh.any():
            fc, fr = ix[fresh].astype(np.intp).T
            table[fr, fc] = out[fresh]
    return out


def _characteristic_length_sq(
    mask: Mask, coms, pressure: str = "uniform", limit_surface: str = "rotation"
) -> np.ndarray:
    """The support's characteristic length ``c`` (squared, pixels^2) for each CoM.

    The ellipsoid ``fx^2 + fy^2 + (m / c)^2 = const`` cannot match the true
    limit surface everywhere; ``limit_surface`` says where it is matched:

    * ``"rotation"``: at pure rotation about the CoM,
      ``c = m_max / f_max = <|r|>`` (the pressure-weighted mean distance to
      the CoM): the classic choice (Lynch et al. 1992). Returns shape (n,).
    * ``"translation"``: its curvature at pure translation, averaged over
      directions: ``c^2 = <|r|^2> / 2``. Returns shape (n,).
    * ``"directional"``: its curvature at pure translation along the motion
      direction ``d``: ``c^2 = <(r . d)^2>``; a small rotation ``omega`` of a
      body sliding at speed ``v`` along ``d`` costs the moment
      ``mu N <(r . d)^2> omega / v``. Returns the second-moment tensor
      ``(<rx^2>, <rx ry>, <ry^2>)``, shape (n, 3), which :func:`simulate`
      contracts with the direction of the push at every step.

    The pressure ``p`` behind the averages ``<.>`` is spread over the mask's
    pixels, gathered into at most ``MAX_SUPPORT_POINTS`` blocks (:class:`Support`):

    * ``"uniform"``: constant (no assumption beyond the footprint).
    * ``"linear"``: the planar ``p = 1 + g . (x - centroid)`` (clipped at 0)
      whose centre of pressure is the CoM, as it must be for a rigid object on
      a flat floor.
    * ``"tilted"``: ``p = exp(lam . x)``, the distribution closest to uniform
      (in relative entropy) whose centre of pressure is the CoM.

    Parameters
    ----------
    mask : Mask
    coms : array_like, shape (n, 2)
    pressure : {"uniform", "linear", "tilted"}
    limit_surface : {"rotation", "translation", "directional"}

    Returns
    -------
    numpy.ndarray, shape (n,) or (n, 3)
    """
    sup = support(mask)
    pts = sup.points
    coms = np.asarray(coms, dtype=float).reshape(-1, 2)
    mean_dist = np.empty(len(coms))
    moments = np.empty((len(coms), 3))
    centroid = np.asarray(mask.centroid)
    if pressure == "linear":
        rel = pts - centroid
        cov = (rel * sup.counts[:, None]).T @ rel / sup.counts.sum() + 1e-9 * np.eye(2)
        slope = np.linalg.solve(cov, (coms - centroid).T).T  # (n, 2)
    step = max(1, _CHUNK // len(pts))
    for lo in range(0, len(coms), step):
        sl = slice(lo, lo + step)
        dx = pts[None, :, 0] - coms[sl, None, 0]
        dy = pts[None, :, 1] - coms[sl, None, 1]
        if pressure == "uniform":
            weight = np.broadcast_to(sup.counts, dx.shape)
        elif pressure == "linear":
            weight = np.maximum(1.0 + slope[sl] @ rel.T, 0.0) * sup.counts
        else:
            weight = _tilted_weights(pts, coms[sl], sup.counts)
        weight = weight / weight.sum(axis=1, keepdims=True)
        mean_dist[sl] = np.einsum("ij,ij->i", weight, np.hypot(dx, dy))
        moments[sl] = np.column_stack(
            [np.einsum("ij,ij->i", weight, a * b) for a, b in ((dx, dx), (dx, dy), (dy, dy))]
        )
        moments[sl] += weight @ sup.spread  # the blocks' own spread
    if limit_surface == "directional":
        return moments
    if limit_surface == "translation":
        return 0.5 * (moments[:, 0] + moments[:, 2])
    # A one-pixel object still has the spread of its pixel square (mean |r| = 0.38 px).
    return np.maximum(mean_dist, 0.38) ** 2
