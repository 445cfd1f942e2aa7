"""`comcore.ActiveSession`: the active estimator as an ask/tell loop on an object that moves.

The session holds the state and the order of calls; what it does at each step
lives in a file of its own: the likelihood of a push (:mod:`comcore.active._likelihood`),
the push choice (:mod:`comcore.active._choice`), the stop rule (:mod:`comcore.active._stop`),
the pose tracking (:mod:`comcore.camera._pose_tracking`), reading a push
(:mod:`comcore.active._reading`) and the records
(:mod:`comcore.active._records`).
"""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._status import SessionError
from .._types import Action, Estimate, Motion, SkippedPush
from .._validation import (
    check_motions,
    check_one_object,
    check_physical,
    check_probability,
    check_rng,
)
from ..camera._pose_tracking import moved_mask
from ..conventions import DEFAULT_PUSHER_RADIUS, apply_motion
from ..motion._limit_surface import check_push_lengths
from ._choice import Candidates, PushChoice
from ._grid import prior_grid
from ._likelihood import Likelihood, Scoring, check_models, gyration_px
from ._options import DEFAULT_CREDIBLE, DEFAULT_MODEL, group_or_default
from ._options import SESSION_SYSTEMATIC_ERROR as SESSION_FLOOR
from ._overlap import pusher_overlap
from ._reading import PushContext, read_push
from ._records import PushLog, PushLoop, SessionState
from ._stop import StopRule, choice_status, stop_reason

__all__ = ["ActiveSession", "session_setup"]


def session_setup(
    mask: Mask, model, pusher_radius, credible, likelihood, systematic_floor=SESSION_FLOOR
) -> tuple:
    """``(Scoring, credible)`` of an active estimator's arguments, each checked and named.

    ``likelihood`` is what the caller passed (a :class:`comcore.Likelihood` or None for its
    defaults); ``systematic_floor`` is the estimator's ``systematic_error`` where the
    likelihood leaves it None.
    """
    pusher_radius = check_physical(pusher_radius, "pusher_radius", "pusher_radius", allow_zero=True)
    models = check_models(model, pusher_radius)
    credible = check_probability(credible, "credible", open_low=True, open_high=True)
    likelihood = group_or_default(likelihood, Likelihood, "likelihood")
    scoring = Scoring.build(likelihood, mask, models, pusher_radius, systematic_floor)
    return scoring, credible


class ActiveSession(PushLoop):
    """Find the CoM by pushing, one push at a time, driven by the caller's loop.

    The ask/tell form of :func:`comcore.estimate_active` (same posterior, likelihood, push choice
    and stop rule) for a robot that cannot reset the object and sees it by camera: :meth:`next_push`
    gives a push in the camera frame, on the object where it is now; :meth:`observe` takes a mask, a
    motion or ``failed=True``; :meth:`estimate` gives the CoM in the first mask's frame. The
    :attr:`pose` is tracked from each mask (registered against the first) or motion. Candidates are
    drawn once on the first mask and move with the object; each is offered once, if it hits the
    object and stays in the image. Each call that changes the state applies the stop rule and
    chooses the next push; reading :attr:`done`, :attr:`status` or :attr:`history` computes nothing.
    Frames, misses: docs/explanation/method.md, docs/how-to/your-robot.md.

    Parameters
    ----------
    mask : Mask
        The object as the camera sees it before the first push.
    candidates : array_like, shape (n, 4), optional
        Pushes in the first mask's frame, each starting outside the object and hitting it
        (default: :func:`comcore.sample_pushes` with ``choice``'s settings).
    model : comcore.Predictor, sequence of them, or None, optional
        Motion model(s), weighed like the friction (default ``comcore.LimitSurfaceModel``;
        ``None``: the Voting Theorem alone).
    pusher_radius : float, optional
        Radius of the round pusher in metres (default 4 mm): set it from your robot.
    prior : array_like, shape (H, W), optional
        Non-negative prior weights of the CoM over the image (default uniform on the object).
    credible : float, optional
        Mass of the credible region, in (0, 1).
    rng : None, int or numpy.random.Generator, optional
        Seeds the default candidates (the only random choice).
    likelihood, stop, choice : Likelihood, StopRule, PushChoice, optional
        How pushes are scored, when to stop, how pushes are chosen (default: each class's).

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    The object turns 0.1 rad in the Voting Theorem's sense and stays put (``model=None``):

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> true_com = np.array([17.0, 20.0])
    >>> stop = comcore.StopRule(max_pushes=3)
    >>> session = comcore.ActiveSession(mask, model=None, stop=stop, rng=0)
    >>> while not session.done:
    ...     action = session.next_push()
    ...     c = comcore.geometry.contacts(mask, action)
    ...     s = comcore.vt.predicted_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
    ...     session.observe(motion=comcore.Motion(0.1 * s, 0.0, 0.0), reset=True)
    >>> session.status, len(session.actions)
    ('budget', 3)
    """

    def __init__(
        self,
        mask: Mask,
        *,
        candidates=None,
        model=DEFAULT_MODEL,
        pusher_radius: float = DEFAULT_PUSHER_RADIUS,
        prior=None,
        credible: float = DEFAULT_CREDIBLE,
        rng=None,
        likelihood=None,
        stop=None,
        choice=None,
    ):
        self._first = check_one_object(mask)
        self._stop_rule = group_or_default(stop, StopRule, "stop")
        self._choice = group_or_default(choice, PushChoice, "choice")
        self._scoring, credible = session_setup(
            self._first, model, pusher_radius, credible, likelihood
        )
        if self._choice.selection == "model" and not self._scoring.models:
            raise ValueError("selection='model' needs a model")
        pixels, prior_weights = prior_grid(self._first, prior)
        self._candidates = Candidates(
            self._first, candidates, self._choice, self._scoring.mus, check_rng(rng),
            pusher_radius=self._scoring.pusher_radius,
        )
        check_push_lengths(self._first, self._candidates.actions, "candidates")
        self._posterior = self._scoring.posterior(pixels, prior_weights)
        self._gyration_px = gyration_px(self._first)
        self._pose = Motion.identity()
        self._mask_now: Mask | None = self._first  # None: the first mask moved to the pose
        self._log = PushLog(self._posterior, credible, self._scoring.systematic_px)
        self._handed_out = False
        self._plan()

    # -- state ---------------------------------------------------------------------------

    @property
    def excess_nats(self) -> float:
        """How much more the pushes surprise the best hypothesis than its own motions would.

        The minimum over (CoM, friction, model) hypotheses of the summed
        excess surprise ``-log p(y | h) + E_h log p(Y | h)`` of the pushes
        with evidence: about 0 or below when some hypothesis explains the
        data, large when none does (0 before the first push).
        """
        return self._log.excess_nats

    @property
    def consistent(self) -> bool:
        """False when no hypothesis explains the pushes well (status ``"inconsistent"``).

        The :attr:`excess_nats` of the best hypothesis is above
        ``10 + 6 sqrt(n)`` for ``n`` pushes with evidence (above the 99.9 %
        quantile of its distribution under the likelihood), or, with a motion
        model, a push's pusher ends inside the object as its reported motion
        moved it (:mod:`comcore.active._overlap`; ``history[-1].contradiction``
        names the push and the depth).
        """
        return self._log.state.consistent

    def _plan(self) -> None:
        """Apply the stop rule to the latest state; if it goes on, choose the next push."""
        self._pending = None
        self._log.set_gain(None)
        state = self._log.state
        self._final = stop_reason(self._stop_rule, state, self._first.resolution)
        if self._final is not None:
            return
        offered = self._candidates.offerable(self._pose, self._current_mask())
        index, gain = self._candidates.choose(
            self._posterior, offered, self._scoring, self._choice.selection
        )
        self._final = choice_status(self._stop_rule, state, gain)
        if self._final is None:
            self._pending = index
            self._log.set_gain(gain)

    def _current_mask(self) -> Mask | None:
        if self._mask_now is not None:
            return self._mask_now
        return moved_mask(self._first, self._pose)

    @property
    def actions(self) -> np.ndarray:
        """Pushes executed (misses included), camera frame as handed out, shape (k, 4)."""
        return np.array([r.camera_action for r in self._log.executed], float).reshape(-1, 4)

    @property
    def motions(self) -> np.ndarray:
        """Their motions, camera frame (about the centroid at the time), shape (k, 3)."""
        return np.array([r.camera_motion for r in self._log.executed], float).reshape(-1, 3)

    @property
    def skipped_candidates(self) -> tuple[SkippedPush, ...]:
        """The given candidates never offered: they start inside the first mask or miss it."""
        return self._candidates.skipped

    @property
    def history(self) -> tuple[SessionState, ...]:
        """One :class:`SessionState` per posterior (the prior first)."""
        return tuple(self._log.history)

    # -- ask / tell ---------------------------------------------------------------------

    def _planned_push(self) -> Action:
        return Action(*self._candidates.in_pose(self._pose, [self._pending])[0])

    def observe(
        self,
        mask: Mask | None = None,
        *,
        motion=None,
        failed: bool = False,
        executed=None,
        frames=None,
        reset: bool = False,
    ) -> None:
        """Report what the push from :meth:`next_push` did: exactly one of the three.

        Parameters
        ----------
        mask : Mask, optional
            The camera's mask after the push (same shape and resolution as
            the first mask). The pose is measured against the first mask.
        motion : Motion or (theta, tx, ty), optional
            The push's motion in the camera frame, about the object's centroid
            before the push (``measure_motion(mask_before, mask_after)``).
        failed : bool, optional
            True: the push could not be executed (no evidence, not counted).
        executed : Action or (x0, y0, x1, y1), optional
            The pusher's path as it really went (camera pixels, the object where
            :meth:`next_push` found it), where the robot knows it better than
            it commands it: the pusher tracked in the camera, or the arm's
            measured path. The push is then scored as executed instead of as
            planned; set ``Likelihood(pusher_error=...)`` to how well you know
            this path, not how well the arm follows a command. Default: as
            planned.
        frames : sequence of PushFrame, optional
            What the camera saw while the object moved, in the order taken:
            ``(pusher, view)`` pairs (:class:`comcore.PushFrame`), ``pusher``
            the pusher's leading point in camera pixels as the robot reports
            it, ``view`` the camera's mask then (registered as ``mask`` is) or
            the object's motion since the push began (as ``motion``). The
            object's path along the push is scored with its end pose
            (:mod:`comcore.active._path`: how, and which frames are dropped
            and why, in the push's record). Default: the end pose alone.
        reset : bool, optional
            True: the object was put back in the first pose after the push (a
            robot that resets it, as :func:`comcore.estimate_active`'s ``push``
            does); the next push is planned there. The same as calling
            :meth:`reset_pose` next, without planning twice.

        Raises
        ------
        SessionError
            If no push is waiting for its observation.
        TypeError, ValueError
            On invalid arguments (named); the session is then unchanged and
            waits for the observation still. A ``mask`` that is not the first
            mask's object moved is refused so (its area changed by more than
            25 %, or its outline lies more than 1.5 px RMS from the first
            mask's after the best rigid motion: a single pixel, another
            object; :func:`comcore.camera._pose_tracking.read_pose`).
        """
        self._check_waiting()
        for name, value in (("failed", failed), ("reset", reset)):
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
        given = [name for name, v in (("mask", mask), ("motion", motion)) if v is not None]
        if failed:
            given.append("failed")
        if len(given) != 1:
            raise TypeError(
                f"observe() takes exactly one of mask, motion or failed=True, got {given}"
            )
        if failed and executed is not None:
            raise TypeError("observe(failed=True) takes no executed push: nothing was executed")
        record, evidence, pose = self._reading(mask, motion, failed, executed, frames)
        overlap = pusher_overlap(self._first, self._scoring, record, self._gyration_px)
        self._log.add(record, self._posterior, *evidence, overlap=overlap)
        self._candidates.made(self._pending)
        if record.outcome != "failed":
            self._mask_now = mask  # None after a motion: the first mask moved to the new pose
            self._pose = pose
        self._handed_out = False
        if reset:
            self._pose, self._mask_now = Motion.identity(), self._first
        self._plan()

    def _reading(self, mask, motion, failed: bool, executed, frames=None):
        """The push's record, its evidence ``(loglik, excess)`` or ``()``, and the new pose."""
        return read_push(
            PushContext(self._first, self._pose, self._posterior, self._scoring, self._gyration_px),
            self._candidates, self._pending, mask, motion, failed, executed=executed, frames=frames,
        )

    def reset_pose(self, pose=None) -> None:
        """Tell the session the object was put back in the first pose (or moved to ``pose``).

        Raises
        ------
        SessionError
            If a push is waiting for its observation.
        """
        if self._handed_out:
            raise SessionError("reset_pose() while a push waits for observe()")
        if pose is None:
            new = Motion.identity()
        else:
            new = Motion(*check_motions(pose, n=1, name="pose")[0])
        self._pose = new
        self._mask_now = self._first if new == Motion.identity() else None
        self._plan()  # a session that found nothing to push in the old pose may go on

    # -- results ------------------------------------------------------------------------

    def estimate(self) -> Estimate:
        """The estimate so far; ``com`` in the first mask's frame.

        ``used`` indexes the candidates of the executed pushes (misses
        included), in order; ``pushes`` holds every reported push's
        :class:`comcore.PushRecord` (failed ones included). ``posterior`` as
        :func:`comcore.estimate_active`'s, with the session's ``pose``.
        """
        used = [r.index for r in self._log.executed]
        return self._log.estimate(
            self._first, self._posterior, used, self.status, pose=self._pose
        )

    def com_in_camera(self) -> tuple[float, float]:
        """The CoM estimate where it is now, in the camera frame (pixels)."""
        com = self._posterior.mean()
        p = self._pose
        moved = apply_motion(com, p.theta, (p.tx, p.ty), self._first.centroid)
        return float(moved[0]), float(moved[1])
