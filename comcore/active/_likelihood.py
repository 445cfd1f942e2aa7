"""The likelihood of one push: the Voting Theorem's term, the motion model's term, the noise.

Open this file to change how an observed push is scored: what a user sets
(:class:`Likelihood`, in metres and radians), its form in one mask's pixels
(:class:`Scoring`, derived from it), and the terms. Every push is scored on
the object (the first mask's frame): its action and force lines there
(:mod:`comcore.vt._voting`), and its motion in the object's frame.

* **The Voting Theorem's term.** The sense of rotation tells the side of the
  push's force line the CoM lies on: soft (a logistic edge whose standard
  deviation is ``hypot(pusher_error, LINE_BLUR_M)``), and wrong with
  probability ``flip_prob``, or more when the observed rotation is within the
  tracking noise of zero (:func:`sense_flip_prob`).
* **The motion model's term** (:mod:`comcore.active._motion_term`): the motion
  each (CoM, friction, model) hypothesis predicts against the observed one,
  Student-t residuals, the pusher's offset marginalised, the whole term raised
  to each power of ``model_weight``; with the frames of a push, the density of
  its path given its end pose (:mod:`comcore.active._motion_term`).
* **The noise.** The tracking error of a measured motion (``motion_noise``,
  widened by a registration's residual: :func:`tracking_noise`), and whether
  any hypothesis explains the pushes at all (:func:`consistency_threshold`;
  for the senses alone, :class:`SenseTally`: how many pushes each hypothesis
  leaves unexplained, against what ``flip_prob`` allows).

What scoring a push reads travels as one :class:`PushToScore`; the model's
predictions for a push are kept for its other readings in a :class:`PushMemo`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np
from scipy.special import ndtr

from .._mask import Mask
from .._validation import (
    check_mu,
    check_pair,
    check_physical,
    check_positive,
    check_powers,
    check_probability,
)
from ..conventions import ANGLE_EPS, check_plausible, rotation_sense
from ..motion._limit_surface import LimitSurfaceModel
from ..motion._predictor import check_model_output, check_predictor
from ..vt._voting import (
    _LOGISTIC_STD,
    LINE_SCALE_PX,
    UNEXPLAINED_STDS,
    SenseTally,
    force_line_distances,
    side_probability,
)
from ._grid import GridPosterior, lattice_stride
from ._motion_term import (
    NEAR_LINE_M,
    KnownPushes,
    ModelNoise,
    com_shift,
    excess_surprise,
    log_likelihood,
    model_error_log_density,
    model_predictions,
    motion_terms,
    offset_marginal,
    path_log_likelihood,
    theta_scale,
)
from ._options import DEFAULT_MODEL, DEFAULT_PUSHER_RADIUS, _bounded_count, _set
from ._options import SESSION_SYSTEMATIC_ERROR as FLOOR

__all__ = [
    "LINE_BLUR_M",
    "MAX_N_MU",
    "NEAR_LINE_M",
    "PRUNE_LOG",
    "UNEXPLAINED_STDS",
    "UNKNOWN_MU_RANGE",
    "Evidence",
    "Likelihood",
    "PushMemo",
    "PushToScore",
    "ReadingKey",
    "Scoring",
    "SenseTally",
    "check_models",
    "consistency_threshold",
    "gyration_px",
    "mu_grid",
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
#: Friction range searched when ``mu`` is unknown (covers common pusher materials).
UNKNOWN_MU_RANGE = (0.0, 2.0)
#: ``Likelihood.path_wander``'s default: chosen among 1, 2 and 4 on seed-1 trials of
#: ``comcore bench``'s ``active-robot`` with frames at 10 Hz, on our engine and with noisy
#: masks (docs/explanation/calibration.md).
PATH_WANDER = 4.0
#: ``Likelihood.model_spacing``'s default (metres): the 2.5 mm pixel every accuracy table
#: was measured at, so that those sessions ask the model about every pixel as before, and a
#: finer camera asks it about as many hypotheses (:mod:`comcore.active._grid`).
MODEL_SPACING = 0.0025
#: Largest cone half-angle used for an unbounded friction range (radians).
MAX_ALPHA = math.pi / 2 - 1e-3
#: Most friction values a likelihood marginalises over: the model is integrated once per
#: value, so the cost of a push grows with it (benchmarks/timing/bench_active.py times it).
MAX_N_MU = 32


@dataclass(frozen=True)
class Likelihood:
    """How an observed push is scored: the Voting Theorem's term, the model's, the noise.

    Lengths are in metres and angles in radians, whatever the camera's
    resolution: the same object gives the same posterior at any resolution.
    The defaults were fitted against the simulator or chosen on seed-1
    benchmark trials (docs/explanation/calibration.md); how each term uses them is in
    :mod:`comcore.active._likelihood`. Lengths outside ``comcore.conventions.PLAUSIBLE``
    (``pusher_error`` and the absolute parts of ``translation_error`` and
    ``motion_noise``: at most 5 cm; the rotation of ``motion_noise``: at most
    0.5 rad) are refused with a guess at the unit they were typed in. Each
    field's docstring says what it sets; :class:`Scoring` reads them in pixels.

    Examples
    --------
    >>> import comcore
    >>> comcore.Likelihood(pusher_error=0.002).pusher_error
    0.002
    >>> comcore.Likelihood(flip_prob=0.7)
    Traceback (most recent call last):
    ...
    ValueError: flip_prob must be in (0, 0.5), got 0.7
    """

    mu: Any = None
    """Contact friction: unknown (None, marginalised over ``[0, 2]``), known (a float), or a
    range ``(low, high)`` (marginalised over it)."""
    n_mu: int = 6
    """Number of friction values the unknown friction is marginalised over (at most
    :data:`MAX_N_MU`)."""
    flip_prob: float = 0.05
    """Probability that an observed sense of rotation is wrong, in (0, 0.5)."""
    theta_tol: float = ANGLE_EPS
    """Rotations with ``|theta| <= theta_tol`` (radians) carry no sense."""
    theta_noise: tuple[float, float] = (0.01, 0.13)
    """The model's rotation error scale (radians): everywhere, and extra near the force line
    (``theta_noise[0] + theta_noise[1] / (1 + (lever / 3.75 cm)^2)``)."""
    translation_error: tuple[float, float] = (0.001, 0.056)
    """The model's error on the CoM's displacement: absolute (metres) and relative to the
    displacement."""
    pusher_error: float = 0.001
    """Standard deviation (metres) of the pusher's position across its path: how far the
    executed push line may lie from the one scored."""
    motion_noise: tuple[float, float] = (math.radians(0.5), 0.0005)
    """Standard deviations of a measured motion's error, rotation (radians) and translation
    (metres): a camera tracker's 0.5 deg and 0.5 mm."""
    model_weight: Any = (0.25, 0.4, 0.6, 1.0)
    """Power in (0, 1] on the model's likelihood: a number fixes it, a sequence of powers is
    learned per session (their mixture, each weighted by how well it predicted every push
    before it was seen)."""
    model_scales: tuple[float, ...] = (1.0,)
    """Factors on the model's error scales, one unknown factor per session marginalised like
    the friction (``(1.0,)``: the scales as given)."""
    path_wander: float | None = PATH_WANDER
    """How much of the motion model's error along a push is not shared by the whole push,
    relative to its error at the push's end (>= 0): how much the frames of a push
    (``observe(..., frames=...)``) say to the model beyond its end pose. Small: the model's
    error is a shape it keeps along the push, and the path tells much; large: little. None:
    the model scores the end pose alone, and the frames only by the Voting Theorem, each
    stretch of the path on its own force line (:mod:`comcore.active._path`)."""
    model_spacing: float = MODEL_SPACING
    """Spacing (metres, >= 0) of the lattice of CoM hypotheses the motion model is asked
    about: on a camera finer than it (1 mm per pixel: every second pixel in x and y) the
    model's terms of every other pixel are interpolated from the lattice's nodes around it
    (:mod:`comcore.active._grid`), which keeps the cost of a push that of a 2.5 mm
    camera. A camera of this size per pixel or coarser, or 0: every pixel asked."""
    systematic_error: float | None = None
    """Standard deviation (metres) of an error on the CoM that more pushes do not average
    away (a motion model that errs the same way on every push of an object): the credible
    region, its radius and the stop rule read the posterior blurred by a Gaussian of this
    size. ``None`` (default): the estimator's own, ``SESSION_SYSTEMATIC_ERROR`` (0) for the
    sessions (their pushes stop before it matters) and ``RECORDED_SYSTEMATIC_ERROR`` (1.5 mm)
    for :func:`comcore.estimate_posterior` and ``comcore estimate``, which take every push of
    a recording (chosen on real pushes, docs/explanation/calibration.md)."""

    def model_error_scales(self, lever_m, displacement_m) -> tuple[np.ndarray, np.ndarray]:
        """The scales of the model's errors the likelihood assumes, for given pushes.

        ``theta_noise[0] + theta_noise[1] / (1 + (lever / 3.75 cm)^2)`` radians for
        the rotation (a push whose line passes near the CoM turns the object
        unpredictably) and ``translation_error[0] + translation_error[1] *
        displacement`` metres for the CoM's displacement, ``lever_m`` the CoM's
        distance to the push's force line and ``displacement_m`` the predicted
        displacement (metres, broadcast).
        """
        theta = theta_scale(np.asarray(lever_m, dtype=float), self.theta_noise, NEAR_LINE_M)
        moved = np.asarray(displacement_m, dtype=float)
        return theta, self.translation_error[0] + self.translation_error[1] * moved

    def model_error_log_density(
        self, theta_error, lever_m, displacement_error_m, displacement_m
    ) -> np.ndarray:
        """Log-density (up to a constant) of a motion model's errors as the likelihood scores them.

        Per push: Student-t residuals (3 degrees of freedom) of the rotation
        error ``theta_error`` (radians) and of the CoM displacement's error
        ``displacement_error_m`` (its norm, metres) with the scales of
        :meth:`model_error_scales`: the model's term of a push's likelihood
        without tracking noise or the pusher's offset, for fitting the scales
        to a model's errors against an engine (benchmarks/accuracy/eval_motion_model.py).
        """
        return model_error_log_density(
            self.theta_noise,
            self.translation_error,
            theta_error,
            lever_m,
            displacement_error_m,
            displacement_m,
        )

    @property
    def mus(self) -> np.ndarray:
        """The friction values the likelihood marginalises over (:func:`mu_grid`).

        >>> import comcore
        >>> comcore.Likelihood(n_mu=2, mu=(0.0, 1.0)).mus.round(3).tolist()
        [0.199, 0.668]
        """
        return mu_grid(self.mu, self.n_mu)

    def __post_init__(self):
        if self.mu is not None:
            check_mu(self.mu)
        _set(self, "n_mu", _bounded_count(self.n_mu, "n_mu", MAX_N_MU, "friction values"))
        flip_prob = check_probability(self.flip_prob, "flip_prob", open_low=True)
        if flip_prob >= 0.5:
            raise ValueError(f"flip_prob must be in (0, 0.5), got {flip_prob}")
        _set(self, "flip_prob", flip_prob)
        _set(self, "theta_tol", check_positive(self.theta_tol, "theta_tol", allow_zero=True))
        _set(self, "theta_noise", check_pair(self.theta_noise, "theta_noise"))
        translation_error = check_pair(self.translation_error, "translation_error")
        check_plausible(translation_error[0], "translation_error's absolute part", "length_noise")
        _set(self, "translation_error", translation_error)
        pusher_error = check_physical(
            self.pusher_error, "pusher_error", "length_noise", allow_zero=True
        )
        _set(self, "pusher_error", pusher_error)
        if self.systematic_error is not None:
            systematic = check_physical(
                self.systematic_error, "systematic_error", "length_noise", allow_zero=True
            )
            _set(self, "systematic_error", systematic)
        motion_noise = check_pair(self.motion_noise, "motion_noise", allow_zero=True)
        check_plausible(motion_noise[0], "motion_noise's rotation", "angle_noise")
        check_plausible(motion_noise[1], "motion_noise's translation", "length_noise")
        _set(self, "motion_noise", motion_noise)
        _set(self, "model_weight", check_powers(self.model_weight, "model_weight"))
        _set(self, "model_scales", _factors(self.model_scales))
        if self.path_wander is not None:
            wander = check_positive(self.path_wander, "path_wander", allow_zero=True)
            _set(self, "path_wander", wander)
        spacing = check_physical(
            self.model_spacing, "model_spacing", "length_noise", allow_zero=True
        )
        _set(self, "model_spacing", spacing)


def _factors(value) -> tuple[float, ...]:
    try:
        scales = tuple(float(v) for v in value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"model_scales must be a sequence of numbers, got {value!r}") from e
    if not scales or not all(math.isfinite(v) and v > 0 for v in scales):
        raise ValueError(f"model_scales must be positive finite factors, got {value!r}")
    return scales


def mu_grid(mu, n_mu: int) -> np.ndarray:
    """Friction values at the mid-points of ``n_mu`` equal bins of cone half-angle."""
    lo, hi = UNKNOWN_MU_RANGE if mu is None else check_mu(mu)
    a_lo, a_hi = math.atan(lo), min(math.atan(hi), MAX_ALPHA)
    if a_hi - a_lo < 1e-12:
        return np.array([lo])
    alphas = a_lo + (np.arange(n_mu) + 0.5) * (a_hi - a_lo) / n_mu
    return np.tan(alphas)


@dataclass(frozen=True)
class Scoring:
    """A :class:`Likelihood` in pixels of one mask, with its models (internal).

    It keeps the likelihood, the mask's resolution and the models; every pixel
    quantity is derived from them here and nowhere else: ``translation_px`` is
    ``translation_error`` with its absolute part in pixels; ``near_px``,
    ``line_scale_px`` (the force line's logistic scale), ``pusher_px``,
    ``systematic_px`` and the translation part of ``tracking`` are pixels too.
    """

    likelihood: Likelihood
    """What the user set, in metres and radians."""
    resolution: float
    """Metres per pixel of the mask the pushes are scored on."""
    models: tuple = ()
    """The motion models (:class:`comcore.Predictor`; empty: the Voting Theorem alone)."""
    pusher_radius: float = 0.0
    """Metres: each push's contact is where the pusher's disc first touches the object."""
    systematic_floor: float = FLOOR
    """``systematic_error`` (metres) where ``likelihood.systematic_error`` is None."""

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
        return cls(likelihood, mask.resolution, models, pusher_radius, systematic_floor)

    @cached_property
    def mus(self) -> np.ndarray:
        """The friction values marginalised over (:func:`mu_grid`)."""
        return mu_grid(self.likelihood.mu, self.likelihood.n_mu)

    @property
    def flip_prob(self) -> float:
        """``Likelihood.flip_prob``."""
        return self.likelihood.flip_prob

    @property
    def theta_tol(self) -> float:
        """``Likelihood.theta_tol`` (radians)."""
        return self.likelihood.theta_tol

    @property
    def theta_noise(self) -> tuple[float, float]:
        """``Likelihood.theta_noise`` (radians)."""
        return self.likelihood.theta_noise

    @property
    def translation_px(self) -> tuple[float, float]:
        """``Likelihood.translation_error``: its absolute part in pixels, and its relative part."""
        absolute, relative = self.likelihood.translation_error
        return (absolute / self.resolution, relative)

    @property
    def near_px(self) -> float:
        """:data:`NEAR_LINE_M` in pixels (the rotation error's fall-off with the lever)."""
        return NEAR_LINE_M / self.resolution

    @property
    def line_scale_px(self) -> float:
        """The force line's logistic scale (pixels): the pusher's error and its blur."""
        line_std_m = math.hypot(self.likelihood.pusher_error, LINE_BLUR_M)
        return line_std_m / _LOGISTIC_STD / self.resolution

    @property
    def tracking(self) -> tuple[float, float]:
        """``Likelihood.motion_noise``: rotation (radians) and translation (pixels)."""
        track_theta, track_m = self.likelihood.motion_noise
        return (track_theta, track_m / self.resolution)

    @property
    def pusher_px(self) -> float:
        """``Likelihood.pusher_error`` in pixels."""
        return self.likelihood.pusher_error / self.resolution

    @property
    def systematic_px(self) -> float:
        """``Likelihood.systematic_error`` (or the estimator's floor) in pixels."""
        systematic = self.likelihood.systematic_error
        systematic = self.systematic_floor if systematic is None else systematic
        return systematic / self.resolution

    @property
    def model_weights(self) -> tuple:
        """``Likelihood.model_weight``: the powers on the model's term."""
        return self.likelihood.model_weight

    @property
    def model_scales(self) -> tuple:
        """``Likelihood.model_scales``: the factors on the model's error scales."""
        return self.likelihood.model_scales

    @property
    def path_wander(self) -> float | None:
        """``Likelihood.path_wander``."""
        return self.likelihood.path_wander

    @property
    def lattice_stride(self) -> int:
        """Every how many pixels the model is asked (:mod:`comcore.active._grid`)."""
        return lattice_stride(self.likelihood.model_spacing, self.resolution)

    @property
    def model_noise(self) -> ModelNoise:
        """The model's error scales in pixels, as :func:`motion_terms` reads them."""
        return ModelNoise(self.theta_noise, self.translation_px, self.near_px)

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
        return GridPosterior(
            pixels,
            prior_weights,
            self.mus,
            n_models=max(len(self.models), 1),
            n_scales=self.n_scales,
            n_tempers=self.n_tempers,
            mu_weights=mu_weights,
        )


def check_models(model, pusher_radius: float = DEFAULT_PUSHER_RADIUS) -> tuple:
    """``model`` as a tuple of :class:`comcore.Predictor` models (empty for None).

    :data:`comcore.active._options.DEFAULT_MODEL` becomes
    ``LimitSurfaceModel(pusher_radius=pusher_radius)``.
    """
    if model is DEFAULT_MODEL:
        return (LimitSurfaceModel(pusher_radius=pusher_radius),)
    if model is None:
        return ()
    models = tuple(model) if isinstance(model, (list, tuple)) else (model,)
    for m in models:
        check_predictor(m, "model")
    if not models:
        raise ValueError("model must not be an empty sequence")
    return models


class Evidence(NamedTuple):
    """One push's log-likelihood over the grid: per temper (n_tempers, p, m, k), and untempered."""

    tempered: np.ndarray
    full: np.ndarray


class PushToScore(NamedTuple):
    """What scoring one push's motion needs (internal): the push, its reading, the hypotheses.

    Built by :func:`push_evidence`; the model's terms are computed on the
    hypotheses it names (the posterior's pixels, or a lattice's nodes).
    """

    scoring: Scoring
    """The likelihood in pixels of the first mask, with its models."""
    mask: Mask
    """The first mask (the object's frame)."""
    action: Any
    """The push in the object's frame, shape (4,)."""
    motion: np.ndarray
    """The observed motion, object frame, about the first mask's centroid, shape (3,)."""
    rotation_observed: bool
    """False: the rotation is unknown (neither its sense nor its size is scored)."""
    tracking: tuple
    """Standard deviations (rad, px) of the motion's measurement error."""
    flip_prob: float
    """The probability the observed sense is wrong (:func:`sense_flip_prob`)."""
    path: Any
    """The object's poses during the push (a ``PushPath``) the model scores, or None."""
    pixels: np.ndarray
    """The CoM hypotheses, shape (p, 2)."""
    distances: np.ndarray
    """Their signed distances to the push's force line per friction value, shape (p, m, 1)."""
    alive: Any = None
    """Which hypotheses (p, m, k) the model is asked about."""
    weights: Any = None
    """Their posterior mass before the push, shape (p, m, k)."""


class ReadingKey(NamedTuple):
    """One reading of a push whose end terms a :class:`PushMemo` keeps."""

    motion: bytes
    """The motion read (its bytes)."""
    rotation_observed: bool
    """Whether its rotation was observed."""
    tracking: tuple
    """Its tracking standard deviations (rad, px)."""


class OffsetMarginal(NamedTuple):
    """The model's motion for a push over the pusher's offset (:func:`offset_marginal`)."""

    asked: np.ndarray
    """Which (pixel, friction, model) hypotheses were asked, shape (p, m, n_models)."""
    motion: np.ndarray
    """The nodes' mean motion, shape (p, m, n_models, 3)."""
    spread: tuple
    """Standard deviations (rad, px) of the motion over the nodes."""


class EndTerms(NamedTuple):
    """The end pose's terms of one reading against the model's predictions."""

    base: list
    """:func:`motion_terms` at the model's own scales."""
    per_scale: list
    """The log-likelihood (p, m, n_models) at each factor of ``model_scales``."""


@dataclass(eq=False)
class PushMemo:
    """The model's predictions for one push, kept for its other readings (internal, mutable).

    The predictions depend on the push and the posterior's live hypotheses, not on the
    motion read: a symmetric outline's rotations, and a reading scored again with its
    path, read them once. Pass one new memo to every :func:`push_evidence` call for
    the same push.
    """

    offset_marginal: OffsetMarginal | None = None
    """The model's motion for the live hypotheses (None until asked)."""
    end_terms: dict = field(default_factory=dict)
    """The end terms of each reading (:class:`ReadingKey` -> :class:`EndTerms`)."""
    known: KnownPushes | None = None
    """The predictions of every push known up front (read instead of asking the model)."""


class Predicted(NamedTuple):
    """The model's predictions for a push on a set of hypotheses, shared by its readings."""

    motion: np.ndarray
    """The end motion over the pusher's offset, shape (p, m, n_models, 3)."""
    offset: np.ndarray
    """Each hypothesis' CoM minus the first mask's centroid, shape (p, 1, 1, 2)."""
    tracking: tuple
    """The reading's tracking (rad, px) widened by the pusher offset's spread."""
    along: Any
    """The motion after each of the path's travels, (p, m, n_models, J, 3), or None."""
    path_weights: Any
    """The posterior mass per (p, m, n_models) the path's scales are averaged over."""


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
    memo: PushMemo | None = None,
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
    memo : PushMemo, optional
        Keeps the model's predictions for another reading of the same push
        (a symmetric outline's other rotations) against the same posterior:
        pass one new :class:`PushMemo` to every call for that push.
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
        push = PushToScore(
            scoring,
            mask,
            action,
            observed,
            rotation_observed,
            tracking,
            flip_prob,
            path=None if scoring.path_wander is None else path,
            pixels=post.pixels,
            distances=distances,
        )
        terms = _model_terms(push, post, PushMemo() if memo is None else memo)
        excess = excess + terms[2]
    # the force line's terms are the same at every temper: computed once
    sides = _sense_logs(distances, observed, theta_tol, scoring.line_scale_px)
    full = _tempered_log_likelihood(sides, flip_prob, terms, 1.0)
    weights = scoring.model_weights if terms is not None and tempered else (1.0,)
    rows = [
        full if w == 1.0 else _tempered_log_likelihood(sides, flip_prob, terms, w) for w in weights
    ]
    return Evidence(np.stack(rows), full), excess


def _tempered_log_likelihood(sides, flip_prob: float, terms, weight: float):
    """The push's log-likelihood with the model's ``terms`` (or None) raised to ``weight``."""
    model_term, flipped_term = (None, None) if terms is None else terms[:2]
    if terms is not None:
        model_term, flipped_term = weight * model_term, weight * flipped_term
    return _with_flips(sides, flip_prob, model_term, flipped_term)


def sense_flip_prob(flip_prob: float, theta: float, track_theta: float, observed: bool) -> float:
    """The probability an observed sense is wrong: ``flip_prob``, or more near zero.

    A rotation within a few tracking standard deviations of zero may have been
    flipped by the noise: the sense is trusted less, by the probability
    ``Phi(-|theta| / sigma)`` that noise of that size flipped it.
    """
    if observed and track_theta > 0:
        flip_prob += (1 - 2 * flip_prob) * float(ndtr(-abs(theta) / track_theta))
    return flip_prob


def _model_terms(push: PushToScore, post: GridPosterior, memo: PushMemo):
    """The model's log-likelihood of the motion, of its flipped sense, and the excess surprise.

    Each (p, m, k); hypotheses more than :data:`PRUNE_LOG` nats below the best
    are not asked about (their terms are ``-inf``, their excess ``inf``).
    """
    alive = post.log_w > post.log_w.max() - PRUNE_LOG  # (p, m, models x scales)
    weights = np.exp(post.log_w)
    lattice = post.model_lattice(push.scoring.lattice_stride)
    if lattice is None:
        return _terms_at(push._replace(alive=alive, weights=weights), memo)
    # a camera finer than the model's spacing: the terms on the lattice, spread to every pixel
    usable = lattice.gather_any(alive)
    on_lattice = push._replace(
        pixels=push.pixels[lattice.nodes],
        distances=push.distances[lattice.nodes],
        alive=usable,
        weights=lattice.gather_sum(weights),
    )
    terms = _terms_at(on_lattice, memo)
    model_term, flipped_term, excess = (lattice.spread(t, usable) for t in terms)
    return (
        np.where(alive, model_term, -np.inf),
        np.where(alive, flipped_term, -np.inf),
        np.where(alive, excess, np.inf),
    )


def _terms_at(push: PushToScore, memo: PushMemo):
    """:func:`_model_terms` on the hypotheses ``push`` names (the posterior's, or a lattice's)."""
    n_s = push.scoring.n_scales
    asked = push.alive.reshape(*push.alive.shape[:2], -1, n_s).any(axis=-1)
    predicted = _predicted(push, asked, memo)
    model_term, base = _scored(push, predicted, push.motion, memo)
    # The consistency check keeps the base scales (a wider factor must not hide a misfit).
    model_excess = excess_surprise(base)
    if push.rotation_observed:
        flipped = push.motion * np.array([-1.0, 1.0, 1.0])
        flipped_term, flipped_base = _scored(push, predicted, flipped, memo, -1.0)
        # A flipped sense explains the motion at the price of the flip.
        flip_cost = np.log((1 - push.flip_prob) / push.flip_prob)
        model_excess = np.minimum(model_excess, excess_surprise(flipped_base) + flip_cost)
    else:
        flipped_term = model_term
    model_excess = np.repeat(model_excess, n_s, axis=-1)
    return model_term, flipped_term, np.where(push.alive, model_excess, np.inf)


def _predicted(push: PushToScore, asked, memo: PushMemo) -> Predicted:
    """The model's predictions for ``push`` on the hypotheses ``asked`` (read from ``memo``)."""
    offset = (push.pixels - np.asarray(push.mask.centroid))[:, None, None, :]
    kept = memo.offset_marginal
    if kept is None or not np.array_equal(kept.asked, asked):  # another posterior's
        motion, spread = offset_marginal(
            push.scoring, push.mask, push.action, push.pixels, offset, asked, known=memo.known
        )
        kept = memo.offset_marginal = OffsetMarginal(asked, motion, spread)
        memo.end_terms.clear()  # they were read against the other predictions
    # The pusher's offset spreads the prediction: its std adds to the tracking's.
    spread, tracking = kept.spread, push.tracking
    widened = (np.hypot(tracking[0], spread[0]), np.hypot(tracking[1], spread[1]))
    along, weights = None, push.weights
    if push.path is not None:
        along = path_predictions(
            push.scoring, push.mask, push.action, push.pixels, asked, push.path
        )
        weights = weights.reshape(*asked.shape, -1).sum(axis=-1)
    return Predicted(kept.motion, offset, widened, along, weights)


def _scored(push: PushToScore, predicted: Predicted, motion, memo: PushMemo, sign=1.0):
    """The motion's log-likelihood per scale factor, and its base scales' residuals.

    ``sign`` -1: the flipped sense's (the path's rotations negated too).
    """
    ends = _end_terms(push, predicted, motion, memo)
    terms = []
    for factor, term in zip(push.scoring.model_scales, ends.per_scale):
        if predicted.along is not None:
            term = term + path_term(push, predicted, motion, factor, sign)
        terms.append(term)
    full = np.stack(terms, axis=-1).reshape(push.alive.shape)
    return np.where(push.alive, full, -np.inf), ends.base


def _end_terms(push: PushToScore, predicted: Predicted, motion, memo: PushMemo) -> EndTerms:
    """The end pose's residuals and log-likelihood per scale factor, kept in ``memo``."""
    key = ReadingKey(
        motion.tobytes(), bool(push.rotation_observed), tuple(map(float, push.tracking))
    )
    entry = memo.end_terms.get(key)
    if entry is None:
        base = _residuals(push, predicted, motion, 1.0)
        factors = [
            base if c == 1.0 else _residuals(push, predicted, motion, c)
            for c in push.scoring.model_scales
        ]
        entry = memo.end_terms[key] = EndTerms(base, [log_likelihood(f) for f in factors])
    return entry


def _residuals(push: PushToScore, predicted: Predicted, motion, factor: float) -> list:
    """:func:`motion_terms` of ``motion`` with the model's error scales times ``factor``."""
    return motion_terms(
        motion,
        predicted.motion,
        np.abs(push.distances),
        predicted.offset,
        push.scoring.model_noise.scaled(factor),
        rotation=push.rotation_observed,
        tracking=predicted.tracking,
    )


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
                pred = check_model_output(
                    model,
                    pred,
                    np.tile(act, (len(path.fractions), 1)),
                    pixels[idx],
                    mu_j,
                    mask,
                    method="predict_path_hypotheses",
                )
                out[idx, j, k] = pred
    return np.where(alive[..., None, None], out, 0.0)


def path_term(push: PushToScore, predicted: Predicted, motion, factor: float, sign: float = 1.0):
    """The path's log density given the end pose (:mod:`comcore.active._motion_term`).

    Per hypothesis (p, m, k) for the model's scales times ``factor``; ``sign`` -1 scores
    the path with every rotation negated (the flipped sense). The scales are the
    end's, averaged (in variance) over the posterior before the push
    (``predicted.path_weights``): one per push, so that the path's density does not
    favour the hypotheses the model claims to predict best, which its normalising
    constant would, many frames over.
    """
    scoring, weights, offset = push.scoring, predicted.path_weights, predicted.offset
    (th_a, th_n), (tr_a, tr_r) = scoring.theta_noise, scoring.translation_px
    lever = np.abs(push.distances)
    th_scale = theta_scale(lever, (factor * th_a, factor * th_n), scoring.near_px)
    moved_pred = predicted.motion[..., 1:] + com_shift(predicted.motion[..., 0], offset)
    tr_scale = factor * (tr_a + tr_r * np.hypot(moved_pred[..., 0], moved_pred[..., 1]))
    total = max(float(weights.sum()), 1e-300)
    th_scale = np.sqrt(
        float((weights * np.broadcast_to(th_scale, weights.shape) ** 2).sum()) / total
    )
    tr_scale = np.sqrt(
        float((weights * np.broadcast_to(tr_scale, weights.shape) ** 2).sum()) / total
    )
    path = push.path
    if sign < 0:
        flipped = (p._replace(motion=p.motion._replace(theta=-p.motion.theta)) for p in path.points)
        path = path._replace(points=tuple(flipped))
    return path_log_likelihood(
        path,
        np.asarray(motion, float),
        predicted.motion,
        predicted.along,
        offset,
        (th_scale, tr_scale),
        wander=scoring.path_wander,
    )


def push_log_likelihood(
    distances,
    motion,
    flip_prob: float,
    theta_tol: float,
    *,
    model_term=None,
    flipped_term=None,
    scale: float = LINE_SCALE_PX,
):
    """Log-likelihood of one observed push over the grid, shape (p, m, 1) or (p, m, k).

    With probability ``1 - flip_prob`` the observed sense is the true one; with
    ``flip_prob`` it is flipped (and then the unflipped rotation is what the
    motion model must explain). The Voting Theorem term is the soft side of
    the force line (:func:`comcore.vt._voting.side_probability`); a rotation
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
