"""A goal session's prior: the grid's prior weights and a fixed posterior's particles."""

from __future__ import annotations

import numpy as np

from ._goal_types import CoMHypotheses, hypotheses_from
from ._grid import prior_grid
from ._mask import Mask
from ._session import ActiveSession
from ._types import Estimate

__all__ = ["prior_frictions", "prior_particles", "touches_border"]

#: Friction values an estimate all but ruled out keep this share of the largest weight in a
#: learning session's prior, so that its own pushes can still revive them.
MU_FLOOR = 1e-6


def touches_border(mask: Mask) -> bool:
    """Whether the mask touches the image border (the object may be partly out of view)."""
    d = mask.data
    return bool(d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any())


def prior_particles(
    first: Mask, prior, n: int
) -> tuple[np.ndarray, np.ndarray, CoMHypotheses | None]:
    """``(pixels, weights, particles)``: the grid's prior and ``n`` particles (None: uniform)."""
    if isinstance(prior, ActiveSession):
        prior = prior.estimate()
    if prior is None:
        pixels, weights = prior_grid(first, None)
        return pixels, weights, None
    if isinstance(prior, Estimate) and prior.extras.get("posterior") is not None:
        image = np.asarray(prior.extras["posterior"], float)
    else:
        hyps = hypotheses_from(prior, first, n)  # validates; an estimate without an image
        image = np.zeros(first.shape)
        rows = np.clip(np.rint(hyps.coms[:, 1]).astype(int), 0, first.shape[0] - 1)
        cols = np.clip(np.rint(hyps.coms[:, 0]).astype(int), 0, first.shape[1] - 1)
        np.add.at(image, (rows, cols), hyps.weights)
    fixed = hypotheses_from(prior, first, n)
    if image.shape != first.shape:
        raise ValueError(f"prior's posterior has shape {image.shape}, first_mask {first.shape}")
    pixels, weights = prior_grid(first, image)
    return pixels, weights, fixed


def prior_frictions(prior, mus: np.ndarray) -> np.ndarray | None:
    """A learning session's prior over its friction values: the estimate's, or None (uniform).

    An :class:`Estimate` (or an :class:`ActiveSession`'s) carries its friction
    posterior (``extras["mu_posterior"]`` over ``extras["mu_grid"]``); a learning
    goal session starts from it where its likelihood marginalises over the same
    values, so that what the estimate learnt of the friction is not forgotten.
    Any other prior, or other friction values, leave the friction uniform.
    """
    if isinstance(prior, ActiveSession):
        prior = prior.estimate()
    if not isinstance(prior, Estimate):
        return None
    grid, weights = prior.extras.get("mu_grid"), prior.extras.get("mu_posterior")
    if grid is None or weights is None or np.shape(grid) != np.shape(mus):
        return None
    if not np.allclose(grid, mus, rtol=1e-9, atol=0.0):
        return None
    weights = np.asarray(weights, dtype=float)
    if not (np.isfinite(weights).all() and (weights >= 0).all() and weights.sum() > 0):
        return None
    weights = np.maximum(weights / weights.sum(), MU_FLOOR * weights.max() / weights.sum())
    return weights / weights.sum()
