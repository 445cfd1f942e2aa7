"""A goal session's prior: the grid's prior weights and a fixed posterior's particles."""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._types import Estimate
from ..active._grid import prior_grid
from ..active._session import ActiveSession
from ._types import CoMHypotheses, estimate_frictions, hypotheses_from

__all__ = ["prior_particles", "touches_border"]

#: Friction values an estimate all but ruled out keep this share of the largest weight in a
#: learning session's prior, so that its own pushes can still revive them.
MU_FLOOR = 1e-6


def touches_border(mask: Mask) -> bool:
    """Whether the mask touches the image border (the object may be partly out of view)."""
    d = mask.data
    return bool(d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any())


def prior_particles(
    first: Mask, prior, n: int, mus: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, CoMHypotheses | None]:
    """``(pixels, weights, mu_weights, particles)`` of a goal session's ``prior``.

    The grid's prior over the CoM pixels; over the friction values ``mus``
    (None: uniform): an :class:`Estimate`'s (or an :class:`ActiveSession`'s)
    friction posterior where it has the same values, so that a learning
    session does not forget what the estimate learnt of the friction (values
    it all but ruled out keep :data:`MU_FLOOR` of the largest weight, so that
    the session's own pushes can revive them); and ``n`` fixed particles
    (None for no prior).
    """
    if isinstance(prior, ActiveSession):
        prior = prior.estimate()
    if prior is None:
        pixels, weights = prior_grid(first, None)
        return pixels, weights, None, None
    if isinstance(prior, Estimate) and prior.posterior is not None:
        image = np.asarray(prior.posterior.image, float)
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
    return pixels, weights, _frictions(prior, mus), fixed


def _frictions(prior, mus: np.ndarray) -> np.ndarray | None:
    frictions = estimate_frictions(prior) if isinstance(prior, Estimate) else None
    if frictions is None or frictions[0].shape != np.shape(mus):
        return None
    grid, weights = frictions
    if not np.allclose(grid, mus, rtol=1e-9, atol=0.0):
        return None
    weights = np.maximum(weights, MU_FLOOR * weights.max())
    return weights / weights.sum()
