"""What an estimate or a session says about itself: :class:`Status`, every member in one place."""

from __future__ import annotations

import enum
import sys

__all__ = ["Status"]

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

    Attributes
    ----------
    OK : "ok"
        The data were consistent and the answer is as good as it says (a
        session: its credible region is as small as its stop rule asks).
    UNCHECKED : "unchecked"
        Alg. 1 (:func:`comcore.estimate_heatmap`) found a region, but nothing
        tests its evidence: any motions, right or wrong, give one.
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
        the estimate is usable, its region wider.
    EXHAUSTED : "exhausted"
        An active session had no candidate push left to offer in this pose.
    UNINFORMATIVE : "uninformative"
        No candidate push left was expected to teach more than
        ``StopRule.min_information`` bits.
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
