"""What a user sets for the active estimator that has no module of its own.

The option groups live where they act: :class:`Likelihood` (how a push's observed
motion is scored), :class:`comcore.StopRule` in :mod:`comcore.active._stop` (when a
session stops) and :class:`comcore.PushChoice` in :mod:`comcore.active._choice` (how
the next push is chosen). Each is a frozen dataclass checked when it is built
(lengths in metres, angles in radians), each default on its field and nowhere else.
This module holds the defaults the entry points share (``model``, ``credible``,
the systematic error's floors), :func:`group_or_default`, which checks a group an
entry point was passed, and the helpers the groups' checks share.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._status import DEFAULT_TARGET_RADIUS
from .._validation import (
    check_count,
    check_mu,
    check_pair,
    check_physical,
    check_positive,
    check_powers,
    check_probability,
)
from ..conventions import ANGLE_EPS, DEFAULT_PUSHER_RADIUS, check_plausible
from ._motion_term import NEAR_LINE_M, model_error_log_density, theta_scale

__all__ = [
    "DEFAULT_CREDIBLE",
    "DEFAULT_MODEL",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_TARGET_RADIUS",
    "MAX_N_MU",
    "RECORDED_SYSTEMATIC_ERROR",
    "SESSION_SYSTEMATIC_ERROR",
    "UNKNOWN_MU_RANGE",
    "Likelihood",
    "group_or_default",
    "mu_grid",
]

#: Mass of the credible region an estimate reports (and the stop rule measures).
DEFAULT_CREDIBLE = 0.9
#: ``Likelihood.systematic_error`` (metres) where it is left ``None``, for the sessions
#: (:class:`comcore.ActiveSession`, :func:`comcore.estimate_active`, :class:`comcore.GoalSession`):
#: none. They stop after a few pushes, before an error shared by the pushes shows; a floor
#: here would keep them pushing (docs/explanation/calibration.md).
SESSION_SYSTEMATIC_ERROR = 0.0
#: ... and for :func:`comcore.estimate_posterior` and ``comcore estimate`` (every push of a
#: recording, its region read from the bagged posterior): the least floor with which the
#: credible region holds the CoM as often as its mass says on the MIT push dataset's train
#: plates (calibrated by benchmarks/realdata/real_pushes.py; docs/explanation/calibration.md).
RECORDED_SYSTEMATIC_ERROR = 0.0015
#: Friction range searched when ``mu`` is unknown (covers common pusher materials).
UNKNOWN_MU_RANGE = (0.0, 2.0)
#: ``Likelihood.path_wander``'s default: chosen among 1, 2 and 4 on seed-1 trials of
#: ``comcore bench``'s ``active-robot`` with frames at 10 Hz, on our engine and with noisy
#: masks (docs/explanation/calibration.md).
PATH_WANDER = 4.0
#: ``Likelihood.model_spacing``'s default (metres): the 2.5 mm pixel every accuracy table
#: was measured at, so that those sessions ask the model about every pixel as before, and a
#: finer camera asks it about as many hypotheses (:mod:`comcore.active._lattice`).
MODEL_SPACING = 0.0025
#: Largest cone half-angle used for an unbounded friction range (radians).
MAX_ALPHA = math.pi / 2 - 1e-3
#: Most friction values a likelihood marginalises over: the model is integrated once per
#: value, so the cost of a push grows with it (benchmarks/timing/bench_active.py times it).
MAX_N_MU = 32


class _DefaultModel:
    """The ``model`` argument's default: ``LimitSurfaceModel(pusher_radius=pusher_radius)``."""

    def __repr__(self) -> str:
        return "<default: comcore.LimitSurfaceModel(pusher_radius=pusher_radius)>"

    def __reduce__(self):
        return "DEFAULT_MODEL"


#: ``model``'s default (``model=None`` asks for the Voting Theorem alone).
DEFAULT_MODEL = _DefaultModel()


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
    0.5 rad) are refused with a guess at the unit they were typed in.

    Attributes
    ----------
    mu : None, float or (float, float)
        Contact friction: unknown (None, marginalised over ``[0, 2]``), known,
        or a range (marginalised over it).
    n_mu : int
        Number of friction values the unknown friction is marginalised over
        (at most :data:`MAX_N_MU`).
    flip_prob : float
        Probability that an observed sense of rotation is wrong, in (0, 0.5).
    theta_tol : float
        Rotations with ``|theta| <= theta_tol`` (radians) carry no sense.
    theta_noise : (float, float)
        The model's rotation error scale (radians): everywhere, and extra near
        the force line (``theta_noise[0] + theta_noise[1] / (1 + (lever /
        3.75 cm)^2)``).
    translation_error : (float, float)
        The model's error on the CoM's displacement: absolute (metres) and
        relative to the displacement.
    pusher_error : float
        Standard deviation (metres) of the pusher's position across its path:
        how far the executed push line may lie from the one scored.
    motion_noise : (float, float)
        Standard deviations of a measured motion's error, rotation (radians)
        and translation (metres): a camera tracker's 0.5 deg and 0.5 mm.
    model_weight : float or tuple of float
        Power in (0, 1] on the model's likelihood: a number fixes it, a
        sequence of powers is learned per session (their mixture, each
        weighted by how well it predicted every push before it was seen).
    model_scales : tuple of float
        Factors on the model's error scales, one unknown factor per session
        marginalised like the friction (``(1.0,)``: the scales as given).
    path_wander : float or None
        How much of the motion model's error along a push is not shared by the
        whole push, relative to its error at the push's end (>= 0): how much
        the frames of a push (``observe(..., frames=...)``) say to the model
        beyond its end pose. Small: the model's error is a shape it keeps
        along the push, and the path tells much; large: little. None: the
        model scores the end pose alone, and the frames only by the Voting
        Theorem, each stretch of the path on its own force line
        (:mod:`comcore.active._path`).
    model_spacing : float
        Spacing (metres, >= 0) of the lattice of CoM hypotheses the motion
        model is asked about: on a camera finer than it (1 mm per pixel: every
        second pixel in x and y) the model's terms of every other pixel are
        interpolated from the lattice's nodes around it
        (:mod:`comcore.active._lattice`), which keeps the cost of a push that
        of a 2.5 mm camera. A camera of this size per pixel or coarser, or 0:
        every pixel asked.
    systematic_error : None or float
        Standard deviation (metres) of an error on the CoM that more pushes do
        not average away (a motion model that errs the same way on every push
        of an object): the credible region, its radius and the stop rule read
        the posterior blurred by a Gaussian of this size. ``None`` (default):
        the estimator's own, :data:`SESSION_SYSTEMATIC_ERROR` (0) for the
        sessions (their pushes stop before it matters) and
        :data:`RECORDED_SYSTEMATIC_ERROR` (1.5 mm) for
        :func:`comcore.estimate_posterior` and ``comcore estimate``, which
        take every push of a recording (chosen on real pushes, docs/explanation/calibration.md).

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
    n_mu: int = 6
    flip_prob: float = 0.05
    theta_tol: float = ANGLE_EPS
    theta_noise: tuple[float, float] = (0.01, 0.13)
    translation_error: tuple[float, float] = (0.001, 0.056)
    pusher_error: float = 0.001
    motion_noise: tuple[float, float] = (math.radians(0.5), 0.0005)
    model_weight: Any = (0.25, 0.4, 0.6, 1.0)
    model_scales: tuple[float, ...] = (1.0,)
    path_wander: float | None = PATH_WANDER
    model_spacing: float = MODEL_SPACING
    systematic_error: float | None = None

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
            self.theta_noise, self.translation_error, theta_error, lever_m,
            displacement_error_m, displacement_m,
        )  # fmt: skip

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


def group_or_default(given, cls: type, keyword: str):
    """The option group an entry point runs with: ``given``, or ``cls()`` for None.

    ``keyword`` is the argument's name (``likelihood``, ``stop``, ``choice``).

    Raises
    ------
    TypeError
        On a value that is neither a ``cls`` nor None.

    Examples
    --------
    >>> import comcore
    >>> group_or_default(None, comcore.StopRule, "stop").max_pushes
    5
    >>> group_or_default({"max_pushes": 3}, comcore.StopRule, "stop")
    Traceback (most recent call last):
    ...
    TypeError: stop must be a comcore.StopRule or None, got dict
    """
    if given is None:
        return cls()
    if not isinstance(given, cls):
        raise TypeError(
            f"{keyword} must be a comcore.{cls.__name__} or None, got {type(given).__name__}"
        )
    return given


def _set(obj, name: str, value) -> None:
    object.__setattr__(obj, name, value)


def _bounded_count(value, name: str, most: int, what: str) -> int:
    """A count in ``[1, most]``; above ``most`` a ValueError saying what it would cost."""
    count = check_count(value, name, 1)
    if count > most:
        raise ValueError(
            f"{name} must be at most {most} ({what}; each one costs time on every push), "
            f"got {count}"
        )
    return count


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
