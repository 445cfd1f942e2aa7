"""Fitting the ellipsoid model's CoM and contact friction to observed pushes."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from comcore import Estimate, Mask
from comcore.checks import readonly
from comcore.geometry import outline_field

from ._model import simulate
from ._support import characteristic_length_sq

__all__ = ["MU_GRID", "EllipsoidFit", "fit_priors"]

#: Contact friction values tried by the coarse fit (both friction classes and beyond).
MU_GRID = (0.1, 0.2, 0.3, 0.45, 0.65, 0.9, 1.2)
#: Most CoM hypotheses of the coarse pass (the mask's pixels on a regular sub-grid).
MAX_COARSE = 300
#: Coarse cells (best first) refined at full pixel resolution.
MAX_REFINED_CELLS = 40
#: Integration steps of the coarse and refined passes (the polish uses the predictor's).
COARSE_STEPS = 8
REFINED_STEPS = 12
#: Local polishing passes: (CoM grid spacing px, half-width of log(mu) range, number of mus).
POLISH_PASSES = ((0.5, 0.7, 7), (0.15, 0.2, 5))
#: The log-likelihood is divided by this for the posterior over the CoM: the
#: model's errors are correlated across pushes, so 12 priors carry less evidence
#: than 12 independent ones. Calibrated against the simulator (see
#: docs/results/motion.md): with it the truth falls within the 1, 2 and 3
#: sigma ellipses about as often as a Gaussian says.
TEMPERATURE = 4.0
#: Degrees of freedom of the Student-t residual model (robust to outliers).
STUDENT_NU = 4.0
#: Smallest residual scales, rotation (radians) and translation (metres): about
#: the model's own error against the simulator when told the true CoM and mu.
MIN_THETA_SCALE = math.radians(3.0)
MIN_TRANSLATION_SCALE_M = 0.00375


@dataclass(frozen=True, eq=False)
class EllipsoidFit:
    """The CoM and contact friction that best explain observed pushes.

    Attributes
    ----------
    com : tuple of float
        Fitted CoM ``(x, y)`` in pixels: the most likely CoM, to sub-pixel precision.
    com_cov : numpy.ndarray, shape (2, 2)
        Posterior covariance of the CoM, pixels squared (read-only).
    mu_contact : float
        Contact friction of the most likely hypothesis.
    log_likelihood : float
        Robust (Student-t) log-likelihood of the priors under the best
        hypothesis, up to a constant.
    residual_scale : tuple of float
        Residual scales ``(theta in radians, translation in pixels)`` used by
        the likelihood: robust estimates from the best fit, floored at
        ``MIN_THETA_SCALE`` and ``MIN_TRANSLATION_SCALE_M``.
    com_mean : tuple of float
        Posterior mean of the CoM over the refined grid (pixels).
    candidates : numpy.ndarray, shape (k, 2)
        CoM hypotheses of the refined grid (pixels, read-only).
    weights : numpy.ndarray, shape (k,)
        Their posterior probabilities (sum to 1, read-only).
    resolution : float
        Metres per pixel of the mask the fit was made on.
    """

    com: tuple[float, float]
    com_cov: np.ndarray
    mu_contact: float
    log_likelihood: float
    residual_scale: tuple[float, float]
    com_mean: tuple[float, float]
    candidates: np.ndarray
    weights: np.ndarray
    resolution: float

    def __post_init__(self):
        for name in ("com_cov", "candidates", "weights"):
            object.__setattr__(self, name, readonly(getattr(self, name), float))

    @property
    def com_m(self) -> tuple[float, float]:
        """The fitted CoM in metres in the mask frame."""
        return (self.com[0] * self.resolution, self.com[1] * self.resolution)

    def to_estimate(self, mask: Mask, level: float = 0.9) -> Estimate:
        """The fit as a :class:`comcore.Estimate`.

        The region is the smallest set of refined candidates holding ``level``
        of the posterior mass (with their pixel neighbours).
        """
        if not 0 < level <= 1:
            raise ValueError(f"level must be in (0, 1], got {level}")
        order = np.argsort(self.weights)[::-1]
        keep = order[: int(np.searchsorted(np.cumsum(self.weights[order]), level)) + 1]
        region = np.zeros(mask.shape, bool)
        pts = np.round(self.candidates[keep]).astype(int)
        inside = (pts[:, 1] >= 0) & (pts[:, 1] < mask.shape[0])
        inside &= (pts[:, 0] >= 0) & (pts[:, 0] < mask.shape[1])
        region[pts[inside, 1], pts[inside, 0]] = True
        return Estimate(
            com=self.com,
            com_m=self.com_m,
            region=region & mask.data,
            covariance=self.com_cov,
            extras={"mu_contact": self.mu_contact, "log_likelihood": self.log_likelihood},
        )


def _nll(pred, observed, scales):
    """Student-t negative log-likelihood summed over priors, shape pred.shape[:-2]."""
    z_theta = (pred[..., 0] - observed[:, 0]) / scales[0]
    z_move = np.hypot(pred[..., 1] - observed[:, 1], pred[..., 2] - observed[:, 2]) / scales[1]
    nu = STUDENT_NU
    out = 0.5 * (nu + 1) * np.log1p(z_theta**2 / nu) + 0.5 * (nu + 2) * np.log1p(z_move**2 / nu)
    return out.sum(axis=-1)


def _coarse_grid(pixels: np.ndarray) -> tuple[np.ndarray, int]:
    stride = max(1, math.ceil(math.sqrt(len(pixels) / MAX_COARSE)))
    while True:
        origin = pixels.min(axis=0) + stride // 2
        on_grid = np.all(np.mod(pixels - origin, stride) == 0, axis=1)
        if stride == 1 or on_grid.sum() >= min(len(pixels), 30):
            return pixels[on_grid], stride
        stride -= 1


def _mu_refinement(grid: np.ndarray, best: int) -> np.ndarray:
    mus = [grid[best]]
    if best > 0:
        mus.insert(0, 0.5 * (grid[best - 1] + grid[best]))
    if best < len(grid) - 1:
        mus.append(0.5 * (grid[best] + grid[best + 1]))
    return np.array(mus)


def _evaluate(mask, field, actions, coms, mus, *, support, radius, n_steps):
    """Predictions for every (com, mu) pair: shape (n_coms, n_mus, n_actions, 3)."""
    c2 = characteristic_length_sq(mask, coms, *support)
    all_coms = np.repeat(coms, len(mus), axis=0)
    all_c2, all_mus = np.repeat(c2, len(mus), axis=0), np.tile(mus, len(coms))
    out = simulate(mask, field, actions, all_coms, all_c2, all_mus, radius=radius, n_steps=n_steps)
    return out.reshape(len(coms), len(mus), len(actions), 3)


def _scales(pred_best, observed, floors):
    res_theta = np.abs(pred_best[:, 0] - observed[:, 0])
    res_move = np.hypot(pred_best[:, 1] - observed[:, 1], pred_best[:, 2] - observed[:, 2])
    theta_scale = max(floors[0], 1.4826 * float(np.median(res_theta)))
    move_scale = max(floors[1], float(np.median(res_move)) / 1.1774)
    return theta_scale, move_scale


def _posterior(log_post, coms):
    log_post = log_post / TEMPERATURE
    w = np.exp(log_post - log_post.max())
    w /= w.sum()
    mean = w @ coms
    rel = coms - mean
    return w, mean, (w[:, None] * rel).T @ rel


def _polish(mask, field, actions, motions, com, mu, *, scales, fixed, **kw):
    """Sub-pixel CoM and finer mu around a grid optimum: two shrinking local grids.

    ``scales`` the residual scales the fit is scored with; ``fixed`` whether the CoM
    and mu are given (then kept); ``kw`` :func:`_evaluate`'s ``support``, ``radius``
    and ``n_steps``.
    """
    fix_com, fix_mu = fixed
    for spacing, spread, n_mu in POLISH_PASSES:
        offsets = spacing * np.arange(-2, 3)
        grid = np.stack(np.meshgrid(offsets, offsets), axis=-1).reshape(-1, 2)
        coms = com[None, :] + (np.zeros((1, 2)) if fix_com else grid)
        mus = np.array([mu]) if fix_mu else mu * np.exp(np.linspace(-spread, spread, n_mu))
        nll = _nll(_evaluate(mask, field, actions, coms, mus, **kw), motions, scales)
        i, j = np.unravel_index(np.argmin(nll), nll.shape)
        com, mu, best = coms[i], float(mus[j]), float(nll[i, j])
    return com, mu, best


def fit_priors(mask, actions, motions, *, com=None, mu=None, support, radius, n_steps):
    """Fit the CoM (over the mask's pixels) and mu to observed motions.

    1. A coarse pass scores a sub-grid of the mask's pixels (at most
       ``MAX_COARSE``) against ``MU_GRID`` (or the given ``mu``) with
       ``COARSE_STEPS`` integration steps.
    2. The ``MAX_REFINED_CELLS`` best coarse cells are scored at every pixel,
       (``REFINED_STEPS``) with ``mu`` refined around its best value; residual scales are then
       estimated from the best fit and the posterior over these pixels gives
       the covariance (the coarse grid's when the belief is wider than them).
    3. Two shrinking local grids polish the best pixel to sub-pixel precision
       and ``mu`` to a few per cent, with the predictor's own ``n_steps``.

    See :class:`EllipsoidFit` for what is returned.
    """
    field = outline_field(mask)
    kw = {"support": support, "radius": radius}
    mus = np.array(MU_GRID if mu is None else (mu,), dtype=float)
    floors = (MIN_THETA_SCALE, MIN_TRANSLATION_SCALE_M / mask.resolution)
    scales = floors
    if com is not None:
        fine_coms, stride, coarse_ok = np.asarray([com], dtype=float), 1, True
    else:
        pixels = mask.pixels
        coms, stride = _coarse_grid(pixels)
        pred = _evaluate(mask, field, actions, coms, mus, n_steps=COARSE_STEPS, **kw)
        nll = _nll(pred, motions, scales)  # (n_coms, n_mus)
        best_com, best_mu = np.unravel_index(np.argmin(nll), nll.shape)
        coarse_log = logsumexp(
            -_nll(pred, motions, _scales(pred[best_com, best_mu], motions, floors)), 1
        )
        cells = np.argsort(-coarse_log)[:MAX_REFINED_CELLS]
        near = np.max(np.abs(pixels[:, None, :] - coms[None, cells, :]), axis=2) <= stride // 2
        fine_coms = pixels[near.any(axis=1)]
        w_coarse, _, cov_coarse = _posterior(coarse_log, coms)
        coarse_ok = w_coarse[cells].sum() >= 0.99
        mus = _mu_refinement(mus, int(best_mu)) if mu is None else mus
    pred = _evaluate(mask, field, actions, fine_coms, mus, n_steps=REFINED_STEPS, **kw)
    nll = _nll(pred, motions, scales)
    best_com, best_mu = np.unravel_index(np.argmin(nll), nll.shape)
    scales = _scales(pred[best_com, best_mu], motions, floors)
    nll = _nll(pred, motions, scales)
    best_com, best_mu = np.unravel_index(np.argmin(nll), nll.shape)
    weights, mean, cov = _posterior(logsumexp(-nll, axis=1), fine_coms)
    if not coarse_ok:  # the belief is wider than the refined cells: use the coarse grid's
        cov = cov_coarse
    cov = cov + np.eye(2) * (stride**2 if not coarse_ok else 1.0) / 12.0
    fixed = (com is not None, mu is not None)
    start = (fine_coms[best_com], float(mus[best_mu]))
    best, mu_best, nll_best = _polish(
        mask, field, actions, motions, *start, scales=scales, fixed=fixed, n_steps=n_steps, **kw
    )
    return EllipsoidFit(
        com=(float(best[0]), float(best[1])),
        com_cov=cov if com is None else np.zeros((2, 2)),
        mu_contact=mu_best,
        log_likelihood=-nll_best,
        residual_scale=(float(scales[0]), float(scales[1])),
        com_mean=(float(mean[0]), float(mean[1])),
        candidates=fine_coms,
        weights=weights,
        resolution=mask.resolution,
    )
