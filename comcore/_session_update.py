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
from typing import NamedTuple

import numpy as np
from scipy.special import ndtr

from ._active_setup import ActiveOptions
from ._mask import Mask
from ._motion import com_shift, model_predictions, motion_excess, motion_log_likelihood
from ._posterior import GridPosterior, line_distances, push_log_likelihood, side_probability

__all__ = [
    "HERMITE_NODES",
    "PRUNE_LOG",
    "Evidence",
    "consistency_threshold",
    "push_evidence",
    "pusher_nodes",
    "tracking_noise",
]

#: Hypotheses this many nats below the best are dropped before the model is asked
#: about them (their posterior is below 1e-11 of the best; saves model calls).
PRUNE_LOG = 25.0
#: Three-point Gauss-Hermite rule for a standard normal: nodes (standard
#: deviations) and weights. The pusher's offset is marginalised over it.
HERMITE_NODES = np.array([0.0, -math.sqrt(3.0), math.sqrt(3.0)])
HERMITE_WEIGHTS = np.array([2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0])


class Evidence(NamedTuple):
    """One push's log-likelihood over the grid: per temper (n_tempers, p, m, k), and untempered."""

    tempered: np.ndarray
    full: np.ndarray


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
) -> tuple[Evidence, np.ndarray]:
    """Log-likelihood over the grid of one push's object-frame motion, as :class:`Evidence`.

    ``Evidence.full`` (p, m, k) is the untempered likelihood; ``Evidence.tempered``
    (n_tempers, p, m, k) holds it with the model's term raised to each power of
    ``options.model_weights`` (one row, untempered, without a model).

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
        alive = post.log_w > post.log_w.max() - PRUNE_LOG  # (p, m, models x scales)
        n_s = options.n_scales
        per_model = alive.reshape(*alive.shape[:2], -1, n_s).any(axis=-1)
        offset = (post.pixels - np.asarray(mask.centroid))[:, None, None, :]
        predicted, spread = _offset_marginal(options, mask, action, post.pixels, offset, per_model)
        # The pusher's offset spreads the prediction: its std adds to the tracking's.
        track = (np.hypot(tracking[0], spread[0]), np.hypot(tracking[1], spread[1]))
        kw = {"rotation": rotation_observed, "tracking": track}
        (th_a, th_n), (tr_a, tr_r) = options.theta_noise, options.translation_noise

        def args(factor):
            noise = ((factor * th_a, factor * th_n), (factor * tr_a, factor * tr_r))
            return (np.abs(distances), offset, *noise, options.near_px)

        def scored(motion):
            terms = [
                motion_log_likelihood(motion, predicted, *args(c), **kw)
                for c in options.model_scales
            ]
            full = np.stack(terms, axis=-1).reshape(alive.shape)
            return np.where(alive, full, -np.inf)

        model_term = scored(observed)
        # The consistency check keeps the base scales (a wider factor must not hide a misfit).
        model_excess = motion_excess(observed, predicted, *args(1.0), **kw)
        if rotation_observed:
            flipped = observed * np.array([-1.0, 1.0, 1.0])
            flipped_term = scored(flipped)
            # A flipped sense explains the motion at the price of the flip.
            flip_cost = np.log((1 - flip_prob) / flip_prob)
            model_excess = np.minimum(
                model_excess, motion_excess(flipped, predicted, *args(1.0), **kw) + flip_cost
            )
        else:
            flipped_term = model_term
        model_excess = np.repeat(model_excess, n_s, axis=-1)
        excess = excess + np.where(alive, model_excess, np.inf)

    def loglik(weight):
        if model_term is None:
            return push_log_likelihood(
                distances, observed, flip_prob, theta_tol, None, None, options.line_scale_px
            )
        return push_log_likelihood(
            distances,
            observed,
            flip_prob,
            theta_tol,
            weight * model_term,
            weight * flipped_term,
            options.line_scale_px,
        )

    full = loglik(1.0)
    weights = options.model_weights if model_term is not None else (1.0,)
    tempered = np.stack([full if w == 1.0 else loglik(w) for w in weights])
    return Evidence(tempered, full), excess


def _offset_marginal(options, mask, action, pixels, offset, alive):
    """The model's motion (p, m, k, 3) marginalised over the pusher's offset, and its spread.

    The executed push lies ``s ~ N(0, pusher_error)`` across the planned one.
    To first order a push moved aside by ``s`` is the planned push on an
    object whose CoM is moved by ``-s``, so the model is asked once about the
    CoMs ``pixels - s`` at the three Gauss-Hermite nodes of ``s``
    (:func:`pusher_nodes`; on a lattice model such as
    :class:`comcore.LimitSurfaceModel` the neighbouring CoMs cost little
    more), the displacement it predicts for the moved CoM kept as that of the
    hypothesis' CoM. Returned: the nodes' mean motion and the standard
    deviations ``(rad, px)`` of the rotation and of each component of the
    CoM's displacement over the nodes (zeros without a pusher error).
    """
    shifts, log_w = pusher_nodes(action, options)
    n, p = len(shifts), len(pixels)
    coms = (pixels[None] - shifts[:, None]).reshape(n * p, 2)
    act = np.asarray(action, dtype=float)[None]
    many = np.concatenate([alive] * n)
    pred = model_predictions(options.models, mask, act, coms, options.mus, many)[..., 0, :]
    pred = np.where(many[..., None], pred, 0.0).reshape(n, p, *alive.shape[1:], 3)
    if n == 1:
        return pred[0], (0.0, 0.0)
    asked = (coms.reshape(n, p, 2) - np.asarray(mask.centroid))[:, :, None, None, :]
    moved = pred[..., 1:] + com_shift(pred[..., 0], asked)  # each node's CoM displacement
    w = np.exp(log_w)
    theta = np.tensordot(w, pred[..., 0], axes=1)
    moved_mean = np.tensordot(w, moved, axes=1)
    theta_sd = np.sqrt(np.tensordot(w, (pred[..., 0] - theta) ** 2, axes=1))
    moved_sd = np.sqrt(np.tensordot(w, ((moved - moved_mean) ** 2).sum(axis=-1), axes=1) / 2)
    mean = np.concatenate([theta[..., None], moved_mean - com_shift(theta, offset)], axis=-1)
    return mean, (theta_sd, moved_sd)


def pusher_nodes(action, options: ActiveOptions):
    """The pusher's offset across its path at Gauss-Hermite nodes: (n, 2) px and log weights.

    The planned push alone (weight 1) without a pusher error; else the three
    nodes ``s = 0, +-sqrt(3) sigma`` (weights 2/3, 1/6, 1/6) across the
    push's direction.
    """
    action = np.asarray(action, dtype=float)
    if options.pusher_px <= 0:
        return np.zeros((1, 2)), np.zeros(1)
    direction = action[2:] - action[:2]
    direction = direction / math.hypot(*direction)
    across = np.array([-direction[1], direction[0]])
    shifts = HERMITE_NODES[:, None] * options.pusher_px * across
    return shifts, np.log(HERMITE_WEIGHTS)


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


def gyration_px(mask: Mask) -> float:
    """The first mask's radius of gyration about its centroid (pixels, at least 0.5).

    :func:`tracking_noise` turns a registration's residual into a rotation error with it.
    """
    offsets = mask.pixels - np.asarray(mask.centroid)
    return max(float(np.sqrt((offsets**2).sum(axis=1).mean())), 0.5)


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
