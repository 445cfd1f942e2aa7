"""The posterior update of :class:`comcore.ActiveSession`: one push's evidence.

Every push is scored on the object (the first mask's frame): the candidate's
action and force lines there, and the motion turned into the object's frame
(:func:`comcore._conventions.object_motion_from_camera`). The Voting
Theorem's term reads the sense of the rotation; the motion model's term (if
any) the whole motion. When the rotation was not observable (an
``ambiguous`` registration) only the translation is scored.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ndtr

from ._active_setup import ActiveOptions
from ._mask import Mask
from ._motion import model_predictions, motion_excess, motion_log_likelihood
from ._posterior import GridPosterior, line_distances, push_log_likelihood, side_probability

__all__ = ["PRUNE_LOG", "consistency_threshold", "push_evidence", "tracking_noise"]

#: Hypotheses this many nats below the best are dropped before the model is asked
#: about them (their posterior is below 1e-11 of the best; saves model calls).
PRUNE_LOG = 25.0


def push_evidence(
    post: GridPosterior,
    options: ActiveOptions,
    mask: Mask,
    action,
    lines,
    motion,
    *,
    rotation_observed: bool = True,
    tracking=None,
) -> tuple[np.ndarray, np.ndarray]:
    """Log-likelihood over the grid, shape (p, m, k), of one push's object-frame motion.

    Also returns each hypothesis' excess surprise at the motion (same shape):
    ``-log p(y | h) + E_{Y ~ h} log p(Y | h)`` summed over the sense and the
    model's terms, 0 on average for the hypothesis that made the motion and
    ``inf`` for hypotheses the model was not asked about.

    Parameters
    ----------
    post : GridPosterior
        The posterior before the push (its live hypotheses are the ones the
        model is asked about).
    options : ActiveOptions
    mask : Mask
        The first mask (the object's frame).
    action : numpy.ndarray, shape (4,)
        The push in the object's frame.
    lines : numpy.ndarray, shape (m, 3)
        Its force line for each friction value.
    motion : numpy.ndarray, shape (3,)
        The object's motion, in the object's frame, about the first mask's centroid.
    rotation_observed : bool, optional
        False: the rotation is unknown (neither its sense nor its size is scored).
    tracking : (float, float), optional
        Standard deviations (rad, px) of this motion's measurement error
        (default ``options.tracking``). A rotation within a few of them may
        have the wrong sense: the sense is trusted less, by the probability
        ``Phi(-|theta| / sigma)`` that noise of that size flipped it.
    """
    observed = np.asarray(motion, dtype=float)
    tracking = options.tracking if tracking is None else tuple(tracking)
    flip_prob = options.flip_prob
    if rotation_observed and tracking[0] > 0:
        flip_prob += (1 - 2 * flip_prob) * float(ndtr(-abs(observed[0]) / tracking[0]))
    theta_tol = options.theta_tol if rotation_observed else np.inf
    sense = 0 if abs(observed[0]) <= theta_tol else (1 if observed[0] > 0 else -1)
    distances = line_distances(post.pixels, lines)[:, :, None]  # (p, m, 1)
    excess = _sense_excess(distances, sense, flip_prob, options.line_scale_px)
    model_term = flipped_term = None
    if options.models:
        alive = post.log_w > post.log_w.max() - PRUNE_LOG
        predicted = model_predictions(
            options.models, mask, np.asarray(action, float)[None], post.pixels, options.mus, alive
        )[..., 0, :]
        predicted = np.where(alive[..., None], predicted, 0.0)  # the dead are not asked (NaN)
        offset = (post.pixels - np.asarray(mask.centroid))[:, None, None, :]
        args = (
            np.abs(distances),
            offset,
            options.theta_noise,
            options.translation_noise,
            options.near_px,
        )
        kw = {"rotation": rotation_observed, "tracking": tracking}
        weight = options.model_weight
        model_term = np.where(
            alive, weight * motion_log_likelihood(observed, predicted, *args, **kw), -np.inf
        )
        model_excess = motion_excess(observed, predicted, *args, **kw)
        if rotation_observed:
            flipped = observed * np.array([-1.0, 1.0, 1.0])
            flipped_term = np.where(
                alive, weight * motion_log_likelihood(flipped, predicted, *args, **kw), -np.inf
            )
            # A flipped sense explains the motion at the price of the flip.
            flip_cost = np.log((1 - flip_prob) / flip_prob)
            model_excess = np.minimum(
                model_excess, motion_excess(flipped, predicted, *args, **kw) + flip_cost
            )
        else:
            flipped_term = model_term
        excess = excess + np.where(alive, model_excess, np.inf)
    loglik = push_log_likelihood(
        distances, observed, flip_prob, theta_tol, model_term, flipped_term, options.line_scale_px
    )
    return loglik, excess


def _sense_excess(distances, sense: int, flip_prob: float, scale: float):
    """``-log P(observed sense | h) + E_h[log P(sense | h)]`` per hypothesis (0 without a sense)."""
    if sense == 0:
        return np.zeros_like(distances)
    q = flip_prob + (1 - 2 * flip_prob) * side_probability(sense * distances, scale)
    q = np.clip(q, 1e-300, 1.0)
    rest = np.clip(1 - q, 1e-300, 1.0)
    return -np.log(q) + q * np.log(q) + rest * np.log(rest)


def consistency_threshold(n_pushes: int) -> float:
    """Excess surprise (nats) of the best hypothesis above which the data are inconsistent.

    Each push's excess has mean 0 and variance about 4 nats^2 (rotation and
    displacement Student-t terms; about 0.4 for a sense alone) under the
    hypothesis that made it; ``10 + 6 sqrt(n)`` is above its 99.9 % quantile
    for 1 to 8 pushes (10.9 / 15.4 / 22.0 for 1 / 3 / 8 pushes, simulated),
    before the minimum over hypotheses lowers it further.
    """
    return 10.0 + 6.0 * float(np.sqrt(max(n_pushes, 1)))


def tracking_noise(tracking, residual_px: float, gyration_px: float) -> tuple[float, float]:
    """Measurement error (rad, px) of a motion: ``motion_noise``, and the registration's.

    Where the motion was measured from masks, the outline's RMS residual
    (px) adds in quadrature to the translation's error, and that residual
    over the first mask's radius of gyration to the rotation's (NaN: not
    measured, ``tracking`` as it is).
    """
    theta, px = tracking
    if not math.isfinite(residual_px):
        return theta, px
    return math.hypot(theta, residual_px / gyration_px), math.hypot(px, residual_px)
