"""Motion-model likelihood and information for :func:`comcore.estimate_active`.

A :class:`comcore.HypothesisPredictor` predicts each push's motion for CoM and
friction hypotheses; this module scores observed motions against those
predictions with error scales measured against the simulator, and estimates
how much a candidate push's motion would tell the hypotheses apart.
"""

from __future__ import annotations

import numpy as np
from scipy.special import digamma, logsumexp

from ._conventions import rotate_vectors
from ._posterior import GridPosterior, line_distances

__all__ = [
    "com_shift",
    "model_gains",
    "model_information",
    "model_predictions",
    "motion_excess",
    "motion_log_likelihood",
    "theta_scale",
]

#: Degrees of freedom of the Student-t likelihoods (heavy tails; fitted: 2-3).
STUDENT_DOF = 3.0
#: Hypotheses (pixel, friction) drawn from the posterior to score candidates with the model.
MODEL_PARTICLES = 64


def _student_t(residual_sq, scale, dof: float, dim: int):
    """Log density (up to a constant) of a ``dim``-variate Student-t, isotropic scale."""
    return -0.5 * (dof + dim) * np.log1p(residual_sq / (dof * scale**2)) - dim * np.log(scale)


def theta_scale(lever, theta_noise, near_line_px: float):
    """Scale (rad) of the model's rotation error for each hypothesis.

    ``absolute + near / (1 + (lever / near_line_px)^2)``: a push whose line
    passes near the CoM balances on an unstable equilibrium, and over a long
    push its rotation is far less predictable than that of a push with a long
    lever arm (measured against the simulator, docs/active.md).
    """
    absolute, near = theta_noise
    return absolute + near / (1 + (lever / near_line_px) ** 2)


def com_shift(theta, offset):
    """``(R(theta) - I) offset``: how a turn about the centroid moves a point at ``offset``.

    ``offset`` (..., 2) is the point minus the mask's centroid; broadcast
    against ``theta``.
    """
    return rotate_vectors(offset, theta) - offset


def motion_log_likelihood(
    observed,
    predicted,
    lever,
    offset,
    theta_noise,
    translation_noise,
    near_line_px,
    *,
    rotation=True,
    tracking=(0.0, 0.0),
):
    """Log-likelihood of an observed motion under predicted ones, shape (p, m).

    Heavy-tailed (Student-t, 3 degrees of freedom) in the rotation and in the
    displacement of each hypothesis' CoM. The rotation's scale comes from
    :func:`theta_scale`. The displacement is compared at the CoM, not at the
    mask's centroid where the motion is reported: the centroid's displacement
    also carries the rotation times the centroid's distance to the CoM, whose
    error the rotation term already scores (against the simulator the CoM
    form explains the data better by 0.5 nats a push). Its scale is
    ``absolute + relative * |predicted displacement|`` (px).

    Parameters
    ----------
    observed : numpy.ndarray, shape (3,)
    predicted : numpy.ndarray, shape (p, m, 3)
    lever : numpy.ndarray, shape (p, m)
        Distance (px) of each hypothesis' CoM to its force line.
    offset : numpy.ndarray, shape (p, 1, 2)
        Each hypothesis' CoM minus the mask's centroid (px).
    theta_noise, translation_noise : tuple of float
        ``(absolute, near)`` radians and ``(absolute, relative)`` pixels.
    near_line_px : float
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
    terms = _motion_terms(
        observed,
        predicted,
        lever,
        offset,
        theta_noise,
        translation_noise,
        near_line_px,
        rotation,
        tracking,
    )
    return sum(_student_t(res_sq, scale, STUDENT_DOF, dim) for res_sq, scale, dim in terms)


def _motion_terms(
    observed,
    predicted,
    lever,
    offset,
    theta_noise,
    translation_noise,
    near_line_px,
    rotation,
    tracking,
):
    """The squared residuals, scales and dimensions scored by :func:`motion_log_likelihood`."""
    track_theta, track_px = tracking
    th_scale = np.hypot(theta_scale(lever, theta_noise, near_line_px), track_theta)
    tr_abs, tr_rel = translation_noise
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


#: ``E[(dof + d) / 2 log(1 + |T|^2 / dof)]`` of a d-variate Student-t ``T`` (d = 1, 2):
#: ``(dof + d) / 2 (digamma((dof + d) / 2) - digamma(dof / 2))``; 0.773 and 1.667 nats.
_EXPECTED_DEFICIT = {
    d: (STUDENT_DOF + d) / 2 * float(digamma((STUDENT_DOF + d) / 2) - digamma(STUDENT_DOF / 2))
    for d in (1, 2)
}


def motion_excess(
    observed,
    predicted,
    lever,
    offset,
    theta_noise,
    translation_noise,
    near_line_px,
    *,
    rotation=True,
    tracking=(0.0, 0.0),
):
    """How much more an observed motion surprises each hypothesis than its own motions would.

    ``-log p(y | h) + E_{Y ~ h}[log p(Y | h)]`` for the Student-t terms of
    :func:`motion_log_likelihood` (same arguments): 0 on average when the
    hypothesis made the motion, large when no hypothesis explains it (each
    term's tail falls like ``exp(-0.75 x)``, heavy as the likelihood's).
    """
    terms = _motion_terms(
        observed,
        predicted,
        lever,
        offset,
        theta_noise,
        translation_noise,
        near_line_px,
        rotation,
        tracking,
    )
    return sum(
        (STUDENT_DOF + dim) / 2 * np.log1p(res_sq / (STUDENT_DOF * scale**2))
        - _EXPECTED_DEFICIT[dim]
        for res_sq, scale, dim in terms
    )


def model_information(
    predicted, lever, offset, weights, theta_noise, translation_noise, near_line_px
):
    """Expected information (nats) from each push's motion about weighted hypotheses.

    ``I = sum_i w_i [log p(y_i | i) - log sum_j w_j p(y_i | j)]`` with ``y_i``
    the motion hypothesis ``i`` predicts: how well the observed motion will
    tell the hypotheses apart, with the error model of
    :func:`motion_log_likelihood`.

    Parameters
    ----------
    predicted : numpy.ndarray, shape (n, a, 3)
        Motions of ``a`` candidate pushes under ``n`` hypotheses.
    lever : numpy.ndarray, shape (n, a)
    offset : numpy.ndarray, shape (n, 2)
        Each hypothesis' CoM minus the mask's centroid.
    weights : numpy.ndarray, shape (n,)
        Hypothesis weights, summing to 1.

    Returns
    -------
    numpy.ndarray, shape (a,)
    """
    pred = np.moveaxis(predicted, 1, 0)  # (a, n, 3)
    th_scale = theta_scale(lever.T, theta_noise, near_line_px)  # (a, n)
    # Observation i (axis 1) seen from hypothesis j (axis 2): both moved at j's CoM.
    theta_i, theta_j = pred[:, :, None, 0], pred[:, None, :, 0]
    off_j = offset[None, None, :, :]
    moved_obs = pred[:, :, None, 1:] + com_shift(theta_i, off_j)
    moved_pred = pred[:, None, :, 1:] + com_shift(theta_j, off_j)
    tr_abs, tr_rel = translation_noise
    tr_scale = tr_abs + tr_rel * np.hypot(moved_pred[..., 0], moved_pred[..., 1])
    log_p = _student_t((theta_i - theta_j) ** 2, th_scale[:, None, :], STUDENT_DOF, 1)
    log_p += _student_t(((moved_obs - moved_pred) ** 2).sum(axis=-1), tr_scale, STUDENT_DOF, 2)
    own = np.einsum("aii->ai", log_p)
    log_mix = logsumexp(log_p + np.log(weights)[None, None, :], axis=2)
    return (own - log_mix) @ weights


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
            pred = np.asarray(model.predict_hypotheses(mask, actions, pixels[idx], float(mu_j)))
            shape = (len(idx), len(actions), 3)
            if pred.shape != shape or not np.isfinite(pred).all():
                raise ValueError(
                    f"model.predict_hypotheses must return finite motions of shape {shape}, "
                    f"got shape {pred.shape}"
                )
            out[idx, j, k] = pred
    return out


def particles(post: GridPosterior, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic systematic draw of ``n`` CoM pixels from the posterior.

    Returns the distinct pixel indices drawn and their weights (counts / n).
    """
    cum = np.cumsum(post.marginal)
    picks = np.searchsorted(cum, (np.arange(n) + 0.5) / n * cum[-1])
    index, counts = np.unique(np.minimum(picks, len(cum) - 1), return_counts=True)
    return index, counts / n


def model_gains(models, mask, post, actions, lines, theta_noise, translation_noise, near_px):
    """Expected information (nats) about the CoM from each candidate's motion.

    The CoM hypotheses are 64 particles drawn from the posterior; the friction
    and the model are held at their most probable values, so that what is
    measured is information about the CoM, not about the friction (a push
    that only tells the friction apart is worth nothing here).

    Parameters
    ----------
    actions : numpy.ndarray, shape (a, 4)
    lines : numpy.ndarray, shape (a, m, 3)
        Force lines of the candidates for each friction value of ``post``.
    """
    index, weights = particles(post, MODEL_PARTICLES)
    j = int(np.argmax(post.mu_marginal))
    k = int(np.argmax(post.model_marginal))
    pixels = post.pixels[index]
    alive = np.ones((len(pixels), 1, 1), dtype=bool)
    pred = model_predictions(models[k : k + 1], mask, actions, pixels, post.mus[j : j + 1], alive)
    lever = np.abs(line_distances(pixels, lines[:, j]))
    offset = pixels - np.asarray(mask.centroid)
    return model_information(
        pred[:, 0, 0], lever, offset, weights, theta_noise, translation_noise, near_px
    )
