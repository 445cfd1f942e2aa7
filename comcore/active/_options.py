"""What a user sets for the active estimator that has no module of its own.

The option groups live where they act: :class:`comcore.Likelihood` in
:mod:`comcore.active._likelihood` (how a push's observed motion is scored),
:class:`comcore.StopRule` in :mod:`comcore.active._stop` (when a session stops) and
:class:`comcore.PushChoice` in :mod:`comcore.active._choice` (how the next push is
chosen). Each is a frozen dataclass checked when it is built (lengths in metres, angles
in radians), each default on its field and nowhere else.
This module holds the defaults the entry points share (``model``, ``credible``,
the systematic error's floors), :func:`group_or_default`, which checks a group an
entry point was passed, and the helpers the groups' checks share.
"""

from __future__ import annotations

from .._status import DEFAULT_TARGET_RADIUS
from .._validation import check_count
from ..conventions import DEFAULT_PUSHER_RADIUS

__all__ = [
    "DEFAULT_CREDIBLE",
    "DEFAULT_MODEL",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_TARGET_RADIUS",
    "RECORDED_SYSTEMATIC_ERROR",
    "SESSION_SYSTEMATIC_ERROR",
    "group_or_default",
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


class _DefaultModel:
    """The ``model`` argument's default: ``LimitSurfaceModel(pusher_radius=pusher_radius)``."""

    def __repr__(self) -> str:
        return "<default: comcore.LimitSurfaceModel(pusher_radius=pusher_radius)>"

    def __reduce__(self):
        return "DEFAULT_MODEL"


#: ``model``'s default (``model=None`` asks for the Voting Theorem alone).
DEFAULT_MODEL = _DefaultModel()


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
