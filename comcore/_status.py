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

    Every :attr:`Estimate.status <comcore.Estimate>`,
    :attr:`ActiveSession.status <comcore.ActiveSession>` and
    :attr:`GoalSession.status <comcore.GoalSession>` is a member. A member is its
    string (``Status.OK == "ok"``, ``json.dumps`` writes ``"ok"``, f-strings print
    ``ok``, and its repr is the string's, ``'ok'``), so code that compares with
    or prints the strings keeps working. Only ``OK``
    makes :attr:`Estimate.ok <comcore.Estimate>` true; every other final status
    comes with the fallback its estimator documents (usually the mask's area
    centroid), never a NaN.

    ``ok`` means one thing everywhere: the data were consistent AND the
    estimate's region reached the target radius (``target_radius``, metres,
    default 6 mm: the equivalent-circle radius ``sqrt(area / pi)`` of the
    region, compared by :func:`region_reached`). Where the data were
    consistent but the region did not reach it, the status says why:

    | entry point | region reached the target | consistent, region wider |
    | --- | --- | --- |
    | a session (``ActiveSession``) | ``ok`` | ``budget``, ``exhausted``, ``uninformative`` |
    | ``estimate_posterior``, ``comcore estimate`` | ``ok`` | ``wide`` |
    | ``estimate_progressive`` (Alg. 2) | ``ok`` | ``wide`` |

    A session (:class:`comcore.ActiveSession`, :func:`comcore.estimate_active`)
    is ``ok`` only after ``StopRule.min_pushes`` pushes with evidence; its
    three wide statuses name why it stopped before its region reached the
    target.
    The region is the 90 % credible region for the sessions and the posterior
    (``StopRule.target_radius`` for a session, the ``target_radius`` keyword
    of :func:`comcore.estimate_posterior`, ``--target-radius`` of ``comcore
    estimate``), and for Alg. 2 the final feasible region it takes its mean
    of (the ``target_radius`` keyword of :func:`comcore.estimate_progressive`).
    ``wide``, ``budget``, ``exhausted`` and ``uninformative`` all say: usable,
    less sure than asked. ``inconsistent`` replaces any of them when the data
    contradict each other: do not use the estimate.

    Attributes
    ----------
    OK : "ok"
        The data were consistent and the estimate's region reached the target
        radius (a session: its credible region is as small as its stop rule
        asks, after ``min_pushes`` pushes with evidence).
    WIDE : "wide"
        The data were consistent but the region is wider than the target
        radius (:func:`comcore.estimate_posterior`, ``comcore estimate``,
        :func:`comcore.estimate_progressive`): the estimate is usable and its
        region says how unsure it is; more pushes, across the region, narrow
        it. A session says ``budget``, ``exhausted`` or ``uninformative``
        instead, naming why it stopped wide.
    UNCHECKED : "unchecked"
        Alg. 1 (:func:`comcore.estimate_heatmap`) found a region, but nothing
        tests its evidence: any motions, right or wrong, give one. Also the
        area-centroid baseline (``comcore estimate --method centroid``, the
        bench's ``centroid``), which uses no push at all.
    NO_ACTIONS : "no_actions"
        No push could be used (none given, or none turned the object enough);
        the estimate is the mask's area centroid.
    FLAT_HEATMAP : "flat_heatmap"
        Alg. 1's heat map is flat over the object: the pushes single out no
        region; the estimate is the centroid.
    EMPTY_REGION : "empty_region"
        The region an estimator kept came out empty; the estimate is the
        centroid of the whole mask.
    INCONSISTENT : "inconsistent"
        The pushes contradict each other: no (CoM, friction, model) hypothesis
        explains them well (the posterior and the sessions, whatever their
        stop), or some of them contradict the region the others leave (Alg. 2,
        :func:`comcore.estimate_progressive`: the estimate rests on the
        others, :attr:`ProgressiveDetails.contradicted
        <comcore.paper.ProgressiveDetails>` lists them). Check the pixel
        frame and the sign of theta.
    NO_EVIDENCE : "no_evidence"
        No push moved the object measurably (:func:`comcore.estimate_posterior`):
        the estimate is the prior's mean.
    BUDGET : "budget"
        A session spent its ``max_pushes`` (:class:`comcore.StopRule`) before
        its region was small (active) or the object reached the goal (goal);
        the estimate is usable, its region wider than ``target_radius`` (or
        fewer than ``min_pushes`` pushes carried evidence): a session's
        ``wide``. In ``comcore bench`` it is the active estimator's trials
        that spent the bench's push budget before the target radius.
    EXHAUSTED : "exhausted"
        An active session had no candidate push left to offer in this pose
        (its region wider than the target: usable, as ``wide``).
    UNINFORMATIVE : "uninformative"
        No candidate push left was expected to teach more than
        ``StopRule.min_information`` bits (its region wider than the target:
        usable, as ``wide``).
    PUSH_FAILED : "push_failed"
        The partial estimate of :func:`comcore.estimate_active` when a push
        failed (:attr:`comcore.PushFailedError.partial`).
    WAITING_PUSH : "waiting_push"
        A session goes on: call its ``next_push()``.
    WAITING_OBSERVATION : "waiting_observation"
        A session handed a push out: call its ``observe(...)``.
    REACHED : "reached"
        :class:`comcore.GoalSession`: the pose is within the goal's tolerances.
    STUCK : "stuck"
        :class:`comcore.GoalSession`: no push is expected to bring the object
        closer (the goal needs a pull, or a push the outline does not allow).
    LOST : "lost"
        :class:`comcore.GoalSession`: the object left the camera's view.
    ERROR : "error"
        ``comcore bench`` only: the estimator (or the simulation of its
        motions) raised; the row's ``message`` says what.

    Examples
    --------
    >>> import json, comcore
    >>> comcore.Status.INCONSISTENT == "inconsistent", json.dumps(comcore.Status.OK)
    (True, '"ok"')
    >>> f"status {comcore.Status('budget')}"
    'status budget'
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
