"""The active estimator's blocking form, :func:`estimate_active`.

A few lines over :class:`comcore.ActiveSession`: a grid posterior over (CoM
pixel, contact friction, motion model) (:mod:`comcore.active._grid`) that each push's
likelihood multiplies (:mod:`comcore.active._likelihood`), the pushes chosen
(:mod:`comcore.active._choice`) and the stop (:mod:`comcore.active._stop`) through the
session. The offline form over recorded pushes is :mod:`comcore.active._posterior`.
"""

from __future__ import annotations

import dataclasses

from .._errors import PushFailedError
from .._mask import Mask
from .._status import Status
from .._types import Estimate, Motion
from .._validation import check_mask, check_motions
from ._option_groups import check_groups, names_the_group
from ._options import DEFAULT_CREDIBLE, DEFAULT_MODEL, DEFAULT_PUSHER_RADIUS
from ._session import ActiveSession

__all__ = ["estimate_active"]


@names_the_group
def estimate_active(
    mask: Mask,
    push,
    candidates=None,
    *,
    model=DEFAULT_MODEL,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    prior=None,
    credible: float = DEFAULT_CREDIBLE,
    rng=None,
    likelihood=None,
    stop=None,
    choice=None,
) -> Estimate:
    """Find the CoM by pushing the real object, choosing each push from what was seen.

    A posterior over (CoM pixel, contact friction, motion model) starts from
    ``prior`` (uniform over the object): friction is one unknown shared by all
    pushes, marginalised, never assumed. Each push's observed motion multiplies
    in a likelihood (:class:`comcore.Likelihood`: the Voting Theorem's sense of
    rotation, soft and sometimes wrong; the motion model's whole motion,
    tempered by a power learned per session). The next push is the candidate
    expected to teach the most about the CoM (:class:`comcore.PushChoice`); the
    loop stops by :class:`comcore.StopRule`: ``"ok"`` when the ``credible``
    region is small enough after enough pushes, ``"budget"``,
    ``"exhausted"``, ``"uninformative"``, or ``"inconsistent"`` when no
    hypothesis explains the motions (a robot, model or tracker that does not
    behave as the likelihood says). docs/explanation/likelihood.md measures every choice.

    Parameters
    ----------
    mask : Mask
        The object as seen before the first push. Every action is given in this
        frame: ``push`` must execute it on the object in this pose (reset the
        object, or map the action through the motions observed so far).
    push : callable
        ``push(action: Action) -> Motion`` (or three numbers ``(theta, tx, ty)``):
        the robot or simulator. A robot that sees where its pusher really went
        returns ``(motion, executed)``, ``executed`` the path as executed (an
        :class:`Action` or four numbers, pixels of ``mask``): the push is then
        scored as executed (:meth:`comcore.ActiveSession.observe`).
    candidates : array_like, shape (n, 4), optional
        Pushes to choose from; each must start outside the object and hit it.
        Default: :func:`comcore.sample_pushes` with ``choice``'s settings.
    model : HypothesisPredictor, sequence of them, or None, optional
        Motion model of the likelihood. Default:
        ``comcore.LimitSurfaceModel(pusher_radius=pusher_radius)``. ``None``:
        the Voting Theorem alone. Several models are weighed against each
        other like the friction.
    pusher_radius : float, optional
        Radius (metres) of the round pusher, for the default model (default
        4 mm, comcore's simulators' pusher): set it from your robot.
    prior : array_like, shape (H, W), optional
        Non-negative prior weights of the CoM over the image (default uniform
        over the object; pass e.g. the convex hull if the CoM may lie off it).
    credible : float, optional
        Mass of the credible region, in (0, 1).
    rng : None, int or numpy.random.Generator, optional
        Seeds the default candidates (the only random choice).
    likelihood : Likelihood, optional
        How pushes are scored (noise scales in metres and radians, friction,
        the model's power); default ``comcore.Likelihood()``.
    stop : StopRule, optional
        When to stop; default ``comcore.StopRule()`` (5 pushes, 6 mm).
    choice : PushChoice, optional
        How pushes are chosen; default ``comcore.PushChoice()``.

    Returns
    -------
    Estimate
        ``com`` is the posterior mean, ``covariance`` the posterior covariance
        (px^2), ``region`` the credible region, ``used`` the indices into
        ``candidates`` in execution order, ``pushes`` one
        :class:`comcore.PushRecord` per push (pass them to
        :func:`comcore.estimate_posterior` to replay the posterior).
        ``posterior`` (:class:`comcore.active.PosteriorDetails`): the
        posterior image (H, W), the credible radius, the friction, model,
        scale and model-weight posteriors, the evidence and the ``history``,
        one :class:`comcore.active.SessionState` per posterior (the prior first).

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
    groups = check_groups(likelihood=likelihood, stop=stop, choice=choice)
    session = ActiveSession(
        mask, candidates=candidates, model=model, pusher_radius=pusher_radius, prior=prior,
        credible=credible, rng=rng, **groups,
    )  # fmt: skip
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
