"""The likelihood of one push: the Voting Theorem's term, the motion model's term, the noise.

Open this file to change how an observed push is scored. Every push is scored on
the object (the first mask's frame): its action and force lines there
(:mod:`comcore.vt._force_lines`), and its motion in the object's frame.

* **The Voting Theorem's term.** The sense of rotation tells the side of the
  push's force line the CoM lies on: soft (a logistic edge whose standard
  deviation is ``hypot(pusher_error, LINE_BLUR_M)``), and wrong with
  probability ``flip_prob``, or more when the observed rotation is within the
  tracking noise of zero (:func:`sense_flip_prob`).
* **The motion model's term** (:mod:`comcore.active._motion_term`): the motion
  each (CoM, friction, model) hypothesis predicts against the observed one,
  Student-t residuals, the pusher's offset marginalised, the whole term raised
  to each power of ``model_weight``.
* **The noise.** The tracking error of a measured motion (``motion_noise``,
  widened by a registration's residual: :func:`tracking_noise`), and whether
  any hypothesis explains the pushes at all (:func:`consistency_threshold`;
  for the senses alone, :class:`SenseTally`: how many pushes each hypothesis
  leaves unexplained, against what ``flip_prob`` allows).

:class:`Scoring` is a :class:`comcore.Likelihood` in pixels of one mask, with
its motion models: what the functions here read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.special import ndtr

from .._mask import Mask
from ..conventions import rotation_sense
from ..motion._limit_surface import LimitSurfaceModel
from ..motion._predictor import HypothesisPredictor
from ..vt._force_lines import LINE_SCALE_PX, force_line_distances, side_probability
from ..vt._senses import _LOGISTIC_STD, UNEXPLAINED_STDS, SenseTally
from ._grid import GridPosterior
from ._lattice import lattice_stride
from ._motion_term import (
    NEAR_LINE_M,
    com_shift,
    excess_surprise,
    log_likelihood,
    model_predictions,
    motion_terms,
    offset_marginal,
    theta_scale,
)
from ._options import DEFAULT_MODEL, DEFAULT_PUSHER_RADIUS, Likelihood, mu_grid
from ._options import SESSION_SYSTEMATIC_ERROR as FLOOR
from ._path_term import path_log_likelihood

__all__ = [
    "LINE_BLUR_M",
    "NEAR_LINE_M",
    "PRUNE_LOG",
    "UNEXPLAINED_STDS",
    "Evidence",
    "Scoring",
    "SenseTally",
    "check_models",
    "consistency_threshold",
    "gyration_px",
    "push_evidence",
    "push_log_likelihood",
    "sense_flip_prob",
    "tracking_noise",
]

#: Blur (metres, a standard deviation) of the force line with an exact pusher:
#: the pusher's radius, the object turning during a 3 cm push, outlines and
#: normals. Fitted against the simulator as a logistic of scale 1.2 px at
#: 2.5 mm/px (docs/results/active.md); the pusher's own error adds in quadrature.
LINE_BLUR_M = 1.2 * 0.0025 * math.pi / math.sqrt(3.0)
#: Hypotheses this many nats below the best are dropped before the model is asked
#: about them (their posterior is below 1e-11 of the best; saves model calls).
PRUNE_LOG = 25.0


@dataclass(frozen=True)
class Scoring:
    """A :class:`comcore.Likelihood` in pixels of one mask, with its models (internal).

    ``translation_px`` is ``translation_error`` with its absolute part in
    pixels; ``near_px``, ``line_scale_px`` (the force line's logistic scale),
    ``pusher_px`` and the translation part of ``tracking`` are pixels too.
    """

    models: tuple
    mus: np.ndarray
    flip_prob: float
    theta_tol: float
    theta_noise: tuple[float, float]
    translation_px: tuple[float, float]
    near_px: float
    line_scale_px: float
    tracking: tuple[float, float]
    pusher_px: float
    model_weights: tuple
    model_scales: tuple
    pusher_radius: float = 0.0
    systematic_px: float = 0.0
    path_wander: float | None = None
    lattice_stride: int = 1

    @classmethod
    def build(
        cls,
        likelihood: Likelihood,
        mask: Mask,
        models: tuple,
        pusher_radius: float = 0.0,
        systematic_floor: float = FLOOR,
    ) -> Scoring:
        """The scoring of ``likelihood`` on ``mask``'s pixels with ``models``.

        ``pusher_radius`` (metres) places each push's contact where the pusher's
        disc first touches the object (0: a point on the leading line);
        ``systematic_floor`` (metres) is the estimator's ``systematic_error`` where
        ``likelihood.systematic_error`` is None.
        """
        systematic = likelihood.systematic_error
        systematic = systematic_floor if systematic is None else systematic
        t_abs, t_rel = likelihood.translation_error
        track_theta, track_m = likelihood.motion_noise
        line_std_m = math.hypot(likelihood.pusher_error, LINE_BLUR_M)
        return cls(
            models=models,
            mus=mu_grid(likelihood.mu, likelihood.n_mu),
            flip_prob=likelihood.flip_prob,
            theta_tol=likelihood.theta_tol,
            theta_noise=likelihood.theta_noise,
            translation_px=(t_abs / mask.resolution, t_rel),
            near_px=NEAR_LINE_M / mask.resolution,
            line_scale_px=line_std_m / _LOGISTIC_STD / mask.resolution,
            tracking=(track_theta, track_m / mask.resolution),
            pusher_px=likelihood.pusher_error / mask.resolution,
            systematic_px=systematic / mask.resolution,
            model_weights=likelihood.model_weight,
            model_scales=likelihood.model_scales,
            pusher_radius=pusher_radius,
            path_wander=likelihood.path_wander,
            lattice_stride=lattice_stride(likelihood.model_spacing, mask.resolution),
        )

    @property
    def n_tempers(self) -> int:
        """Powers on the model's likelihood weighed per session (1 without a model)."""
        return len(self.model_weights) if self.models else 1

    @property
    def n_scales(self) -> int:
        """Model-error scale factors marginalised (1 without a model)."""
        return len(self.model_scales) if self.models else 1

    def posterior(self, pixels, prior_weights, mu_weights=None) -> GridPosterior:
        """A grid posterior over ``pixels`` (with their prior) for this scoring's hypotheses."""
        n_models = max(len(self.models), 1)
        return GridPosterior(
            pixels, prior_weights, self.mus, n_models, self.n_scales, self.n_tempers, mu_weights
        )


def check_models(model, pusher_radius: float = DEFAULT_PUSHER_RADIUS) -> tuple:
    """``model`` as a tuple of HypothesisPredictors (empty for None).

    :data:`comcore.active._options.DEFAULT_MODEL` becomes
    ``LimitSurfaceModel(pusher_radius=pusher_radius)``.
    """
    if model is DEFAULT_MODEL:
        return (LimitSurfaceModel(pusher_radius=pusher_radius),)
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


class Evidence(NamedTuple):
    """One push's log-likelihood over the grid: per temper (n_tempers, p, m, k), and untempered."""

    tempered: np.ndarray
    full: np.ndarray


def push_evidence(
    post: GridPosterior,
    scoring: Scoring,
    mask: Mask,
    action,
    lines,
    motion,
    *,
    rotation_observed: bool = True,
    tracking=None,
    path=None,
    memo: dict | None = None,
    tempered: bool = True,
) -> tuple[Evidence, np.ndarray]:
    """Log-likelihood over the grid of one push's object-frame motion, as :class:`Evidence`.

    ``Evidence.full`` (p, m, k) is the untempered likelihood; ``Evidence.tempered``
    (n_tempers, p, m, k) holds it with the model's term raised to each power of
    ``scoring.model_weights`` (one row, untempered, without a model).

    Also returns each hypothesis' excess surprise at the motion (same shape):
    ``-log p(y | h) + E_{Y ~ h} log p(Y | h)`` summed over the sense and the
    model's terms, 0 on average for the hypothesis that made the motion and
    ``inf`` for hypotheses the model was not asked about.

    Parameters
    ----------
    post : GridPosterior
        The posterior before the push (its live hypotheses are the ones the
        model is asked about).
    scoring : Scoring
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
        (default ``scoring.tracking``).
    path : PushPath, optional
        The object's poses during the push (:mod:`comcore.active._path`): their
        density given the end pose joins the model's term. Ignored without a
        model or with the rotation unobserved.
    memo : dict, optional
        Keeps the model's predictions for another reading of the same push
        (a symmetric outline's other rotations) against the same posterior:
        pass one empty dict to every call for that push. The predictions
        depend on the push and the posterior's live hypotheses, not on the
        motion read; the end pose's terms of each reading are kept too (a
        reading scored again with its path adds the path's term to them).
    tempered : bool, optional
        False: ``Evidence.tempered`` holds ``full`` alone (one row), for a caller that
        reads ``full`` only (a reading weighed against another).
    """
    observed = np.asarray(motion, dtype=float)
    tracking = scoring.tracking if tracking is None else tuple(tracking)
    flip_prob = sense_flip_prob(scoring.flip_prob, observed[0], tracking[0], rotation_observed)
    theta_tol = scoring.theta_tol if rotation_observed else np.inf
    sense = int(rotation_sense(observed[0], theta_tol))
    distances = force_line_distances(post.pixels, lines)[:, :, None]  # (p, m, 1)
    excess = _sense_excess(distances, sense, flip_prob, scoring.line_scale_px)
    terms = None
    if path is not None and (not rotation_observed or not path.points):
        path = None
    if scoring.models:
        model_path = None if scoring.path_wander is None else path
        terms = _model_terms(
            post, scoring, mask, action, distances, observed, rotation_observed, tracking,
            flip_prob, model_path, memo,
        )  # fmt: skip
        excess = excess + terms[2]

    # the force line's terms are the same at every temper: computed once
    sides = _sense_logs(distances, observed, theta_tol, scoring.line_scale_px)

    def loglik(weight):
        model_term, flipped_term = (None, None) if terms is None else terms[:2]
        if terms is not None:
            model_term, flipped_term = weight * model_term, weight * flipped_term
        return _with_flips(sides, flip_prob, model_term, flipped_term)

    full = loglik(1.0)
    weights = scoring.model_weights if terms is not None and tempered else (1.0,)
    tempered = np.stack([full if w == 1.0 else loglik(w) for w in weights])
    return Evidence(tempered, full), excess


def sense_flip_prob(flip_prob: float, theta: float, track_theta: float, observed: bool) -> float:
    """The probability an observed sense is wrong: ``flip_prob``, or more near zero.

    A rotation within a few tracking standard deviations of zero may have been
    flipped by the noise: the sense is trusted less, by the probability
    ``Phi(-|theta| / sigma)`` that noise of that size flipped it.
    """
    if observed and track_theta > 0:
        flip_prob += (1 - 2 * flip_prob) * float(ndtr(-abs(theta) / track_theta))
    return flip_prob


def _model_terms(
    post, scoring, mask, action, distances, observed, rotation_observed, tracking, flip_prob,
    path=None, memo=None,
):  # fmt: skip
    """The model's log-likelihood of the motion, of its flipped sense, and the excess surprise.

    Each (p, m, k); hypotheses more than :data:`PRUNE_LOG` nats below the best
    are not asked about (their terms are ``-inf``, their excess ``inf``). ``memo``:
    :func:`push_evidence`'s.
    """
    alive = post.log_w > post.log_w.max() - PRUNE_LOG  # (p, m, models x scales)
    weights = np.exp(post.log_w)
    lattice = post.model_lattice(scoring.lattice_stride)
    if lattice is None:
        return _terms_at(
            post.pixels, alive, weights, scoring, mask, action, distances, observed,
            rotation_observed, tracking, flip_prob, path, memo,
        )  # fmt: skip
    # a camera finer than the model's spacing: the terms on the lattice, spread to every pixel
    usable = lattice.gather_any(alive)
    terms = _terms_at(
        post.pixels[lattice.nodes], usable, lattice.gather_sum(weights), scoring, mask, action,
        distances[lattice.nodes], observed, rotation_observed, tracking, flip_prob, path, memo,
    )  # fmt: skip
    model_term, flipped_term, excess = (lattice.spread(t, usable) for t in terms)
    return (
        np.where(alive, model_term, -np.inf),
        np.where(alive, flipped_term, -np.inf),
        np.where(alive, excess, np.inf),
    )


def _terms_at(
    pixels, alive, weights, scoring, mask, action, distances, observed, rotation_observed,
    tracking, flip_prob, path, memo,
):  # fmt: skip
    """:func:`_model_terms` on the hypotheses ``pixels`` (the posterior's, or its lattice's).

    ``alive`` (p, m, k) says which are asked about, ``weights`` (p, m, k) their posterior
    mass (the path's scales are averaged over it).
    """
    n_s = scoring.n_scales
    per_model = alive.reshape(*alive.shape[:2], -1, n_s).any(axis=-1)
    offset = (pixels - np.asarray(mask.centroid))[:, None, None, :]
    memo = {} if memo is None else memo
    kept = memo.get("offset_marginal")
    if kept is None or not np.array_equal(kept[0], per_model):  # another posterior's
        kept = (per_model, offset_marginal(scoring, mask, action, pixels, offset, per_model))
        memo["offset_marginal"] = kept
    predicted, spread = kept[1]  # (and the end's terms per reading: end_terms)
    # The pusher's offset spreads the prediction: its std adds to the tracking's.
    track = (np.hypot(tracking[0], spread[0]), np.hypot(tracking[1], spread[1]))
    kw = {"rotation": rotation_observed, "tracking": track}
    (th_a, th_n), (tr_a, tr_r) = scoring.theta_noise, scoring.translation_px

    def args(factor):
        noise = ((factor * th_a, factor * th_n), (factor * tr_a, factor * tr_r))
        return (np.abs(distances), offset, *noise, scoring.near_px)

    along = None
    if path is not None:
        along = path_predictions(scoring, mask, action, pixels, per_model, path)
        weights = weights.reshape(*alive.shape[:2], -1, n_s).sum(axis=-1)

    def end_terms(motion):
        """The end's log-likelihood per scale and its base residuals, kept in ``memo``."""
        key = ("end_terms", motion.tobytes(), bool(rotation_observed), *map(float, tracking))
        entry = memo.get(key)
        if entry is None or entry[0] is not kept:
            base = motion_terms(motion, predicted, *args(1.0), **kw)
            factors = [base if c == 1.0 else motion_terms(motion, predicted, *args(c), **kw)
                       for c in scoring.model_scales]  # fmt: skip
            entry = memo[key] = (kept, base, [log_likelihood(f) for f in factors])
        return entry[1], entry[2]

    def scored(motion, sign=1.0):
        """The motion's log-likelihood per scale factor, and its base scales' residuals."""
        base, plain = end_terms(motion)
        terms = []
        for c, term in zip(scoring.model_scales, plain):
            if along is not None:
                term = term + path_term(
                    path, along, motion, predicted, offset, np.abs(distances), c, scoring,
                    weights, sign,
                )  # fmt: skip
            terms.append(term)
        full = np.stack(terms, axis=-1).reshape(alive.shape)
        return np.where(alive, full, -np.inf), base

    model_term, base = scored(observed)
    # The consistency check keeps the base scales (a wider factor must not hide a misfit).
    model_excess = excess_surprise(base)
    if rotation_observed:
        flipped_term, flipped_base = scored(observed * np.array([-1.0, 1.0, 1.0]), -1.0)
        # A flipped sense explains the motion at the price of the flip.
        flip_cost = np.log((1 - flip_prob) / flip_prob)
        model_excess = np.minimum(model_excess, excess_surprise(flipped_base) + flip_cost)
    else:
        flipped_term = model_term
    model_excess = np.repeat(model_excess, n_s, axis=-1)
    return model_term, flipped_term, np.where(alive, model_excess, np.inf)


def path_predictions(scoring, mask, action, pixels, alive, path) -> np.ndarray:
    """The model's motion after each of the path's travels, (p, m, k, J, 3) (0 where not asked).

    A model with ``predict_path_hypotheses`` (:class:`comcore.LimitSurfaceModel`) reads
    them off one integration of the push; any other is asked about the push cut short
    at each kept frame's travel (the same straight path, ending there).
    """
    act = np.asarray(action, dtype=float)
    out = np.zeros((*alive.shape, len(path.points), 3))
    direction = (act[2:] - act[:2]) / math.hypot(*(act[2:] - act[:2]))
    travel = np.array([p.travel for p in path.points])
    ends = act[:2] + travel[:, None] * direction
    cut = np.column_stack([np.tile(act[:2], (len(travel), 1)), ends])
    plain = [k for k, m in enumerate(scoring.models) if not hasattr(m, "predict_path_hypotheses")]
    if plain:
        models = tuple(scoring.models[k] for k in plain)
        pred = model_predictions(models, mask, cut, pixels, scoring.mus, alive[:, :, plain])
        out[:, :, plain] = np.nan_to_num(pred)
    for k, model in enumerate(scoring.models):
        if k in plain:
            continue
        for j, mu_j in enumerate(scoring.mus):
            idx = np.flatnonzero(alive[:, j, k])
            if len(idx):
                pred = model.predict_path_hypotheses(
                    mask, act, pixels[idx], float(mu_j), path.fractions
                )
                out[idx, j, k] = pred
    return np.where(alive[..., None, None], out, 0.0)


def path_term(
    path, along, motion, predicted, offset, lever, factor, scoring, weights, sign=1.0
):  # fmt: skip
    """The path's log density given the end pose (:func:`comcore.active._path.path_log_likelihood`).

    Per hypothesis (p, m, k) for the model's scales times ``factor``; ``sign`` -1 scores
    the path with every rotation negated (the flipped sense). The scales are the
    end's, averaged (in variance) over the posterior before the push (``weights``,
    (p, m, k)): one per push, so that the path's density does not favour the
    hypotheses the model claims to predict best, which its normalising
    constant would, many frames over.
    """
    (th_a, th_n), (tr_a, tr_r) = scoring.theta_noise, scoring.translation_px
    th_scale = theta_scale(lever, (factor * th_a, factor * th_n), scoring.near_px)
    moved_pred = predicted[..., 1:] + com_shift(predicted[..., 0], offset)
    tr_scale = factor * (tr_a + tr_r * np.hypot(moved_pred[..., 0], moved_pred[..., 1]))
    total = max(float(weights.sum()), 1e-300)
    th_scale = np.sqrt(
        float((weights * np.broadcast_to(th_scale, weights.shape) ** 2).sum()) / total
    )
    tr_scale = np.sqrt(
        float((weights * np.broadcast_to(tr_scale, weights.shape) ** 2).sum()) / total
    )
    points = path.points
    if sign < 0:
        points = tuple(p._replace(motion=p.motion._replace(theta=-p.motion.theta)) for p in points)
    return path_log_likelihood(
        points, np.asarray(motion, float), predicted, along, offset, th_scale, tr_scale,
        path.tracking, path.fractions, scoring.path_wander,
    )  # fmt: skip


def push_log_likelihood(
    distances, motion, flip_prob: float, theta_tol: float, model_term=None, flipped_term=None,
    scale: float = LINE_SCALE_PX,
):  # fmt: skip
    """Log-likelihood of one observed push over the grid, shape (p, m, 1) or (p, m, k).

    With probability ``1 - flip_prob`` the observed sense is the true one; with
    ``flip_prob`` it is flipped (and then the unflipped rotation is what the
    motion model must explain). The Voting Theorem term is the soft side of
    the force line (:func:`comcore.vt._force_lines.side_probability`); a rotation
    within ``theta_tol`` carries no sense information.

    Parameters
    ----------
    distances : numpy.ndarray, shape (p, m, 1)
        Signed distances of the grid pixels to the push's force lines.
    motion : numpy.ndarray, shape (3,)
    flip_prob, theta_tol : float
    model_term, flipped_term : numpy.ndarray, shape (p, m, k), optional
        The model's log-likelihood of the motion as observed and with its
        rotation negated (both or neither).
    scale : float, optional
        Logistic scale (pixels) of the force line's soft edge.
    """
    sides = _sense_logs(distances, motion, theta_tol, scale)
    return _with_flips(sides, flip_prob, model_term, flipped_term)


def _sense_logs(distances, motion, theta_tol: float, scale: float):
    """:func:`push_log_likelihood`'s log probabilities of the observed sense and of its flip."""
    sense = int(rotation_sense(float(motion[0]), theta_tol))
    floor = 1e-300
    if sense == 0:
        return np.zeros_like(distances), np.zeros_like(distances)
    log_same = np.log(np.maximum(side_probability(sense * distances, scale), floor))
    log_flip = np.log(np.maximum(side_probability(-sense * distances, scale), floor))
    return log_same, log_flip


def _with_flips(sides, flip_prob: float, model_term=None, flipped_term=None):
    """:func:`push_log_likelihood` from the sense's terms ``sides`` (:func:`_sense_logs`)."""
    log_same, log_flip = sides
    if model_term is not None:
        log_same = log_same + model_term
        log_flip = log_flip + flipped_term
    return np.logaddexp(np.log1p(-flip_prob) + log_same, np.log(flip_prob) + log_flip)


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
    over the first mask's radius of gyration to the rotation's (NaN or None:
    not measured, ``tracking`` as it is).
    """
    theta, px = tracking
    if residual_px is None or not math.isfinite(residual_px):
        return theta, px
    return math.hypot(theta, residual_px / gyration_px), math.hypot(px, residual_px)
