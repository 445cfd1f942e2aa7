"""The posterior update of :class:`comcore.ActiveSession`: one push's evidence.

Every push is scored on the object (the first mask's frame): the candidate's
action and force lines there, and the motion turned into the object's frame
(:func:`comcore._conventions.object_motion_from_camera`). The Voting
Theorem's term reads the sense of the rotation; the motion model's term (if
any) the whole motion. When the rotation was not observable (an
``ambiguous`` registration) only the translation is scored.
"""

from __future__ import annotations

import numpy as np

from ._active_setup import ActiveOptions
from ._mask import Mask
from ._motion import model_predictions, motion_log_likelihood
from ._posterior import GridPosterior, line_distances, push_log_likelihood

__all__ = ["PRUNE_LOG", "push_evidence"]

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
) -> np.ndarray:
    """Log-likelihood over the grid, shape (p, m, k), of one push's object-frame motion.

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
    """
    observed = np.asarray(motion, dtype=float)
    distances = line_distances(post.pixels, lines)[:, :, None]  # (p, m, 1)
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
        weight = options.model_weight
        model_term = np.where(
            alive,
            weight * motion_log_likelihood(observed, predicted, *args, rotation=rotation_observed),
            -np.inf,
        )
        if rotation_observed:
            flipped = observed * np.array([-1.0, 1.0, 1.0])
            flipped_term = np.where(
                alive, weight * motion_log_likelihood(flipped, predicted, *args), -np.inf
            )
        else:
            flipped_term = model_term
    theta_tol = options.theta_tol if rotation_observed else np.inf
    return push_log_likelihood(
        distances, observed, options.flip_prob, theta_tol, model_term, flipped_term
    )
