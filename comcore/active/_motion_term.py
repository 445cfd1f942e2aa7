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
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.special import digamma

from ..conventions import rotate_vectors
from ..motion._predictor import check_model_output

__all__ = [
    "NEAR_LINE_M",
    "STUDENT_DOF",
    "KnownPushes",
    "ModelNoise",
    "com_shift",
    "excess_surprise",
    "friction_predictions",
    "log_likelihood",
    "model_error_log_density",
    "model_predictions",
    "motion_terms",
    "offset_marginal",
    "path_log_likelihood",
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

    Hypotheses that are not alive are left NaN (the models are not asked). A
    model with ``predict_frictions(mask, actions, coms, mus)`` is asked once
    about every friction value (:func:`friction_predictions`); any other once
    per friction value, about the hypotheses alive at it.
    """
    out = np.full((*alive.shape, len(actions), 3), np.nan)
    for model in models:  # optional: a model that batches friction values is told them
        expect = getattr(model, "expect_frictions", None)
        if callable(expect):
            expect(mask, mus)
    for k, model in enumerate(models):
        if callable(getattr(model, "predict_frictions", None)):
            friction_predictions(
                model, mask, actions, pixels, mus, alive[:, :, k], out=out[:, :, k]
            )
    for j, mu_j in enumerate(mus):
        for k, model in enumerate(models):
            idx = np.flatnonzero(alive[:, j, k])
            if len(idx) == 0 or callable(getattr(model, "predict_frictions", None)):
                continue
            pred = model.predict_hypotheses(mask, actions, pixels[idx], float(mu_j))
            out[idx, j, k] = check_model_output(model, pred, actions, pixels[idx], mu_j, mask)
    return out


def friction_predictions(model, mask, actions, pixels, mus, alive, *, out) -> None:
    """One ``model.predict_frictions`` call for every friction value, written into ``out``.

    ``alive`` (p, m) says which (pixel, mu) hypotheses to keep; the model is
    asked about every pixel alive at some friction value and returns
    ``(n_mu, n_coms, n_actions, 3)``. ``out`` (p, m, a, 3) is filled where
    ``alive``.
    """
    idx = np.flatnonzero(alive.any(axis=1))
    if len(idx) == 0:
        return
    mus = np.asarray(mus, dtype=float)
    pred = np.asarray(model.predict_frictions(mask, actions, pixels[idx], mus.copy()))
    shape = (len(mus), len(idx), len(actions), 3)
    if pred.shape != shape or not np.isfinite(pred).all():
        raise ValueError(
            f"model.predict_frictions must return finite motions of shape {shape} "
            f"(friction values, CoMs, actions, 3), got shape {pred.shape}"
        )
    keep = alive[idx][..., None, None]
    out[idx] = np.where(keep, np.moveaxis(pred, 0, 1), np.nan)


#: Most numbers one batched call of :meth:`KnownPushes._fill` may hold (pushes x CoMs x
#: friction values x models x 3): 32 MiB of predictions.
MAX_BATCH_VALUES = 2**22


@dataclass(eq=False)
class KnownPushes:
    """The model's predictions for pushes known up front, asked for all of them at once.

    Internal and mutable: :func:`comcore.estimate_posterior` makes one and passes it to
    every push it scores, its theta-units check included. The first push scored fills
    it: every push's CoMs at the pusher's offset nodes (:func:`pusher_nodes`) for
    the hypotheses then alive (the prior's: every later posterior's are among them),
    asked in one :func:`model_predictions` call over all the pushes. Later pushes,
    and the check's second posterior, read it instead of asking the model again.
    """

    actions: np.ndarray
    """The pushes, shape (n, 4)."""
    pixels: np.ndarray | None = None
    """The hypotheses' CoMs the predictions are for, shape (p, 2) (None until filled)."""
    asked: np.ndarray | None = None
    """Which (pixel, friction, model) hypotheses were asked, shape (p, m, k)."""
    motions: np.ndarray | None = None
    """Each push's predictions at its nodes' CoMs, shape (n, nodes * p, m, k, 3)."""

    def predictions(self, scoring, mask, action, pixels, alive):
        """:func:`offset_marginal`'s model predictions for ``action``, or None if not kept.

        Shape (nodes * p, m, k, 3) as :func:`model_predictions` gives them
        (first axis node-major); None when ``action`` is not one of the
        pushes, the hypotheses are other CoMs, or one alive was not asked.
        """
        if self.motions is None:
            self._fill(scoring, mask, pixels, alive)
        hit = np.flatnonzero(np.all(self.actions == np.asarray(action, dtype=float), axis=1))
        if len(hit) == 0 or not np.array_equal(self.pixels, pixels):
            return None
        if np.any(alive & ~self.asked):
            return None
        return self.motions[hit[0]]

    def _fill(self, scoring, mask, pixels, alive) -> None:
        """Ask each model about the pushes in few calls, for the hypotheses ``alive``.

        The pushes go in chunks whose every push against every CoM asked for the
        chunk holds at most :data:`MAX_BATCH_VALUES` numbers; a model that keeps
        its own memo of each push (``expect_frictions``: comcore's lattice
        models, whose last digits depend on the pushes asked together) one at a time.
        """
        p, n = len(pixels), len(self.actions)
        coms = [_node_coms(pixels, pusher_nodes(a, scoring)[0]) for a in self.actions]
        rows = len(coms[0])  # nodes x p, node-major
        many = np.concatenate([alive] * (rows // p))
        self.motions = np.empty((n, *many.shape, 3))
        for k, model in enumerate(scoring.models):
            chunk = max(1, min(n, math.isqrt(MAX_BATCH_VALUES // (rows * many[0, :, 0].size * 3))))
            if callable(getattr(model, "expect_frictions", None)):
                chunk = 1
            for start in range(0, n, chunk):
                part = range(start, min(n, start + chunk))
                union = np.concatenate([coms[i] for i in part])
                asked = np.concatenate([many[:, :, k : k + 1]] * len(part))
                acts = self.actions[start : part.stop]
                pred = model_predictions((model,), mask, acts, union, scoring.mus, asked)
                for c, i in enumerate(part):  # push i's rows against its own action
                    self.motions[i, :, :, k] = pred[c * rows : (c + 1) * rows, :, 0, c]
        self.pixels, self.asked = np.array(pixels, dtype=float), alive.copy()


def _node_coms(pixels, shifts) -> np.ndarray:
    """The CoMs asked for a push: ``pixels`` moved by minus each node's shift, node-major."""
    n, p = len(shifts), len(pixels)
    return (pixels[None] - shifts[:, None]).reshape(n * p, 2)


def offset_marginal(scoring, mask, action, pixels, offset, alive, *, known=None):
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
    ``scoring`` is the :class:`comcore.active._likelihood.Scoring` of the session;
    ``known`` (:class:`KnownPushes`), where the pushes are known up front, keeps the
    model's predictions for every push (the model is asked only where it cannot).
    """
    shifts, log_w = pusher_nodes(action, scoring)
    n, p = len(shifts), len(pixels)
    coms = _node_coms(pixels, shifts)
    many = np.concatenate([alive] * n)
    pred = None if known is None else known.predictions(scoring, mask, action, pixels, alive)
    if pred is None:
        act = np.asarray(action, dtype=float)[None]
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


def path_log_likelihood(
    path, observed_end, predicted_end, predicted_path, offset, scales, *, wander: float
):
    """Log density of a push's path given its end pose, per hypothesis, shape (p, m, k).

    Parameters
    ----------
    path : PushPath
        The kept poses (object frame), ``J`` of them, each frame's travel after
        contact as a fraction of the push's, in (0, 1), and the frames' tracking
        standard deviations (radians, pixels) (:class:`comcore.active._path.PushPath`).
    observed_end : numpy.ndarray, shape (3,)
    predicted_end : numpy.ndarray, shape (p, m, k, 3)
        The model's end motion per hypothesis (as the end term scores it).
    predicted_path : numpy.ndarray, shape (p, m, k, J, 3)
        The model's motion after each kept frame's travel.
    offset : numpy.ndarray, shape (p, 1, 1, 2)
        Each hypothesis' CoM minus the first mask's centroid (pixels).
    scales : (float or numpy.ndarray, float or numpy.ndarray)
        The model's error scales at the end, rotation (radians) and translation
        (pixels), without tracking, each broadcast to (p, m, k): one per push as
        the session scores it (then the covariance is factored once for every
        hypothesis), or one per hypothesis.
    wander : float
        ``Likelihood.path_wander``.
    """
    theta_scale, translation_scale = scales
    tracking = path.tracking
    obs = np.vstack([np.asarray([p.motion for p in path.points], float), observed_end[None]])
    pred = np.concatenate([predicted_path, predicted_end[..., None, :]], axis=-2)  # (.., K, 3)
    f = np.append(np.asarray(path.fractions, float), 1.0)
    cov = np.outer(f, f) + wander**2 * np.minimum.outer(f, f)
    lam, vecs = np.linalg.eigh(cov)
    lam = np.maximum(lam, 1e-12)
    end_var = 1.0 + wander**2
    off = offset[..., None, :]  # (p, 1, 1, 1, 2)
    theta_res = obs[:, 0] - pred[..., 0]  # (p, m, k, K)
    moved_obs = obs[:, 1:] + com_shift(obs[:, 0], off)
    moved_pred = pred[..., 1:] + com_shift(pred[..., 0], off)
    shift_res = moved_obs - moved_pred  # (p, m, k, K, 2)
    th_a = np.square(np.asarray(theta_scale, float))
    tr_a = np.square(np.asarray(translation_scale, float))
    total = _conditional_t(theta_res[..., None], th_a, tracking[0] ** 2, lam, vecs, end_var)
    total = total + _conditional_t(shift_res, tr_a, tracking[1] ** 2, lam, vecs, end_var)
    return total


def _conditional_t(res, a, b: float, lam, vecs, end_var: float):
    """Student-t log density of the residual paths ``res`` (..., K, c) given their ends.

    Covariance ``a * cov + b * I`` per component (``cov = vecs diag(lam) vecs^T``); the
    conditional of the first ``K - 1`` rows on the last: the joint's quadratic form and
    log-determinant minus the last row's.
    """
    n_comp, n_rows = res.shape[-1], res.shape[-2]
    a = np.asarray(a, float)
    var = a[..., None] * lam + b  # (..., K), or (K,) for one scale per push
    # the residuals projected on the eigenvectors: one matrix product over every hypothesis
    rows = np.moveaxis(res, -1, -2).reshape(-1, n_rows)  # (... c, K)
    if var.ndim == 1:  # one scale per push: whitened by the same matrix for every hypothesis
        proj = (rows @ (vecs / np.sqrt(var))).reshape(*res.shape[:-2], n_comp, n_rows)
        quad = np.einsum("...ck,...ck->...", proj, proj)
    else:
        proj = (rows @ vecs).reshape(*res.shape[:-2], n_comp, n_rows)  # (..., c, K)
        quad = (np.square(proj) / var[..., None, :]).sum(axis=(-2, -1))
    logdet = np.log(var).sum(axis=-1) * n_comp
    end = a * end_var + b
    quad = quad - np.square(res[..., -1, :]).sum(axis=-1) / end
    logdet = logdet - n_comp * np.log(end)
    dims = (res.shape[-2] - 1) * n_comp
    nu = STUDENT_DOF
    return -0.5 * (nu + dims) * np.log1p(np.maximum(quad, 0.0) / nu) - 0.5 * logdet
