"""The stop rule: when an active session stops, and what its status says.

Open this file to change when the active estimator stops. The rule is a pure
function of the record so far (:class:`comcore._records.SessionState`: the
credible region's radius, the pushes made and those with evidence, whether any
hypothesis explains them) and of :class:`comcore.StopRule`. The session applies
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
(:func:`comcore._likelihood.consistency_threshold`).
"""

from __future__ import annotations

__all__ = ["STATUSES", "choice_status", "offline_status", "stop_index", "stop_reason"]

#: Every status a session can stop with.
STATUSES = ("ok", "budget", "exhausted", "uninformative", "inconsistent")


def stop_reason(rule, state, resolution: float) -> str | None:
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
    str or None
        ``"ok"``, ``"budget"`` or ``"inconsistent"`` (either, when no
        hypothesis explains the pushes), or None.

    Examples
    --------
    >>> import comcore
    >>> from comcore._records import SessionState
    >>> state = SessionState((0.0, 0.0), 3.0, 2.0, 0.0, 0.0, n_pushes=2, n_evidence=2)
    >>> stop_reason(comcore.StopRule(), state, 0.0025)  # 5 mm <= 6 mm after 2 pushes
    'ok'
    >>> stop_reason(comcore.StopRule(min_pushes=3), state, 0.0025) is None
    True
    """
    small = state.credible_radius_px <= rule.target_radius / resolution
    if small and state.n_evidence >= rule.min_pushes:
        reason = "ok"
    elif state.n_pushes >= rule.max_pushes:
        reason = "budget"
    else:
        return None
    return reason if state.consistent else "inconsistent"


def choice_status(rule, state, gain: float | None) -> str | None:
    """The status after choosing a push of expected ``gain`` bits (None: none was offered).

    None when the push is worth making; else ``"exhausted"`` (nothing offered)
    or ``"uninformative"`` (``gain`` not above ``min_information``), or
    ``"inconsistent"`` when no hypothesis explains the pushes.
    """
    if gain is None:
        reason = "exhausted"
    elif not gain > rule.min_information:
        reason = "uninformative"
    else:
        return None
    return reason if state.consistent else "inconsistent"


def offline_status(state) -> str:
    """The status of a posterior over recorded pushes (it chooses none, so it has no budget).

    ``"no_evidence"`` when no push carried any, ``"inconsistent"`` when no
    hypothesis explains them, else ``"ok"``.
    """
    if state.n_evidence == 0:
        return "no_evidence"
    return "ok" if state.consistent else "inconsistent"


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
