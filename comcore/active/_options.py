"""What a user sets for the active estimator, in three groups, each default written once.

:class:`Likelihood` (:mod:`comcore.active._likelihood`) says how a push's observed motion
is scored, :class:`StopRule`
when a session stops, :class:`PushChoice` how the next push is chosen. Each is a
frozen dataclass checked when it is built (lengths in metres, angles in
radians), and each default lives on its field and nowhere else. The entry points
(:func:`comcore.estimate_active`, :class:`comcore.ActiveSession`,
:func:`comcore.estimate_posterior`, :func:`comcore.calibrate_model_weight`) take
them as ``likelihood=``, ``stop=`` and ``choice=``; what is not a group's (the
motion ``model``, ``pusher_radius``, ``prior``, ``credible``, ``rng``,
``candidates``) stays a keyword of its own.

A flat option passed to an entry point (``max_pushes=3``) is a TypeError naming
the group to pass instead (:mod:`comcore.active._option_groups`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._status import DEFAULT_TARGET_RADIUS
from .._validation import check_count, check_physical, check_positive
from ..geometry._sampling import DEFAULT_TRAVEL_M
from ._stop import stop_index, stop_reason

__all__ = [
    "DEFAULT_CREDIBLE",
    "DEFAULT_MODEL",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_TARGET_RADIUS",
    "MAX_CANDIDATES",
    "RECORDED_SYSTEMATIC_ERROR",
    "SELECTIONS",
    "SESSION_SYSTEMATIC_ERROR",
    "PushChoice",
    "StopRule",
]

#: Radius (metres) of the pusher assumed when none is given: the simulators' default pusher.
DEFAULT_PUSHER_RADIUS = 0.004
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
#: Ways to choose the next push.
SELECTIONS = ("sense", "model")
#: Most default candidates drawn (:func:`comcore.sample_pushes`): a session's cost grows with
#: them (benchmarks/timing/bench_active.py times it).
MAX_CANDIDATES = 20_000


class _DefaultModel:
    """The ``model`` argument's default: ``LimitSurfaceModel(pusher_radius=pusher_radius)``."""

    def __repr__(self) -> str:
        return "<default: comcore.LimitSurfaceModel(pusher_radius=pusher_radius)>"

    def __reduce__(self):
        return "DEFAULT_MODEL"


#: ``model``'s default (``model=None`` asks for the Voting Theorem alone).
DEFAULT_MODEL = _DefaultModel()


@dataclass(frozen=True)
class StopRule:
    """When a session stops (its status then says why).

    It stops ``"ok"`` when the equivalent-circle radius ``sqrt(area / pi)`` of
    the credible region is at most ``target_radius`` after at least
    ``min_pushes`` pushes with evidence; ``"budget"`` when ``max_pushes``
    pushes are spent; ``"exhausted"`` when no candidate is left;
    ``"uninformative"`` when none is expected to teach more than
    ``min_information`` bits; and ``"inconsistent"`` instead of any of these
    when no hypothesis explains the pushes. The rule itself is
    :mod:`comcore.active._stop`.

    Attributes
    ----------
    max_pushes : int
        Budget of real pushes (>= 0).
    min_pushes : int
        Pushes with evidence before a small region may stop the session
        ``"ok"`` (0 lets a tight prior stop it before any push): one push
        cannot check the model, its motion is explained at some CoM however
        wrong the model is.
    target_radius : float
        The credible region's radius (metres) at which the session stops
        ``"ok"`` (default 6 mm, as :func:`comcore.estimate_posterior`'s;
        :class:`comcore.Status` maps the statuses). A region can be no
        smaller than part of a pixel (its last pixel counts in part: a
        posterior on one pixel has radius ``sqrt(credible / pi)`` pixels,
        0.535 at 90 %); at most 0.5 m.
    min_information : float
        Stop when no push is expected to teach more bits than this.

    Examples
    --------
    >>> import comcore
    >>> comcore.StopRule(max_pushes=8).max_pushes
    8
    >>> comcore.StopRule(max_pushes=2.5)
    Traceback (most recent call last):
    ...
    TypeError: max_pushes must be an int, got float
    """

    max_pushes: int = 5
    min_pushes: int = 2
    target_radius: float = DEFAULT_TARGET_RADIUS
    min_information: float = 1e-3

    def reason(self, state, resolution: float) -> str | None:
        """Why a session in ``state`` (a ``SessionState``) stops now, or None.

        The rule itself is :func:`comcore.active._stop.stop_reason`.
        """
        return stop_reason(self, state, resolution)

    def stop_index(self, history, resolution: float) -> int:
        """Where a run through ``history`` (its states, the prior first) would have stopped.

        For evaluating stop rules on recorded runs that did not stop early:
        see :func:`comcore.active._stop.stop_index`.
        """
        return stop_index(self, history, resolution)

    def __post_init__(self):
        _set(self, "max_pushes", check_count(self.max_pushes, "max_pushes", 0))
        _set(self, "min_pushes", check_count(self.min_pushes, "min_pushes", 0))
        target = check_physical(self.target_radius, "target_radius", "target_radius")
        _set(self, "target_radius", target)
        info = check_positive(self.min_information, "min_information", allow_zero=True)
        _set(self, "min_information", info)


@dataclass(frozen=True)
class PushChoice:
    """How the next push is chosen among the candidates (in :mod:`comcore.active._choice`).

    Attributes
    ----------
    selection : {"sense", "model"}
        ``"sense"``: the candidate whose observed sense of rotation is expected
        to tell the most about the CoM (exact over the whole posterior).
        ``"model"``: the candidate whose whole motion, as the motion model
        predicts it, is expected to tell the most (slower; it steers towards
        pushes where the model is least right, docs/explanation/method.md).
    n_candidates : int
        Number of default candidates (:func:`comcore.sample_pushes`), at most
        :data:`MAX_CANDIDATES`.
    cone : float
        Half-angle (radians, in [0, pi/2)) of the default candidates'
        directions about the inward normal; 0 pushes along the normal, where
        the contact sticks for any friction.
    travel : float
        How far (metres) the default candidates push past first contact: set
        it from your workspace. Longer pushes tell more per push, and the
        model errs more on them. At most 0.5 m (``comcore.conventions.PLAUSIBLE``).

    Examples
    --------
    >>> import comcore
    >>> comcore.PushChoice(selection="rotation")
    Traceback (most recent call last):
    ...
    ValueError: selection must be one of ('sense', 'model'), got 'rotation'
    """

    selection: str = "sense"
    n_candidates: int = 200
    cone: float = 0.0
    travel: float = DEFAULT_TRAVEL_M

    def __post_init__(self):
        if self.selection not in SELECTIONS:
            raise ValueError(f"selection must be one of {SELECTIONS}, got {self.selection!r}")
        n_candidates = _bounded_count(self.n_candidates, "n_candidates", MAX_CANDIDATES, "pushes")
        _set(self, "n_candidates", n_candidates)
        cone = check_positive(self.cone, "cone", allow_zero=True)
        if cone >= math.pi / 2:
            raise ValueError(f"cone must be a half-angle in [0, pi/2) radians, got {cone}")
        _set(self, "cone", cone)
        _set(self, "travel", check_physical(self.travel, "travel", "push_length"))


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
