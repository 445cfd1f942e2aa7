"""Support points of a pixel footprint and pressure distributions consistent with a CoM.

A rigid object on a flat floor presses with its centre of pressure at its
CoM, but how the pressure is spread is unknown. The spreads here are small
departures from a uniform footprint that put the centre of pressure at a CoM
hypothesis: the uniform pressure tilted linearly, ``p(x) = a + g . x``, with
the tilt clipped at zero where it would go negative (and ``a, g`` solved
again so that the total and the centre of pressure stay right), or tilted
exponentially, ``p(x) ~ exp(lam . x)``; and, concentrated towards the CoM, a
pressure falling off from it, tilted linearly.
"""

from __future__ import annotations

import math
import weakref

import numpy as np

from .._mask import Mask

__all__ = ["PRESSURES", "Support", "into_hull", "pressures", "support"]

#: Pressure spreads: ``"linear"`` (the clipped linear tilt), ``"tilted"`` (the
#: exponential tilt) and ``"peaked"`` (the linear tilt of a pressure that falls
#: off linearly from the CoM hypothesis).
PRESSURES = ("linear", "tilted", "peaked")
#: Newton steps solving a tilt.
TILT_ITERATIONS = 25


class Support:
    """A mask's pixels gathered into square blocks: the support points of the limit surface.

    Attributes
    ----------
    points : numpy.ndarray, shape (N, 2)
        Centroids of the blocks' object pixels, relative to the mask's area centroid.
    weights : numpy.ndarray, shape (N,)
        Share of the object's pixels in each block (sums to 1).
    cell : float
        Side of a block, pixels.
    """

    def __init__(self, mask: Mask, max_points: int):
        pix = mask.pixels
        block = max(1, math.ceil(math.sqrt(len(pix) / max_points)))
        cols, rows = (pix[:, 0] // block).astype(np.int64), (pix[:, 1] // block).astype(np.int64)
        _, index = np.unique(rows * (cols.max() + 1) + cols, return_inverse=True)
        counts = np.bincount(index).astype(float)
        centroid = np.asarray(mask.centroid)
        self.points = np.column_stack(
            [np.bincount(index, weights=pix[:, i]) / counts - centroid[i] for i in (0, 1)]
        )
        self.weights = counts / counts.sum()
        self.cell = float(block)
        self.hull = _hull_edges(self.points)


def _hull_edges(points: np.ndarray) -> np.ndarray:
    """Edges ``(x0, y0, x1, y1)`` of the convex hull of points, shape (k, 4)."""
    if len(points) < 3 or np.linalg.matrix_rank(points - points.mean(axis=0)) < 2:
        return np.empty((0, 4))
    from scipy.spatial import ConvexHull

    ring = points[ConvexHull(points).vertices]
    return np.column_stack([ring, np.roll(ring, -1, axis=0)])


def into_hull(sup: Support, targets: np.ndarray, margin: float = 1e-3) -> np.ndarray:
    """Targets outside the support points' hull moved to its nearest point (pulled in a hair).

    A centre of pressure can only lie inside that hull; a CoM hypothesis near
    the outline, outside the blocks' centroids, gets the pressure of the
    nearest centre of pressure that exists.
    """
    edges = sup.hull
    if not len(edges):
        return np.zeros_like(targets)  # one block (or a line of them): its centroid
    a, b = edges[:, :2], edges[:, 2:]
    d = b - a
    # Counter-clockwise hull (scipy's order): inside is to the left of every edge.
    rel = targets[:, None, :] - a[None]
    outside = (d[None, :, 0] * rel[..., 1] - d[None, :, 1] * rel[..., 0] < 0).any(axis=1)
    if not outside.any():
        return targets
    t = np.clip((rel * d[None]).sum(-1) / (d * d).sum(-1)[None], 0.0, 1.0)
    foot = a[None] + t[..., None] * d[None]
    nearest = foot[np.arange(len(targets)), np.argmin(((targets[:, None] - foot) ** 2).sum(-1), 1)]
    centre = sup.weights @ sup.points
    moved = centre + (1.0 - margin) * (nearest - centre)
    return np.where(outside[:, None], moved, targets)


_SUPPORTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def support(mask: Mask, max_points: int) -> Support:
    """The (cached) :class:`Support` of an immutable mask."""
    table = _SUPPORTS.setdefault(mask, {})
    if max_points not in table:
        table[max_points] = Support(mask, max_points)
    return table[max_points]


def _clipped_tilt(base: np.ndarray, x: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Pressures ``base * max(0, a + g . x)`` with total 1 and mean ``target``, shape (n, N).

    ``(a, g)`` minimises the convex ``sum base (a + g . x)_+^2 / 2 - a - g . target``,
    whose gradient is the error in the total and the centre of pressure:
    semi-smooth Newton steps (halved when they do not lower it) from the
    unclipped tilt. ``base`` (N,) or (n, N), non-negative; ``x`` (N, 2);
    ``target`` (n, 2). A target outside the support points' hull drives the
    pressure onto the hull's nearest points (the iterations stop there).
    """
    base = np.broadcast_to(base, (len(target), len(x)))
    feats = np.column_stack([np.ones(len(x)), x])  # (N, 3)
    goal = np.column_stack([np.ones(len(target)), target])
    moments = np.einsum("nj,jk,jl->nkl", base, feats, feats) + 1e-12 * np.eye(3)
    theta = np.linalg.solve(moments, goal[..., None])[..., 0]  # the unclipped tilt

    def objective(theta, base, goal):
        lin = np.maximum(theta @ feats.T, 0.0)
        return 0.5 * (lin * lin * base).sum(axis=1) - np.einsum("nk,nk->n", theta, goal)

    todo = np.arange(len(theta))
    for _ in range(TILT_ITERATIONS):  # on the rows not yet solved (most never clip)
        th, bs, gl = theta[todo], base[todo], goal[todo]
        lin = th @ feats.T
        grad = (np.maximum(lin, 0.0) * bs) @ feats - gl
        keep = np.abs(grad).max(axis=1) >= 1e-10
        todo, th, bs, gl = todo[keep], th[keep], bs[keep], gl[keep]
        lin, grad = lin[keep], grad[keep]
        if not len(todo):
            break
        hess = np.einsum("nj,jk,jl->nkl", (lin > 0) * bs, feats, feats) + 1e-12 * np.eye(3)
        step = -np.linalg.solve(hess, grad[..., None])[..., 0]
        f0, alpha = objective(th, bs, gl), np.ones(len(th))
        for _ in range(6):
            worse = objective(th + alpha[:, None] * step, bs, gl) > f0 + 1e-15
            if not worse.any():
                break
            alpha = np.where(worse, 0.5 * alpha, alpha)
        theta[todo] = th + alpha[:, None] * step
    p = np.maximum(theta @ feats.T, 0.0) * base
    total = p.sum(axis=1, keepdims=True)
    return np.where(
        total > 0, p / np.where(total > 0, total, 1.0), base / base.sum(1, keepdims=True)
    )


def _exponential_tilt(base: np.ndarray, x: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Pressures ``base * exp(lam . x)`` with total 1 and mean ``target``, shape (n, N).

    ``lam`` minimises the convex log-partition function minus ``lam . target``
    (Newton steps, capped in length, on the rows not yet solved); the
    distribution closest to ``base`` in relative entropy with that mean.
    """
    scale = max(float(np.ptp(x, axis=0).max()), 1.0)
    xs, ts = x / scale, target / scale
    lam = np.zeros_like(ts)
    todo = np.arange(len(ts))
    for _ in range(TILT_ITERATIONS):
        z = lam[todo] @ xs.T
        q = base * np.exp(z - z.max(axis=1, keepdims=True))
        q /= q.sum(axis=1, keepdims=True)
        mean = q @ xs
        grad = mean - ts[todo]
        keep = np.abs(grad).max(axis=1) * scale >= 1e-9
        todo, q, mean, grad = todo[keep], q[keep], mean[keep], grad[keep]
        if not len(todo):
            break
        cov = np.einsum("nj,jk,jl->nkl", q, xs, xs) - mean[:, :, None] * mean[:, None, :]
        step = -np.linalg.solve(cov + 1e-12 * np.eye(2), grad[..., None])[..., 0]
        norm = np.hypot(step[:, 0], step[:, 1])
        lam[todo] += step * np.minimum(1.0, 8.0 / np.maximum(norm, 1e-300))[:, None]
    z = lam @ xs.T
    q = base * np.exp(z - z.max(axis=1, keepdims=True))
    return q / q.sum(axis=1, keepdims=True)


def pressures(sup: Support, coms_rel: np.ndarray, family: str = "linear") -> np.ndarray:
    """Pressure over the support for each CoM (relative to the centroid), (n, N), rows sum to 1.

    * ``"linear"``: the uniform footprint tilted linearly (clipped at zero) so
      that the centre of pressure is the CoM: the least committal choice.
    * ``"tilted"``: the uniform footprint tilted exponentially: the
      distribution closest to uniform in relative entropy with that centre.
    * ``"peaked"``: a pressure falling off linearly with the distance from the
      CoM hypothesis, to zero just beyond the footprint's farthest point, then
      tilted the same way: mass concentrated towards the CoM.
    """
    x = sup.points
    coms_rel = into_hull(sup, np.asarray(coms_rel, dtype=float).reshape(-1, 2))
    if family == "linear":
        return _clipped_tilt(sup.weights, x, coms_rel)
    if family == "tilted":
        return _exponential_tilt(sup.weights, x, coms_rel)
    d = np.hypot(x[None, :, 0] - coms_rel[:, :1], x[None, :, 1] - coms_rel[:, 1:])
    base = sup.weights * (1.0 - d / (d.max(axis=1, keepdims=True) + sup.cell))
    return _clipped_tilt(base, x, coms_rel)
