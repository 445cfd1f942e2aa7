"""The stop rule: when an active session stops, and what its status says.

Open this file to change when the active estimator stops. What a user sets is
:class:`StopRule` (``comcore.StopRule``); the rule is a pure function of the record
so far (:class:`comcore.active._records.SessionState`: the credible region's radius,
the pushes made and those with evidence, whether any hypothesis explains them) and
of that rule. The session applies
it after every observation (:class:`comcore.ActiveSession`), the offline
posterior reads its status from it (:func:`comcore.estimate_posterior`), and the
benchmark scripts that evaluate other rules on recorded runs call
:func:`stop_index` instead of writing their own.

In order:

1. ``"ok"``: the credible region's equivalent-circle radius is at most
   ``target_radius`` after at least ``min_pushes`` pushes with evidence;
2. ``"budget"``: ``max_pushes`` pushes were made (misses count, failed pushes
   do not);
3. otherwise the session chooses a push: ``"exhausted"`` when no candidate is
   left to offer, ``"uninformative"`` when none is expected to teach more than
   ``min_information`` bits.

Whatever the reason, the status is ``"inconsistent"`` instead when no (CoM,
friction, model) hypothesis explains the pushes well
(:func:`comcore.active._likelihood.consistency_threshold`), or when a push's
pusher ends inside the object as its motion moved it, which no hypothesis
explains (:mod:`comcore.active._overlap`).

A posterior over recorded pushes (:func:`offline_status`) chooses none and has
no budget: it is ``"ok"`` (consistent, its credible region at most its
``target_radius``, the session's 6 mm by default), ``"wide"`` (consistent, its
region wider: the session's ``"budget"``, ``"exhausted"`` or
``"uninformative"``), ``"no_evidence"`` or ``"inconsistent"``. Besides the
likelihood's check, its observed senses of rotation are checked on their own
(:func:`sense_check`), the one check the Voting Theorem alone can make: a
recording whose senses no CoM explains (theta with the wrong sign on an
object whose pushes do not all pass near its centroid), or whose answer most
of them contradict, is not ``"ok"`` whatever the model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._status import DEFAULT_TARGET_RADIUS, Status, region_reached
from .._validation import check_count, check_physical, check_positive

__all__ = [
    "SENSE_ALPHA",
    "STATUSES",
    "SenseCheck",
    "StopRule",
    "choice_status",
    "offline_status",
    "sense_check",
    "stop_index",
    "stop_reason",
]

#: Every status a session can stop with.
STATUSES = (Status.OK, Status.BUDGET, Status.EXHAUSTED, Status.UNINFORMATIVE, Status.INCONSISTENT)
#: The senses are inconsistent when even the hypothesis that explains most of them leaves
#: so many unexplained that, had it made them, so many or more would occur with less than
#: this probability (before the minimum over hypotheses lowers the count further).
SENSE_ALPHA = 1e-3


class SenseCheck(NamedTuple):
    """The check of a recording's observed senses (``posterior.senses`` of an offline posterior)."""

    n_pushes: int
    """Pushes whose sense of rotation was observed (counted)."""
    fewest_unexplained: int
    """The fewest of them any (CoM, friction) hypothesis leaves unexplained."""
    unexplained_at_estimate: int
    """Those a CoM at the estimate leaves unexplained (any friction)."""
    expected: float
    """How many the hypothesis that made them would leave unexplained, on average."""
    p_value: float
    """Probability of ``fewest_unexplained`` or more under that hypothesis."""

    @property
    def consistent(self) -> bool:
        """``p_value`` at least :data:`SENSE_ALPHA` and the estimate explains most senses."""
        return self.p_value >= SENSE_ALPHA and 2 * self.unexplained_at_estimate <= self.n_pushes


@dataclass(frozen=True)
class StopRule:
    """When a session stops (its status then says why).

    It stops ``"ok"`` when the equivalent-circle radius ``sqrt(area / pi)`` of
    the credible region is at most ``target_radius`` after at least
    ``min_pushes`` pushes with evidence; ``"budget"`` when ``max_pushes``
    pushes are spent; ``"exhausted"`` when no candidate is left;
    ``"uninformative"`` when none is expected to teach more than
    ``min_information`` bits; and ``"inconsistent"`` instead of any of these
    when no hypothesis explains the pushes (:func:`stop_reason`).

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
        ``"ok"`` (default 6 mm, as :func:`comcore.estimate_posterior`'s
        ``target_radius``;
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

        The rule itself is :func:`stop_reason`.
        """
        return stop_reason(self, state, resolution)

    def stop_index(self, history, resolution: float) -> int:
        """Where a run through ``history`` (its states, the prior first) would have stopped.

        For evaluating stop rules on recorded runs that did not stop early:
        see :func:`stop_index`.
        """
        return stop_index(self, history, resolution)

    def __post_init__(self):
        checked = {
            "max_pushes": check_count(self.max_pushes, "max_pushes", 0),
            "min_pushes": check_count(self.min_pushes, "min_pushes", 0),
            "target_radius": check_physical(self.target_radius, "target_radius", "target_radius"),
            "min_information": check_positive(
                self.min_information, "min_information", allow_zero=True
            ),
        }
        for name, value in checked.items():
            object.__setattr__(self, name, value)


def stop_reason(rule, state, resolution: float) -> Status | None:
    """Why a session in ``state`` stops before choosing a push, or None to go on.

    Parameters
    ----------
    rule : comcore.StopRule
    state : SessionState
        The latest state of the session's record (its credible radius in
        pixels, its push counts, whether it is consistent).
    resolution : float
        Metres per pixel of the first mask (``target_radius`` is in metres).

    Returns
    -------
    Status or None
        ``"ok"``, ``"budget"`` or ``"inconsistent"`` (either, when no
        hypothesis explains the pushes or ``state.contradiction`` says why
        none can), or None.

    Examples
    --------
    >>> import comcore
    >>> from comcore.active._records import SessionState
    >>> state = SessionState((0.0, 0.0), 3.0, 2.0, 0.0, 0.0, n_pushes=2, n_evidence=2)
    >>> stop_reason(comcore.StopRule(), state, 0.0025)  # 5 mm <= 6 mm after 2 pushes
    'ok'
    >>> stop_reason(comcore.StopRule(min_pushes=3), state, 0.0025) is None
    True
    """
    small = region_reached(state.credible_radius_px, rule.target_radius, resolution)
    if small and state.n_evidence >= rule.min_pushes:
        reason = Status.OK
    elif state.n_pushes >= rule.max_pushes:
        reason = Status.BUDGET
    else:
        return None
    return reason if state.consistent else Status.INCONSISTENT


def choice_status(rule, state, gain: float | None) -> Status | None:
    """The status after choosing a push of expected ``gain`` bits (None: none was offered).

    None when the push is worth making; else ``"exhausted"`` (nothing offered)
    or ``"uninformative"`` (``gain`` not above ``min_information``), or
    ``"inconsistent"`` when no hypothesis explains the pushes.
    """
    if gain is None:
        reason = Status.EXHAUSTED
    elif not gain > rule.min_information:
        reason = Status.UNINFORMATIVE
    else:
        return None
    return reason if state.consistent else Status.INCONSISTENT


def offline_status(
    state, senses: SenseCheck | None = None, *, reached: bool = True
) -> Status:
    """The status of a posterior over recorded pushes (it chooses none, so it has no budget).

    ``"no_evidence"`` when no push carried any, ``"inconsistent"`` when no
    hypothesis explains them or their senses fail :func:`sense_check`, else
    ``"ok"`` when its credible region ``reached`` the target radius
    (:func:`comcore._status.region_reached`) and ``"wide"`` when not.

    Examples
    --------
    >>> from comcore.active._records import SessionState
    >>> state = SessionState((0.0, 0.0), 9.0, 2.0, 0.0, 0.0, n_pushes=2, n_evidence=2)
    >>> offline_status(state), offline_status(state, reached=False)
    ('ok', 'wide')
    """
    if state.n_evidence == 0:
        return Status.NO_EVIDENCE
    if senses is not None and not senses.consistent:
        return Status.INCONSISTENT
    if not state.consistent:
        return Status.INCONSISTENT
    return Status.OK if reached else Status.WIDE


def sense_check(tally, estimate_index: int) -> SenseCheck:
    """Whether a recording's observed senses are what its best hypothesis would give.

    ``tally`` (:class:`comcore.vt._voting.SenseTally`) counts, for every
    (CoM, friction) hypothesis, the pushes whose observed sense it leaves
    unexplained, and the probability of each being so under the hypothesis
    that made them (``flip_prob`` and the force line's blur). The fewest any
    hypothesis leaves is compared with the Poisson-binomial law of that count:
    below :data:`SENSE_ALPHA` the senses are inconsistent (with ``flip_prob``
    0.05 and 40 pushes, 10 or more unexplained). So is an estimate (the
    posterior mean, at grid pixel ``estimate_index``) that leaves more than
    half of them unexplained, whatever the hypotheses' best.

    Examples
    --------
    >>> import numpy as np
    >>> from comcore.vt._voting import SenseTally
    >>> tally = SenseTally((2, 1))
    >>> for _ in range(20):  # twenty pushes, each saying the CoM is on the side of pixel 0
    ...     tally.add(np.array([[5.0], [-5.0]]), +1, 0.05, 1.0)
    >>> sense_check(tally, 0).consistent, sense_check(tally, 1).consistent
    (True, False)
    """
    allowed = np.asarray(tally.allowed, dtype=float)
    fewest = tally.fewest
    return SenseCheck(
        n_pushes=len(allowed),
        fewest_unexplained=fewest,
        unexplained_at_estimate=tally.at_pixel(estimate_index) if len(allowed) else 0,
        expected=float(allowed.sum()),
        p_value=_at_least(fewest, allowed),
    )


def _at_least(k: int, probabilities: np.ndarray) -> float:
    """P(at least ``k`` of independent events with these probabilities): Poisson-binomial."""
    if k <= 0:
        return 1.0
    counts = np.zeros(len(probabilities) + 1)
    counts[0] = 1.0
    for p in probabilities:  # the law of the count, one event at a time
        counts[1:] = counts[1:] * (1.0 - p) + counts[:-1] * p
        counts[0] *= 1.0 - p
    return float(min(1.0, math.fsum(counts[k:])))


def stop_index(rule, states, resolution: float) -> int:
    """Where a session that went through ``states`` would have stopped under ``rule``.

    For evaluating stop rules offline on recorded runs whose pushes do not
    depend on the rule (a run made without stopping early): the index of the
    first state at which :func:`stop_reason` stops, else the last state (a
    recorded run that ended on ``"exhausted"`` or ``"uninformative"`` ends
    there). ``states`` are a session's or :func:`comcore.estimate_posterior`'s
    history, the prior first.
    """
    states = list(states)
    if not states:
        raise ValueError("states must hold at least the prior's state")
    for k, state in enumerate(states):
        if stop_reason(rule, state, resolution) is not None:
            return k
    return len(states) - 1
