"""The motion model's term of a push's likelihood: predicted against observed motion.

A :class:`comcore.Predictor` predicts each push's motion for CoM and
friction hypotheses (:func:`model_predictions`); the observed motion is scored
against the predictions with heavy-tailed Student-t residuals in the rotation
and in the displacement of each hypothesis' CoM (:func:`motion_log_likelihood`),
with error scales fitted against the simulator (docs/explanation/likelihood.md). The pusher's
offset across its path is marginalised at three Gauss-Hermite nodes
(:func:`offset_marginal`). :mod:`comcore.active._likelihood` combines this term with
the Voting Theorem's.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.special import digamma

from ..conventions import rotate_vectors
from ..motion._predictor import check_model_output

__all__ = [
    "NEAR_LINE_M",
    "STUDENT_DOF",
    "ModelNoise",
    "com_shift",
    "excess_surprise",
    "log_likelihood",
    "model_error_log_density",
    "model_predictions",
    "motion_terms",
    "offset_marginal",
    "pusher_nodes",
    "student_t",
    "theta_scale",
]


#: Degrees of freedom of the Student-t likelihoods (heavy tails; fitted: 2-3).
STUDENT_DOF = 3.0
#: Length (metres) over which the rotation's model error falls off with the
#: lever arm (fitted against the simulator for 3 cm pushes, docs/explanation/likelihood.md).
NEAR_LINE_M = 0.0375

#: Three-point Gauss-Hermite rule for a standard normal: nodes (standard
#: deviations) and weights. The pusher's offset is marginalised over it.
HERMITE_NODES = np.array([0.0, -math.sqrt(3.0), math.sqrt(3.0)])
HERMITE_WEIGHTS = np.array([2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0])


class ModelNoise(NamedTuple):
    """The scales of a motion model's errors in pixels of one mask (internal).

    What :func:`motion_terms` and :func:`comcore.active._choice.model_information`
    read: the session's are ``Scoring.model_noise``.
    """

    theta: tuple[float, float]
    """``(absolute, near)`` radians: the rotation's scale (:func:`theta_scale`)."""
    translation_px: tuple[float, float]
    """``(absolute, relative)``: the CoM displacement's scale, its absolute part in pixels."""
    near_px: float
    """:data:`NEAR_LINE_M` in pixels."""

    def scaled(self, factor: float) -> ModelNoise:
        """Every scale times ``factor`` (the near-line length as it is)."""
        (th_a, th_n), (tr_a, tr_r) = self.theta, self.translation_px
        return self._replace(
            theta=(factor * th_a, factor * th_n), translation_px=(factor * tr_a, factor * tr_r)
        )


def student_t(residual_sq, scale, dof: float, dim: int):
    """Log density (up to a constant) of a ``dim``-variate Student-t, isotropic scale."""
    return -0.5 * (dof + dim) * np.log1p(residual_sq / (dof * scale**2)) - dim * np.log(scale)


def theta_scale(lever, theta_noise, near_line_px: float):
    """Scale (rad) of the model's rotation error for each hypothesis.

    ``absolute + near / (1 + (lever / near_line_px)^2)``: a push whose line
    passes near the CoM balances on an unstable equilibrium, and over a long
    push its rotation is far less predictable than that of a push with a long
    lever arm (measured against the simulator, docs/results/active.md).
    """
    absolute, near = theta_noise
    return absolute + near / (1 + (lever / near_line_px) ** 2)


def com_shift(theta, offset):
    """``(R(theta) - I) offset``: how a turn about the centroid moves a point at ``offset``.

    ``offset`` (..., 2) is the point minus the mask's centroid; broadcast
    against ``theta``.
    """
    return rotate_vectors(offset, theta) - offset


def motion_terms(
    observed,
    predicted,
    lever,
    offset,
    noise: ModelNoise,
    *,
    rotation=True,
    tracking=(0.0, 0.0),
) -> list[tuple]:
    """The residuals an observed motion leaves against predicted ones, and their scales.

    ``[(squared residual, scale, dimension), ...]``, each (p, m): scored by
    :func:`log_likelihood` and :func:`excess_surprise`. Heavy-tailed
    (Student-t, 3 degrees of freedom) in the rotation and in the
    displacement of each hypothesis' CoM. The rotation's scale comes from
    :func:`theta_scale`. The displacement is compared at the CoM, not at the
    mask's centroid where the motion is reported: the centroid's displacement
    also carries the rotation times the centroid's distance to the CoM, whose
    error the rotation term already scores (the CoM form explains the
    simulator's motions better: docs/results/active.md). Its scale is
    ``absolute + relative * |predicted displacement|`` (px).

    Parameters
    ----------
    observed : numpy.ndarray, shape (3,)
    predicted : numpy.ndarray, shape (p, m, 3)
    lever : numpy.ndarray, shape (p, m)
        Distance (px) of each hypothesis' CoM to its force line.
    offset : numpy.ndarray, shape (p, 1, 2)
        Each hypothesis' CoM minus the mask's centroid (px).
    noise : ModelNoise
        The model's error scales (radians, pixels).
    rotation : bool, optional
        False when the observed rotation is unknown (a registration that
        cannot see the object turn): only the centroid's displacement is
        scored, its scale widened by the rotation's error times the
        hypothesis' distance to the centroid.
    tracking : (float, float), optional
        Standard deviations of the observed motion's own error: rotation
        (rad) and translation (px). They add to the model's scales in
        quadrature.
    """
    track_theta, track_px = tracking
    th_scale = np.hypot(theta_scale(lever, noise.theta, noise.near_px), track_theta)
    tr_abs, tr_rel = noise.translation_px
    if not rotation:
        pred_t = predicted[..., 1:]
        scale = tr_abs + tr_rel * np.hypot(pred_t[..., 0], pred_t[..., 1])
        scale = np.hypot(scale, track_px) + th_scale * np.hypot(offset[..., 0], offset[..., 1])
        return [(((observed[1:] - pred_t) ** 2).sum(axis=-1), scale, 2)]
    moved_obs = observed[1:] + com_shift(observed[0], offset)
    moved_pred = predicted[..., 1:] + com_shift(predicted[..., 0], offset)
    tr_scale = tr_abs + tr_rel * np.hypot(moved_pred[..., 0], moved_pred[..., 1])
    tr_scale = np.hypot(tr_scale, track_px)
    return [
        ((observed[0] - predicted[..., 0]) ** 2, th_scale, 1),
        (((moved_obs - moved_pred) ** 2).sum(axis=-1), tr_scale, 2),
    ]


def log_likelihood(terms) -> np.ndarray:
    """Log-likelihood (up to a constant) of :func:`motion_terms`' residuals, shape (p, m)."""
    return sum(student_t(res_sq, scale, STUDENT_DOF, dim) for res_sq, scale, dim in terms)


#: ``E[(dof + d) / 2 log(1 + |T|^2 / dof)]`` of a d-variate Student-t ``T`` (d = 1, 2):
#: ``(dof + d) / 2 (digamma((dof + d) / 2) - digamma(dof / 2))``; 0.773 and 1.667 nats.
_EXPECTED_DEFICIT = {
    d: (STUDENT_DOF + d) / 2 * float(digamma((STUDENT_DOF + d) / 2) - digamma(STUDENT_DOF / 2))
    for d in (1, 2)
}


def excess_surprise(terms) -> np.ndarray:
    """How much more an observed motion surprises each hypothesis than its own motions would.

    ``-log p(y | h) + E_{Y ~ h}[log p(Y | h)]`` for the Student-t terms of
    :func:`motion_terms`: 0 on average when the hypothesis made the motion,
    large when no hypothesis explains it (each term's tail falls like
    ``exp(-0.75 x)``, heavy as the likelihood's).
    """
    return sum(
        (STUDENT_DOF + dim) / 2 * np.log1p(res_sq / (STUDENT_DOF * scale**2))
        - _EXPECTED_DEFICIT[dim]
        for res_sq, scale, dim in terms
    )


def model_predictions(models, mask, actions, pixels, mus, alive) -> np.ndarray:
    """Motions of ``actions`` per (pixel, mu, model) where ``alive``, shape (p, m, k, a, 3).

    Hypotheses that are not alive are left NaN (the models are not asked).
    """
    out = np.full((*alive.shape, len(actions), 3), np.nan)
    for model in models:  # optional: a model that batches friction values is told them
        expect = getattr(model, "expect_frictions", None)
        if callable(expect):
            expect(mask, mus)
    for j, mu_j in enumerate(mus):
        for k, model in enumerate(models):
            idx = np.flatnonzero(alive[:, j, k])
            if len(idx) == 0:
                continue
            pred = model.predict_hypotheses(mask, actions, pixels[idx], float(mu_j))
            out[idx, j, k] = check_model_output(model, pred, actions, pixels[idx], mu_j, mask)
    return out


def offset_marginal(scoring, mask, action, pixels, offset, alive):
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
    ``scoring`` is the :class:`comcore.active._likelihood.Scoring` of the session.
    """
    shifts, log_w = pusher_nodes(action, scoring)
    n, p = len(shifts), len(pixels)
    coms = (pixels[None] - shifts[:, None]).reshape(n * p, 2)
    act = np.asarray(action, dtype=float)[None]
    many = np.concatenate([alive] * n)
    pred = model_predictions(scoring.models, mask, act, coms, scoring.mus, many)[..., 0, :]
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


def pusher_nodes(action, scoring):
    """The pusher's offset across its path at Gauss-Hermite nodes: (n, 2) px and log weights.

    The planned push alone (weight 1) without a pusher error; else the three
    nodes ``s = 0, +-sqrt(3) sigma`` (weights 2/3, 1/6, 1/6) across the
    push's direction.
    """
    action = np.asarray(action, dtype=float)
    if scoring.pusher_px <= 0:
        return np.zeros((1, 2)), np.zeros(1)
    direction = action[2:] - action[:2]
    direction = direction / math.hypot(*direction)
    across = np.array([-direction[1], direction[0]])
    shifts = HERMITE_NODES[:, None] * scoring.pusher_px * across
    return shifts, np.log(HERMITE_WEIGHTS)


def model_error_log_density(
    theta_noise, translation_error, theta_error, lever_m, displacement_error_m, displacement_m
):
    """Log-density (up to a constant) of a motion model's errors as the likelihood scores them.

    See :meth:`comcore.Likelihood.model_error_log_density`; all lengths in metres.
    """
    th_scale = theta_scale(np.asarray(lever_m, float), theta_noise, NEAR_LINE_M)
    tr_scale = translation_error[0] + translation_error[1] * np.asarray(displacement_m, float)
    theta_sq = np.asarray(theta_error, float) ** 2
    moved_sq = np.asarray(displacement_error_m, float) ** 2
    theta_term = student_t(theta_sq, th_scale, STUDENT_DOF, 1)
    return theta_term + student_t(moved_sq, tr_scale, STUDENT_DOF, 2)
