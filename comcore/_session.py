"""`comcore.ActiveSession`: the active estimator as an ask/tell loop on an object that moves."""

from __future__ import annotations

import inspect

import numpy as np

from ._active_setup import DEFAULT_MODEL, active_options, build_estimate, prior_grid
from ._conventions import apply_motion, object_motion_from_camera
from ._errors import SessionError
from ._geometry import contacts
from ._mask import Mask
from ._planning import Candidates, push_force_lines
from ._posterior import GridPosterior
from ._session_log import SessionLog
from ._session_pose import (
    IDENTITY,
    actions_from_pose,
    is_miss,
    moved_mask,
    read_pose,
    relative,
    symmetric_branches,
)
from ._session_update import gyration_px, push_evidence, tracking_noise
from ._types import Action, Estimate, Motion
from ._validation import check_actions, check_mask, check_motions, check_rng

__all__ = ["ActiveSession"]

_OPTIONS = frozenset(inspect.signature(active_options).parameters) - {"mask", "model"}
#: How far (metres) an executed push's start is moved back along its line when it lies
#: just inside the object as the session sees it (see ActiveSession.observe).
EXECUTED_BACKOFF_M = 0.005


class ActiveSession:
    """Find the CoM by pushing, one push at a time, driven by the caller's loop.

    The ask/tell form of :func:`comcore.estimate_active` (same posterior,
    likelihood, push choice and stop rule; see there), for a robot that
    cannot reset the object and sees it through a camera::

        session = comcore.ActiveSession(first_mask, pusher_radius=0.004, rng=0)
        while not session.done:
            action = session.next_push()   # camera frame, on the object as it is now
            robot.execute(action)
            session.observe(camera_mask())  # or observe(motion=...), observe(failed=True)
        estimate = session.estimate()       # .com in the first mask's frame

    **Frames.** The posterior lives on the object, in the first mask's frame.
    The session tracks the object's :attr:`pose` relative to the first mask:
    from each observed mask, registered against the FIRST mask with
    :func:`comcore.measure_motion` (so tracking errors do not pile up), or
    from each motion the caller's tracker reports (camera frame, about the
    object's current centroid). Candidates are drawn once on the first mask
    and move with the object: :meth:`next_push` offers only pushes that, in
    the current pose, start and end in the image, start outside the object
    and hit it (checked on the last observed mask, or on the first mask moved
    to the pose). A push is never offered twice.

    **Pushes without evidence.** A push after which the object turned by
    less than 0.01 rad and moved by less than 1 mm
    (:data:`comcore._session_pose.MISS_ROTATION`, ``MISS_TRANSLATION_M``) is a
    miss: recorded, counted in the budget, no evidence. ``observe(failed=True)``
    (the robot could not execute it): not counted, no evidence. A mask whose
    registration is ``ambiguous`` (a disc: the rotation cannot be seen) gives
    the translation only.

    **Noise.** The likelihood's scales are in metres and radians
    (``pusher_error``, ``motion_noise``, ``theta_noise``,
    ``translation_error``: see :func:`comcore.estimate_active`); where the
    session registers masks itself, the registration's residual widens the
    tracking noise of that push.

    Parameters
    ----------
    mask : Mask
        The object as the camera sees it before the first push.
    model : HypothesisPredictor, sequence of them, or None, optional
        Motion model (see :func:`comcore.estimate_active`): by default
        ``comcore.LimitSurfaceModel(pusher_radius=pusher_radius)`` (the
        option ``pusher_radius``, metres, default 4 mm); ``None``: the Voting
        Theorem alone.
    candidates : array_like, shape (n, 4), optional
        Pushes in the first mask's frame; default ``comcore.sample_pushes``.
    rng : None, int or numpy.random.Generator, optional
        Seeds the default candidates (the only random choice).
    prior : array_like, shape (H, W), optional
        Prior weights of the CoM (see :func:`comcore.estimate_active`).
    **options
        The other options of :func:`comcore.estimate_active` (``max_pushes``,
        ``target_radius``, ``credible``, ``mu``, ``flip_prob``, ...).

    Attributes
    ----------
    done : bool
    status : str
        ``"waiting_push"`` (call :meth:`next_push`), ``"waiting_observation"``
        (call :meth:`observe`), or final: ``"ok"``, ``"budget"``,
        ``"exhausted"`` (no candidate left that can be pushed in this pose),
        ``"uninformative"``, or ``"inconsistent"`` (instead of any of them)
        when no hypothesis explains the motions well (:attr:`consistent`).
    pose : Motion
        The object's pose now relative to the first mask.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    The object turns 0.1 rad in the Voting Theorem's sense and stays put (no
    physics: the Voting Theorem alone, ``model=None``):

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> true_com = np.array([17.0, 20.0])
    >>> session = comcore.ActiveSession(mask, max_pushes=3, model=None, rng=0)
    >>> while not session.done:
    ...     action = session.next_push()
    ...     c = comcore.contacts(mask, action)
    ...     s = comcore.vt.rotation_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
    ...     session.observe(motion=comcore.Motion(0.1 * s, 0.0, 0.0))
    ...     session.reset_pose()  # the caller put the object back
    >>> session.status, len(session.actions)
    ('budget', 3)
    """

    def __init__(
        self, mask: Mask, *, model=DEFAULT_MODEL, candidates=None, rng=None, prior=None, **options
    ):
        self._first = check_mask(mask)
        unknown = sorted(set(options) - _OPTIONS)
        if unknown:
            raise TypeError(f"unknown option(s) {unknown}; ActiveSession takes {sorted(_OPTIONS)}")
        self._opts = active_options(self._first, model=model, **options)
        pixels, prior_w = prior_grid(self._first, prior)
        self._cands = Candidates(self._first, candidates, self._opts, check_rng(rng))
        self._post = GridPosterior(
            pixels,
            prior_w,
            self._opts.mus,
            max(len(self._opts.models), 1),
            self._opts.n_scales,
            self._opts.n_tempers,
        )
        self._gyration_px = gyration_px(self._first)
        self._pose = IDENTITY
        self._mask_now: Mask | None = self._first  # None: the first mask moved to the pose
        self._log = SessionLog(self._post, self._opts.credible)
        self._final: str | None = None
        self._pending: int | None = None
        self._handed_out = False
        self._planned = False

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
        quantile of its distribution under the likelihood).
        """
        return self._log.consistent

    def _plan(self):
        """Decide whether to stop, else choose the next push (lazily, once per state)."""
        if self._planned:
            return
        self._planned = True
        self._final, self._pending = None, None
        state = self._log.history[-1]
        state["expected_gain_bits"] = None
        small = state["credible_radius_px"] <= self._opts.target_px
        if small and self._log.n_evidence >= self._opts.min_pushes:
            self._final = "ok"
        elif len(self._log.executed) >= self._opts.max_pushes:
            self._final = "budget"
        else:
            offered = self._cands.offerable(self._pose, self._current_mask())
            index, gain = self._cands.choose(self._post, offered, self._opts)
            if index is None:
                self._final = "exhausted" if gain is None else "uninformative"
            else:
                self._pending = index
                state["expected_gain_bits"] = gain
        if self._final is not None and not self._log.consistent:
            self._final = "inconsistent"

    def _current_mask(self) -> Mask | None:
        if self._mask_now is not None:
            return self._mask_now
        return moved_mask(self._first, self._pose)

    @property
    def done(self) -> bool:
        """True once the session has stopped (see :attr:`status`)."""
        self._plan()
        return self._final is not None

    @property
    def status(self) -> str:
        """What the session waits for, or why it stopped."""
        self._plan()
        if self._final is not None:
            return self._final
        return "waiting_observation" if self._handed_out else "waiting_push"

    @property
    def pose(self) -> Motion:
        """The object's pose now, relative to the first mask (about its centroid)."""
        return self._pose

    @property
    def actions(self) -> np.ndarray:
        """Pushes executed (misses included), camera frame as handed out, shape (k, 4)."""
        return self._log.rows("camera_action", 4)

    @property
    def motions(self) -> np.ndarray:
        """Their motions, camera frame (about the centroid at the time), shape (k, 3)."""
        return self._log.rows("camera_motion", 3)

    @property
    def history(self) -> tuple[dict, ...]:
        """One dict per state (prior first): ``com``, ``entropy_bits``, ``credible_radius_px``..."""
        self._plan()
        return tuple(dict(h) for h in self._log.history)

    # -- ask / tell ---------------------------------------------------------------------

    def next_push(self) -> Action:
        """The next push, in the current camera frame, on the object as it is now.

        Calling it again before :meth:`observe` returns the same push.

        Raises
        ------
        SessionError
            If the session is done.
        """
        if self.done:
            raise SessionError(f"the session is done (status {self._final!r}): no push to offer")
        self._handed_out = True
        return Action(*self._cands.in_pose(self._pose, [self._pending])[0])

    def observe(
        self, mask: Mask | None = None, *, motion=None, failed: bool = False, executed=None
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
            planned; set ``pusher_error`` to how well you know this path, not
            how well the arm follows a command. Default: as planned.

        Raises
        ------
        SessionError
            If no push is waiting for its observation.
        TypeError, ValueError
            On invalid arguments (named); the session is then unchanged.
        """
        if self.done or not self._handed_out:
            what = f"the session is done (status {self._final!r})" if self.done else "no push"
            raise SessionError(f"observe() called but {what} is waiting: call next_push() first")
        if not isinstance(failed, (bool, np.bool_)):
            raise TypeError(f"failed must be a bool, got {type(failed).__name__}")
        given = [name for name, v in (("mask", mask), ("motion", motion)) if v is not None]
        if failed:
            given.append("failed")
        if len(given) != 1:
            raise TypeError(
                f"observe() takes exactly one of mask, motion or failed=True, got {given}"
            )
        index = self._pending
        done_as = None if executed is None else self._executed(executed, failed)
        record = {
            "index": index,
            "camera_action": self._cands.in_pose(self._pose, [index])[0],
            # an executed path that misses the object is kept as planned: a miss carries no
            # evidence, and a replay (estimate_posterior) needs pushes that hit the first mask
            "object_action": self._cands.actions[index]
            if done_as is None or done_as[1] is None
            else done_as[0],
            "pose_before": self._pose,
        }
        if failed:
            self._commit(record, "failed", self._pose, None, None)
            return
        reading = read_pose(self._first, self._pose, mask, motion)
        branches = symmetric_branches(reading, self._pose)
        if is_miss(relative(self._pose, branches[0].pose), self._first.resolution):
            self._record_reading(record, branches[0])
            self._commit(record, "miss", branches[0].pose, mask, None)
            return
        action, lines = self._cands.actions[index], self._cands.lines[index]
        if done_as is not None:
            action, lines = done_as
            if lines is None:
                raise ValueError(
                    f"executed {np.asarray(executed, float).ravel().tolist()} misses the "
                    "object as the session sees it, but the object moved: pass the path the "
                    "pusher took, in camera pixels"
                )
        # A symmetric outline (a hexagon) turned by more than half its symmetry angle looks
        # like a smaller turn the other way: of the rotations the masks allow, keep the one
        # the posterior explains best (its marginal likelihood), not merely the nearest.
        best = None
        for branch in branches:
            camera_motion = relative(self._pose, branch.pose)
            obj_motion = object_motion_from_camera(camera_motion, self._pose.theta)
            loglik, excess = push_evidence(
                self._post,
                self._opts,
                self._first,
                action,
                lines,
                obj_motion,
                rotation_observed=not branch.ambiguous,
                tracking=tracking_noise(self._opts.tracking, branch.residual_px, self._gyration_px),
            )
            evidence = self._post.predictive(loglik.full)
            if best is None or evidence > best[0]:
                best = (evidence, branch, obj_motion, loglik, excess)
        _, branch, obj_motion, loglik, excess = best
        self._record_reading(record, branch)
        record["object_motion"] = tuple(float(v) for v in obj_motion)
        self._commit(record, "evidence", branch.pose, mask, loglik, excess)

    def _executed(self, executed, failed: bool):
        """The executed push in the object's frame and its force lines (None: it misses)."""
        if failed:
            raise TypeError("observe(failed=True) takes no executed push: nothing was executed")
        acts = check_actions(executed, "executed", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"executed must be a single action (4 numbers), got {acts.shape[0]}")
        obj = actions_from_pose(acts, self._pose, self._first.centroid)
        con = contacts(self._first, obj)
        # A start just inside the outline as the session sees it (its pose is measured, to
        # a pixel or so): the pusher met the outline where its line enters, so the start is
        # moved back along the line, 1 mm at a time, at most EXECUTED_BACKOFF_M.
        step = np.asarray(Action(*obj[0]).direction) * (0.001 / self._first.resolution)
        for _ in range(round(EXECUTED_BACKOFF_M / 0.001)):
            if not con.starts_inside[0]:
                break
            obj[0, :2] -= step
            con = contacts(self._first, obj)
        if con.starts_inside[0]:
            raise ValueError(
                f"executed {acts[0].tolist()} starts inside the object as the session sees it"
            )
        if not con.hit[0]:
            return obj[0], None
        return obj[0], push_force_lines(con, obj, self._opts.mus)[0]

    def _record_reading(self, record, reading) -> None:
        record["camera_motion"] = tuple(relative(self._pose, reading.pose))
        record["residual_px"] = reading.residual_px
        record["ambiguous"] = reading.ambiguous
        record["symmetry"] = reading.symmetry

    def _commit(self, record, outcome, pose, mask, loglik, excess=None):
        record["outcome"] = outcome
        if outcome != "failed" and "object_motion" not in record:
            record["object_motion"] = tuple(
                float(v)
                for v in object_motion_from_camera(record["camera_motion"], self._pose.theta)
            )
        self._log.add(record, self._post, loglik, excess)
        self._cands.made(record["index"])
        if outcome != "failed":
            self._mask_now = mask  # None after a motion: the first mask moved to the new pose
            self._pose = pose
        self._handed_out = False
        self._planned = False

    def reset_pose(self, pose=None) -> None:
        """Tell the session the object was put back in the first pose (or moved to ``pose``).

        Raises
        ------
        SessionError
            If a push is waiting for its observation.
        """
        if self._handed_out:
            raise SessionError("reset_pose() while a push waits for observe()")
        new = IDENTITY if pose is None else Motion(*check_motions(pose, n=1, name="pose")[0])
        self._pose = new
        self._mask_now = self._first if new == IDENTITY else None
        self._planned = False

    # -- results ------------------------------------------------------------------------

    def estimate(self) -> Estimate:
        """The estimate so far; ``com`` in the first mask's frame.

        ``used`` indexes the candidates of the executed pushes (misses
        included), in order. ``extras`` as :func:`comcore.estimate_active`'s
        (``"actions"`` and ``"motions"`` in the first mask's frame, as the
        posterior used them), plus ``"camera_actions"``, ``"camera_motions"``,
        ``"outcomes"`` (``"evidence"`` / ``"miss"`` per executed push),
        ``"failed"`` (candidates reported as failed) and ``"pose"``.
        """
        return self._estimate(self.status)

    def _estimate(self, status: str) -> Estimate:
        extras = {
            **self._log.extras(),
            "camera_actions": self.actions,
            "camera_motions": self.motions,
            "pose": self._pose,
        }
        used = [r["index"] for r in self._log.executed]
        return build_estimate(
            self._first, self._post, self._opts.credible, used, self._log.history, status, extras
        )

    def com_in_camera(self) -> tuple[float, float]:
        """The CoM estimate where it is now, in the camera frame (pixels)."""
        com = self._post.mean()
        p = self._pose
        moved = apply_motion(com, p.theta, (p.tx, p.ty), self._first.centroid)
        return float(moved[0]), float(moved[1])


def _signature() -> inspect.Signature:
    """ActiveSession's signature with every option named (for introspection and typo checks)."""
    own = list(inspect.signature(ActiveSession.__init__).parameters.values())
    options = [
        p.replace(kind=inspect.Parameter.KEYWORD_ONLY)
        for name, p in inspect.signature(active_options).parameters.items()
        if name in _OPTIONS
    ]
    return inspect.Signature([*own[:-1], *options])


ActiveSession.__init__.__signature__ = _signature()  # type: ignore[attr-defined]
