"""The active estimator's blocking form, :func:`estimate_active`.

A few lines over :class:`comcore.ActiveSession`: a grid posterior over (CoM
pixel, contact friction, motion model) (:mod:`comcore.active._grid`) that each push's
likelihood multiplies (:mod:`comcore.active._likelihood`), the pushes chosen
(:mod:`comcore.active._choice`) and the stop (:mod:`comcore.active._stop`) through the
session. The offline form over recorded pushes is :mod:`comcore.active._posterior`.
"""

from __future__ import annotations

import dataclasses

from .._mask import Mask
from .._status import PushFailedError, Status
from .._types import Estimate, Motion
from .._validation import check_mask, check_motions
from ._session import ActiveSession

__all__ = ["estimate_active"]


def estimate_active(mask: Mask, push, candidates=None, **options) -> Estimate:
    """Find the CoM by pushing the real object, choosing each push from what was seen.

    The blocking form of :class:`comcore.ActiveSession`: a posterior over (CoM
    pixel, contact friction, motion model) that each push's observed motion
    multiplies by its likelihood (:class:`comcore.Likelihood`); the next push is
    the candidate expected to teach the most about the CoM
    (:class:`comcore.PushChoice`), until :class:`comcore.StopRule` stops it.

    Parameters
    ----------
    mask : Mask
        The object as seen before the first push. Every action is given in this
        frame: ``push`` must execute it on the object in this pose (reset the
        object, or map the action through the motions observed so far).
    push : callable
        ``push(action: Action) -> Motion`` (or ``(theta, tx, ty)``): the robot or
        simulator; or ``-> (motion, executed)``, ``executed`` the pusher's path
        as it really went (pixels of ``mask``), scored as executed.
    candidates : array_like, shape (n, 4), optional
        Pushes to choose from (default: drawn with ``choice``'s settings).
    **options
        :class:`comcore.ActiveSession`'s keywords (``model``, ``pusher_radius``,
        ``prior``, ``credible``, ``rng``, ``likelihood``, ``stop``, ``choice``).

    Returns
    -------
    Estimate
        ``com`` the posterior mean, ``region`` the credible region, ``used`` the
        indices into ``candidates`` in execution order, ``pushes`` one
        :class:`comcore.PushRecord` per push (:func:`comcore.estimate_posterior`
        replays them), ``posterior`` (:class:`comcore.active.PosteriorDetails`).

    Raises
    ------
    PushFailedError
        If ``push`` raises or returns an invalid motion or executed path; its
        ``index`` says which push, ``partial`` holds the estimate so far.
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    A toy robot whose object turns 0.1 rad in the Voting Theorem's sense and
    does not move (no physics: the Voting Theorem alone, ``model=None``):

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> true_com = np.array([17.0, 20.0])
    >>> def push(action):
    ...     c = comcore.geometry.contacts(mask, action)
    ...     s = comcore.vt.predicted_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
    ...     return comcore.Motion(0.1 * s, 0.0, 0.0)
    >>> est = comcore.estimate_active(mask, push, model=None, stop=comcore.StopRule(max_pushes=8),
    ...                               rng=0)
    >>> est.status, len(est.used), round(est.error_px(true_com), 1)
    ('budget', 8, 1.2)
    >>> comcore.estimate_active(mask, push, model=None, stop=comcore.StopRule(max_pushes=0)).com
    (22.5, 22.5)
    """
    mask = check_mask(mask)
    if not callable(push):
        raise TypeError(
            f"push must be callable as push(action) -> Motion, got {type(push).__name__}"
        )
    session = ActiveSession(mask, candidates=candidates, **options)
    while not session.done:
        action = session.next_push()
        try:
            motion, executed = _push_result(push(action))
        except Exception as e:
            raise _push_failed(session, action, e) from e
        try:  # push() executes every action on the object in mask's pose
            session.observe(motion=motion, executed=executed, reset=True)
        except (TypeError, ValueError) as e:  # a bad executed path; the session is unchanged
            if executed is None:
                raise
            raise _push_failed(session, action, e) from e
    return session.estimate()


def _push_failed(session: ActiveSession, action, error: Exception) -> PushFailedError:
    """The error for a push that raised or returned something invalid, with the estimate so far."""
    n_done = len(session.actions)
    return PushFailedError(
        f"push {n_done} ({tuple(action)}) failed: {type(error).__name__}: {error}",
        index=n_done,
        action=action,
        partial=dataclasses.replace(session.estimate(), status=Status.PUSH_FAILED),
    )


def _push_result(result):
    """``(motion, executed or None)`` from what ``push`` returned (validated)."""
    if not isinstance(result, Motion) and isinstance(result, (tuple, list)) and len(result) == 2:
        motion, executed = result
        return check_motions(motion, n=1, name="push result's motion")[0], executed
    return check_motions(result, n=1, name="push result")[0], None
