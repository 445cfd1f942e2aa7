"""Arguments, grids and the result of :func:`comcore.estimate_active`."""

from __future__ import annotations

import math

import numpy as np

from ._conventions import pixel_centres
from ._mask import Mask
from ._predictor import HypothesisPredictor
from ._types import Estimate
from ._validation import check_mu

__all__ = [
    "MAX_ALPHA",
    "UNKNOWN_MU_RANGE",
    "build_estimate",
    "check_models",
    "mu_grid",
    "pair",
    "prior_grid",
]

#: Friction range searched when ``mu`` is unknown (covers common pusher materials).
UNKNOWN_MU_RANGE = (0.0, 2.0)
#: Largest cone half-angle used for an unbounded friction range (radians).
MAX_ALPHA = math.pi / 2 - 1e-3


def mu_grid(mu, n_mu: int) -> np.ndarray:
    """Friction values at the mid-points of ``n_mu`` equal bins of cone half-angle."""
    lo, hi = UNKNOWN_MU_RANGE if mu is None else check_mu(mu)
    a_lo, a_hi = math.atan(lo), min(math.atan(hi), MAX_ALPHA)
    if a_hi - a_lo < 1e-12:
        return np.array([lo])
    alphas = a_lo + (np.arange(n_mu) + 0.5) * (a_hi - a_lo) / n_mu
    return np.tan(alphas)


def prior_grid(mask: Mask, prior) -> tuple[np.ndarray, np.ndarray]:
    """Pixels with positive prior weight and their normalised weights."""
    if prior is None:
        return mask.pixels, np.full(mask.area_px, 1.0 / mask.area_px)
    try:
        weights = np.asarray(prior, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"prior must be an array_like of numbers of shape {mask.shape}") from e
    if weights.shape != mask.shape:
        raise ValueError(f"prior must have the mask's shape {mask.shape}, got {weights.shape}")
    if not np.isfinite(weights).all() or (weights < 0).any() or weights.sum() <= 0:
        raise ValueError("prior must be finite, non-negative and not all zero")
    support = weights > 0
    w = weights[support]
    return pixel_centres(support), w / w.sum()


def pair(value, name: str) -> tuple[float, float]:
    """Validate an ``(absolute > 0, other >= 0)`` pair of numbers."""
    try:
        a, r = (float(v) for v in value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a pair of numbers (absolute, other)") from e
    if not (a > 0 and math.isfinite(a) and r >= 0 and math.isfinite(r)):
        raise ValueError(f"{name} must be a pair with absolute > 0 and other >= 0, got ({a}, {r})")
    return a, r


def check_models(model) -> tuple:
    """``model`` as a tuple of HypothesisPredictors (empty for None)."""
    if model is None:
        return ()
    models = tuple(model) if isinstance(model, (list, tuple)) else (model,)
    for m in models:
        if not isinstance(m, HypothesisPredictor):
            raise TypeError(
                "model must implement comcore.HypothesisPredictor (a predict_hypotheses(mask, "
                f"actions, coms, mu) method) or be a sequence of them, got {type(m).__name__}"
            )
    if not models:
        raise ValueError("model must not be an empty sequence")
    return models


def build_estimate(mask, post, level, candidates, used, motions, history, status) -> Estimate:
    """The :class:`Estimate` of a posterior: mean, covariance, credible region, extras."""
    region_idx, area = post.credible(level)
    rows, cols = post.pixels[:, 1].astype(int), post.pixels[:, 0].astype(int)
    region = np.zeros(mask.shape, dtype=bool)
    region[rows[region_idx], cols[region_idx]] = True
    image = np.zeros(mask.shape)
    np.add.at(image, (rows, cols), post.marginal)
    com = tuple(float(v) for v in post.mean())
    return Estimate(
        com=com,
        com_m=mask.to_metres(com),
        region=region,
        used=tuple(used),
        status=status,
        covariance=post.covariance(),
        extras={
            "motions": np.array(motions, dtype=float).reshape(-1, 3),
            "actions": candidates[list(used)].reshape(-1, 4),
            "posterior": image,
            "credible_radius_px": math.sqrt(area / math.pi),
            "mu_grid": post.mus.copy(),
            "mu_posterior": post.mu_marginal,
            "model_posterior": post.model_marginal,
            "history": tuple(history),
        },
    )
