"""What an estimate or a session says about itself: :class:`Status`, every member in one place."""

from __future__ import annotations

import enum
import sys

__all__ = [
    "DEFAULT_TARGET_RADIUS",
    "ComcoreError",
    "ImageError",
    "PushFailedError",
    "SessionError",
    "Status",
    "region_reached",
]

#: Radius (metres) an estimate's region must reach for ``"ok"`` (:class:`Status`):
#: ``StopRule.target_radius`` of the sessions, ``target_radius`` of
#: :func:`comcore.estimate_posterior` and :func:`comcore.estimate_progressive`, and
#: ``comcore estimate --target-radius``.
DEFAULT_TARGET_RADIUS = 0.006

if sys.version_info >= (3, 11):
    from enum import StrEnum as _StrEnum
else:  # Python 3.10

    class _StrEnum(str, enum.Enum):
        """``enum.StrEnum`` of Python 3.11: members are their strings, printed as such."""

        __str__ = str.__str__
        __format__ = str.__format__


class Status(_StrEnum):
    """Why an estimator returned what it did, or what a session waits for.

    Every ``status`` of an :class:`~comcore.Estimate`, :class:`~comcore.ActiveSession` and
    :class:`~comcore.GoalSession` is a member. A member is its string (``Status.OK == "ok"``;
    ``json.dumps``, f-strings and repr give the string). Only ``OK`` makes ``Estimate.ok`` true;
    every other final status comes with its estimator's fallback (usually the mask's area
    centroid), never a NaN. What to do on each: docs/tutorials/robot-session.md.

    ``ok`` means, for every estimator, that the data were consistent AND the estimate's region
    (the 90 % credible region; Alg. 2's final feasible region) reached ``target_radius``
    (metres, default 6 mm; radius ``sqrt(area / pi)``, by :func:`region_reached`), a session's
    only after ``StopRule.min_pushes`` pushes with evidence. Consistent but wider, it says why:

    | entry point | region reached the target | consistent, region wider |
    | --- | --- | --- |
    | a session (``ActiveSession``) | ``ok`` | ``budget``, ``exhausted``, ``uninformative`` |
    | ``estimate_posterior``, ``comcore estimate`` | ``ok`` | ``wide`` |
    | ``estimate_progressive`` (Alg. 2) | ``ok`` | ``wide`` |

    Attributes
    ----------
    OK : "ok"
        Consistent, and the region reached the target radius.
    WIDE : "wide"
        Consistent, but the region is wider than the target radius (offline estimators): usable.
    UNCHECKED : "unchecked"
        Alg. 1 (:func:`comcore.estimate_heatmap`) or the centroid baseline: nothing tests it.
    NO_ACTIONS, FLAT_HEATMAP, EMPTY_REGION : "no_actions", "flat_heatmap", "empty_region"
        The mask's centroid: no push could be used (none given, or none turned enough);
        Alg. 1's heat map is flat over the object; the region an estimator kept is empty.
    INCONSISTENT : "inconsistent"
        The pushes contradict each other (Alg. 2 lists them in ``progressive.contradicted``):
        do not use the estimate; check the pixel frame and the sign of theta.
    NO_EVIDENCE : "no_evidence"
        No push moved the object measurably (:func:`comcore.estimate_posterior`); the prior's mean.
    BUDGET, EXHAUSTED, UNINFORMATIVE : "budget", "exhausted", "uninformative"
        A session stopped wide but usable: it spent ``StopRule.max_pushes`` (``comcore bench``:
        its budget); had no candidate push left in this pose; had none expected to teach
        ``StopRule.min_information`` bits.
    PUSH_FAILED : "push_failed"
        :func:`comcore.estimate_active`'s partial estimate when a push failed.
    WAITING_PUSH, WAITING_OBSERVATION : "waiting_push", "waiting_observation"
        A session goes on: call its ``next_push()``, or ``observe(...)`` for the push handed out.
    REACHED, STUCK, LOST : "reached", "stuck", "lost"
        :class:`comcore.GoalSession`: within tolerance; no push brings it closer; out of view.
    ERROR : "error"
        ``comcore bench`` only: the estimator (or its simulation) raised; see the row's message.

    Examples
    --------
    >>> import json
    >>> from comcore import Status
    >>> Status("budget") == "budget", json.dumps(Status.OK), f"{Status.WIDE}"
    (True, '"ok"', 'wide')
    """

    OK = "ok"
    WIDE = "wide"
    UNCHECKED = "unchecked"
    NO_ACTIONS = "no_actions"
    FLAT_HEATMAP = "flat_heatmap"
    EMPTY_REGION = "empty_region"
    INCONSISTENT = "inconsistent"
    NO_EVIDENCE = "no_evidence"
    BUDGET = "budget"
    EXHAUSTED = "exhausted"
    UNINFORMATIVE = "uninformative"
    PUSH_FAILED = "push_failed"
    WAITING_PUSH = "waiting_push"
    WAITING_OBSERVATION = "waiting_observation"
    REACHED = "reached"
    STUCK = "stuck"
    LOST = "lost"
    ERROR = "error"

    def __repr__(self) -> str:
        return repr(self.value)

    @classmethod
    def check(cls, value, name: str = "status") -> Status:
        """``value`` as a member, or a ValueError listing the members.

        >>> Status.check("ok") is Status.OK
        True
        >>> Status.check("contradiction")
        Traceback (most recent call last):
        ...
        ValueError: status must be a comcore.Status, one of ['ok', ...], got 'contradiction'
        """
        try:
            return cls(value)
        except ValueError:
            raise ValueError(
                f"{name} must be a comcore.Status, one of {[m.value for m in cls]}, got {value!r}"
            ) from None


def region_reached(radius_px: float, target_radius: float, resolution: float) -> bool:
    """Whether a region of equivalent-circle radius ``radius_px`` reached ``target_radius``.

    The one comparison behind every ``ok`` (:class:`Status`): ``radius_px``
    pixels of ``resolution`` metres at most ``target_radius`` metres.

    >>> region_reached(2.0, 0.006, 0.0025), region_reached(3.0, 0.006, 0.0025)
    (True, False)
    """
    return radius_px <= target_radius / resolution


class ComcoreError(Exception):
    """Base class of every error that comcore raises on its own account.

    Input validation errors are plain :class:`ValueError` / :class:`TypeError`
    (they name the argument and what was expected); this base is for failures
    that are not about the shape of the input.
    """


class ImageError(ComcoreError, ValueError):
    """A camera image or mask that does not show one whole object.

    Raised by :func:`comcore.mask_from_image` (an all-dark or all-bright image,
    an object touching the image border, a speckled or empty result) and by
    :func:`comcore.measure_motion` (a mask touching the image border: part of
    the object may be out of view). The message says what was seen.
    """


class PushFailedError(ComcoreError, RuntimeError):
    """A caller-supplied ``push`` callable failed or returned an invalid motion.

    Attributes
    ----------
    index : int
        Zero-based number of the push that failed.
    action : comcore.Action
        The action that was being executed.
    partial : object
        What the estimator had learned before the failure (an
        :class:`comcore.Estimate`), or ``None``.
    """

    def __init__(self, message: str, *, index: int, action, partial=None):
        super().__init__(message)
        self.index = index
        self.action = action
        self.partial = partial


class SessionError(ComcoreError, RuntimeError):
    """A :class:`comcore.ActiveSession` method called out of turn.

    ``observe()`` before ``next_push()`` (or twice for one push),
    ``next_push()`` after the session is done. The session is unchanged.
    """
