"""`comcore.GoalSession`: push an object to a goal pose, learning its CoM on the way.

The ask/tell loop of :class:`comcore.ActiveSession` with another aim: each
push is chosen to bring the object to the goal (:mod:`comcore.goal._planner`),
and each push's motion is also evidence for the CoM posterior, scored by the
same likelihood (:func:`comcore.active._likelihood.push_evidence`) into the same grid
(:mod:`comcore.active._grid`) and records (:mod:`comcore.active._records`); the pose is
tracked as the active session tracks it (:mod:`comcore.camera._pose_tracking`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._mask import Mask
from .._status import Status
from .._types import Action, Estimate, Motion, PushRecord
from .._validation import check_count, check_mask, check_one_object, check_physical, check_rng
from ..active._choice import Candidates, PushChoice
from ..active._likelihood import Likelihood, PushMemo, gyration_px
from ..active._options import DEFAULT_CREDIBLE, DEFAULT_MODEL, group_or_default
from ..active._overlap import pusher_overlap
from ..active._path import check_frames
from ..active._reading import (
    PushContext,
    best_branch,
    branch_evidence,
    frame_path,
    path_of,
    push_record,
)
from ..active._records import PushLog, PushLoop
from ..active._session import ActiveSession, session_setup
from ..active._stop import StopRule
from ..camera._pose_tracking import (
    executed_in_object,
    is_miss,
    moved_mask,
    read_pose,
    relative,
    symmetric_branches,
)
from ..conventions import DEFAULT_PUSHER_RADIUS
from ..geometry._sampling import DEFAULT_SAMPLED_STANDOFF_M, sample_pushes
from ._costs import pose_cost, turn_outside
from ._planner import (
    COARSE_PARTICLES,
    Plan,
    PlanningContext,
    learning_safe,
    plan_push,
    reached,
)
from ._prior import prior_particles, touches_border
from ._translation import STANDOFF_M, planning_model
from ._types import (
    MAX_PLANNING_PARTICLES,
    PLANNING_PARTICLES,
    CoMHypotheses,
    Goal,
    MetricPose,
    _systematic,
    hypotheses_from,
)

__all__ = [
    "DEFAULT_GOAL_MAX_PUSHES",
    "DEFAULT_GOAL_TRAVEL_M",
    "DEFAULT_LEARNING_PUSHES",
    "GOAL_STATUSES",
    "GoalSession",
]

#: The session says ``"reached"`` when the pose it reads is within the goal's tolerances less
#: this share of the camera's reading error (:attr:`comcore.Likelihood.motion_noise`: 0.5
#: degrees and 0.5 mm by default), so that the true pose is within them.
READING_MARGIN = 0.5
#: ``GoalSession(max_pushes=...)``'s default: the push budget (an
#: :class:`comcore.ActiveSession`'s :class:`comcore.StopRule` allows 5).
DEFAULT_GOAL_MAX_PUSHES = 30
#: ``GoalSession(travel=...)``'s default: how far (metres) the pusher may travel after
#: contact in one push (an ActiveSession's candidates travel 3 cm).
DEFAULT_GOAL_TRAVEL_M = 0.05
#: ``GoalSession(learning_pushes=...)``'s default: the learning pushes in a row a session may
#: make where no push passes the planner's rules, before it says ``"stuck"``.
DEFAULT_LEARNING_PUSHES = 3
#: The seed the learning pushes' candidates are drawn with where ``rng`` is None.
LEARNING_SEED = 0
#: A learning push must be expected to teach more than this rule's ``min_information`` (an
#: :class:`comcore.ActiveSession`'s default, 1e-3 bits), as an active session's push must.
LEARNING_RULE = StopRule()
#: The learning pushes' candidates: an ActiveSession's, and each cut to these shares of its
#: travel after contact. Each cut teaches what the whole push does (the sense of the turn is
#: the same: the same force lines), so the longest safe one of the most informative is made.
LEARNING_LENGTHS = (0.5, 0.25)
#: Learning pushes safe under the planner's coarse particles are checked under all of its
#: particles, the most informative first: at most this many.
LEARNING_TRIES = 4
#: What :attr:`GoalSession.status` can say.
GOAL_STATUSES = (
    Status.WAITING_PUSH,
    Status.WAITING_OBSERVATION,
    Status.REACHED,
    Status.BUDGET,
    Status.STUCK,
    Status.LOST,
)


def unit_hints(goal: Goal, first: Mask) -> str:
    """What a goal outside the camera's view was likely meant as, the likelier reading first.

    Only for a goal in metres (``units="m"``). Each reading (the numbers as
    millimetres, ``/ 1000``, or as pixels, ``units="px"``) is ranked first by
    whether it puts the object in view, then by how near the distance it asks
    is to the object's size in the mask (its diameter about the centroid), on
    a log scale: goals are a few object sizes away, so 100 meant for a 5 cm
    object reads as 10 cm (millimetres) before 25 cm (pixels at 2.5 mm), and 8
    meant for it reads as 2 cm (pixels) before 8 mm.
    """
    if goal.units != "m":
        return ": pixels beyond the image?"
    h, w = first.shape
    cx, cy = first.centroid
    size = 2.0 * float(np.hypot(*(first.pixels - first.centroid).T).max()) + 1.0
    field = "displacement" if goal.displacement is not None else "position"
    given = goal.displacement if goal.displacement is not None else goal.position
    readings = []
    for label, scaled in (
        ("millimetres", dataclasses.replace(goal, **{field: tuple(v / 1000 for v in given)})),
        ("pixels", dataclasses.replace(goal, units="px")),
    ):
        tx, ty = scaled.target_px(first)
        in_view = 0 <= cx + tx <= w - 1 and 0 <= cy + ty <= h - 1
        fit = abs(np.log((np.hypot(tx, ty) + 1.0) / size))
        if label == "millimetres":
            numbers = ", ".join(f"{v / 1000:g}" for v in given)
            hint = f"millimetres, {field}=({numbers}) in metres"
        else:
            hint = "pixels, units='px'"
        readings.append((not in_view, fit, hint))
    readings.sort()
    first_hint, second_hint = (hint for *_, hint in readings)
    return f": did you mean {first_hint}? Or {second_hint}?"


def _goal_budget(max_pushes, travel, resolution: float) -> tuple[float, int]:
    """The push length (pixels) and the budget of a goal session, each checked and named."""
    max_pushes = check_count(max_pushes, "max_pushes", 1)
    travel = check_physical(travel, "travel", "push_length")
    travel_px = travel / resolution
    if travel_px < 2:
        raise ValueError(f"travel {travel} m is under two pixels of the mask")
    return travel_px, max_pushes


def _push_directions(push_directions) -> np.ndarray | None:
    """The camera directions (radians) the robot may push along, or None for any."""
    if push_directions is None:
        return None
    allowed = np.atleast_1d(np.asarray(push_directions, dtype=float))
    if allowed.ndim != 1 or len(allowed) == 0 or not np.isfinite(allowed).all():
        raise ValueError(
            f"push_directions must be finite angles (radians), got {push_directions!r}"
        )
    return allowed


def _named_prior_particles(first, prior, n: int, mus):
    """:func:`prior_particles`, its refusals naming ``prior`` (the argument the user passed).

    The hypotheses' validators name the argument of :func:`hypotheses_from`, ``posterior``.
    """
    try:
        return prior_particles(first, prior, n, mus)
    except ValueError as e:
        message = str(e)
        if not message.startswith("posterior"):
            raise
        raise ValueError("prior" + message[len("posterior") :]) from None


class GoalSession(PushLoop):
    """Push an object to a goal pose, one push at a time, driven by the caller's loop.

    The loop of :class:`ActiveSession` with another aim: each push is the one of least expected
    remaining pose error, predicted by the motion model over particles of the CoM posterior, which
    each push also updates (``learn``); where no push passes the planner's rules, a *learning push*
    narrows it first (:attr:`push_kinds`). The statuses, the poses (:attr:`pose` in pixels,
    :attr:`pose_m` in metres) and the planner: docs/tutorials/goal.md.

    Parameters
    ----------
    mask : Mask
        The object as the camera sees it before the first push.
    goal : Goal
        The pose wanted, relative to ``mask`` (:class:`comcore.Goal`).
    model, likelihood : optional
        The likelihood's motion model(s) and scoring, as for :class:`ActiveSession`.
    pusher_radius : float, optional
        Radius of the round pusher in metres (default 4 mm).
    prior : None, Estimate, ActiveSession or CoM hypotheses, optional
        What is known of the CoM: None (uniform), an active estimate or :class:`ActiveSession` of
        ``mask`` (starting at its pose), or CoM pixels ``(k, 2)`` / ``(coms, weights)``.
    rng : None, int or numpy.random.Generator, optional
        Draws the learning pushes' candidates (None: :data:`LEARNING_SEED`).
    max_pushes : int, optional
        The push budget (at least 1; default :data:`DEFAULT_GOAL_MAX_PUSHES`).
    travel : float, optional
        How far the pusher may travel after contact, metres (default 5 cm).
    learn : bool, optional
        Update the posterior with every push (default True); False plans on the prior, fixed.
    planner_model : comcore.Predictor, optional
        The planner's model (default :class:`comcore.LimitSurfaceModel` with ``pusher_radius``).
    n_particles : int, optional
        Posterior particles a push is planned over (default 32, at most 10,000).
    push_directions : array_like, optional
        The only camera directions (radians; pi/2: +y down the screen) the robot may push along.
    learning_pushes : int, optional
        The most learning pushes in a row (default 3; 0: ``"stuck"`` at once).

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (named); e.g. a goal outside the camera's view.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 40))
    >>> goal = comcore.Goal(displacement=(0.03, 0.0))
    >>> session = comcore.GoalSession(mask, goal=goal, travel=0.02, model=None, rng=0)
    >>> session.status, session.next_push().ex > session.next_push().sx
    ('waiting_push', True)
    >>> session.observe(motion=(0.0, 12.0, 0.0))  # 3 cm to the right
    >>> session.status, session.done
    ('reached', True)
    """

    def __init__(
        self,
        mask: Mask,
        goal: Goal,
        *,
        model=DEFAULT_MODEL,
        pusher_radius: float = DEFAULT_PUSHER_RADIUS,
        prior=None,
        rng=None,
        likelihood=None,
        max_pushes: int = DEFAULT_GOAL_MAX_PUSHES,
        travel: float = DEFAULT_GOAL_TRAVEL_M,
        learn: bool = True,
        planner_model=None,
        n_particles: int = PLANNING_PARTICLES,
        push_directions=None,
        learning_pushes: int = DEFAULT_LEARNING_PUSHES,
    ):
        self._first = check_one_object(mask)
        if not isinstance(goal, Goal):
            raise TypeError(f"goal must be a comcore.Goal, got {type(goal).__name__}")
        if not isinstance(learn, (bool, np.bool_)):
            raise TypeError(f"learn must be a bool, got {type(learn).__name__}")
        self._goal, self._learn = goal, bool(learn)
        budget = _goal_budget(max_pushes, travel, self._first.resolution)
        self._max_travel_px, self._max_pushes = budget
        self._n_particles = check_count(n_particles, "n_particles", 1)
        if self._n_particles > MAX_PLANNING_PARTICLES:
            raise ValueError(
                f"n_particles must be at most {MAX_PLANNING_PARTICLES}, got {n_particles} (the "
                f"default is {PLANNING_PARTICLES})"
            )
        self._allowed = _push_directions(push_directions)
        self._rng = check_rng(LEARNING_SEED if rng is None else rng)
        self._max_learning = check_count(learning_pushes, "learning_pushes", 0)
        self._radius = check_physical(
            pusher_radius, "pusher_radius", "pusher_radius", allow_zero=True
        )
        likelihood = group_or_default(likelihood, Likelihood, "likelihood")
        # the pose is read by the camera: "reached" keeps a margin of its reading error
        self._margin = tuple(READING_MARGIN * v for v in likelihood.motion_noise)
        self._likelihood = likelihood  # its model-error scales: the planner's caution too
        self._scoring, credible = session_setup(
            self._first, model, pusher_radius, DEFAULT_CREDIBLE, likelihood
        )
        self._planner = planning_model(self._radius) if planner_model is None else planner_model
        self._target = goal.target_px(self._first)
        self._check_goal_in_view()
        start = Motion.identity()
        if isinstance(prior, ActiveSession):  # go on from where its pushes left the object
            start = prior.pose
            if prior.estimate().region.shape != self._first.shape:
                raise ValueError("prior's ActiveSession runs on a mask of another shape")
        pixels, weights, mu_weights, fixed = _named_prior_particles(
            self._first, prior, self._n_particles, self._scoring.mus
        )
        self._posterior = self._scoring.posterior(pixels, weights, mu_weights)
        self._fixed = fixed if not self._learn else None  # fixed planning particles
        self._reach = float(np.hypot(*(self._first.pixels - self._first.centroid).T).max()) + 1
        self._gyration = gyration_px(self._first)
        self._pose = start
        self._band = goal.turn_band(start.theta)  # what max_turn bounds the turn outside of
        self._log = PushLog(self._posterior, credible, self._scoring.systematic_px)
        self._n_pushes, self._final, self._plan, self._handed_out = 0, None, None, False
        self._min_travel = 0.0  # after a push that did not move the object: a longer one
        self._kinds: list[str] = []  # why each recorded push was made
        self._learning: Candidates | None = None  # the learning pushes' candidates, when needed
        self._learning_index: int | None = None  # the candidate the planned learning push is
        self._learning_run = 0  # learning pushes in a row
        self._update()

    def _check_goal_in_view(self) -> None:
        if self._target is None:
            return
        h, w = self._first.shape
        x = self._first.centroid[0] + self._target[0]
        y = self._first.centroid[1] + self._target[1]
        if not (0 <= x <= w - 1 and 0 <= y <= h - 1):
            raise ValueError(
                f"goal puts the object's centroid at ({x:.0f}, {y:.0f}) px, outside the camera's "
                f"{w} x {h} px view" + unit_hints(self._goal, self._first)
            )

    # -- state ---------------------------------------------------------------------------

    def _update(self) -> None:
        """Check the goal and the budget; if it goes on, plan the next push."""
        self._plan = None
        if reached(self._goal, self._target, self._first.resolution, self._pose, self._margin):
            self._final = Status.REACHED
            return
        if self._n_pushes >= self._max_pushes:
            self._final = Status.BUDGET
            return
        hyps = self._fixed or hypotheses_from(self._posterior, self._first, self._n_particles)
        turn = None
        if self._goal.max_turn is not None:  # once past the bound, no push that goes further
            now = float(turn_outside(self._pose.theta, self._band))
            turn = (*self._band, max(self._goal.max_turn, now))
        context = PlanningContext(
            self._first,
            self._goal,
            self._target,
            self._planner,
            self._max_travel_px,
            self._radius,
            reach_px=self._reach,
            allowed=self._allowed,
            scales=self._likelihood,
            turn=turn,
        )
        self._plan = plan_push(context, self._pose, hyps, self._min_travel)
        self._learning_index = None
        if self._plan is None and self._learn and self._learning_run < self._max_learning:
            self._plan = self._learning_plan(hyps, context)
        if self._plan is None:
            self._final = Status.STUCK

    def _learning_candidates(self) -> Candidates:
        """An ActiveSession's candidates (``travel`` long), and each cut shorter."""
        res = self._first.resolution
        choice = PushChoice(travel=self._max_travel_px * res)
        full = sample_pushes(
            self._first, choice.n_candidates, cone=choice.cone, travel=choice.travel,
            rng=self._rng,
        )
        start, vector = full[:, :2], full[:, 2:] - full[:, :2]
        unit = vector / np.hypot(*vector.T)[:, None]
        standoff = DEFAULT_SAMPLED_STANDOFF_M / res  # sample_pushes' start before the contact
        cut = [
            np.hstack([start, start + unit * (standoff + f * self._max_travel_px)])
            for f in LEARNING_LENGTHS
        ]
        return Candidates(
            self._first, np.vstack([full, *cut]), choice, self._scoring.mus, self._rng,
            pusher_radius=self._scoring.pusher_radius,
        )

    def _learning_plan(self, hyps, context: PlanningContext) -> Plan | None:
        """The most informative push safe for the goal, as an ActiveSession chooses (or None)."""
        if self._learning is None:
            self._learning = self._learning_candidates()
        cands = self._learning
        offered = cands.offerable(self._pose, moved_mask(self._first, self._pose))
        index = np.flatnonzero(offered)
        camera = cands.in_pose(self._pose, index)
        if self._allowed is not None and len(index):  # the robot's directions only
            angle = np.arctan2(camera[:, 3] - camera[:, 1], camera[:, 2] - camera[:, 0])
            off = np.angle(np.exp(1j * (angle[:, None] - self._allowed[None, :])))
            keep = np.abs(off).min(axis=1) <= np.radians(1.0)
            index, camera = index[keep], camera[keep]
        # safe under a few particles first (as the planner's coarse pass), then the most
        # informative of those checked under all of them, the next where it is not safe
        share_index, share = _systematic(hyps.weights, COARSE_PARTICLES)
        coarse = CoMHypotheses(hyps.coms[share_index], hyps.mus[share_index], share)
        safe, _, _ = learning_safe(context, self._pose, coarse, cands.actions[index])
        index, camera = index[safe], camera[safe]
        for _ in range(LEARNING_TRIES):
            offered[:] = False
            offered[index] = True
            best, gain = cands.choose(self._posterior, offered, self._scoring, "sense")
            # as an ActiveSession stops "uninformative": a push that teaches nothing is not made
            if best is None or not gain > LEARNING_RULE.min_information:
                return None
            ok, cost, means = learning_safe(context, self._pose, hyps, cands.actions[[best]])
            if ok[0]:
                break
            keep = index != best
            index, camera = index[keep], camera[keep]
        else:
            return None
        at = int(np.flatnonzero(index == best)[0])
        self._learning_index = best
        cost_now = float(pose_cost(
            self._goal, self._target, self._first.resolution, *self._pose
        ))
        return Plan(
            cands.actions[best].copy(),
            Action(*camera[at]),
            float(cost[0]),
            cost_now,
            Motion(*(float(v[0]) for v in means)),
            "learn",
        )

    @property
    def goal(self) -> Goal:
        """The goal."""
        return self._goal

    @property
    def pose_m(self) -> MetricPose:
        """:attr:`pose` with its translation in metres: the first mask's frame, +y down the screen.

        ``theta`` (radians, counter-clockwise on screen) is the turn since the
        first mask; ``(tx, ty)`` how far its area centroid has moved, in
        metres (``resolution *`` :attr:`pose`'s pixels): the units of a
        :class:`Goal`'s ``displacement``, which it is compared with directly
        (a ``position`` is ``first.centroid_m`` plus it).
        """
        res = self._first.resolution
        return MetricPose(self._pose.theta, self._pose.tx * res, self._pose.ty * res)

    @property
    def push_kinds(self) -> tuple[str, ...]:
        """Why each push in :attr:`pushes` was made, in order: ``"goal"``, ``"probe"``, ``"learn"``.

        ``"goal"``: expected to bring the object closer; ``"probe"``: no push
        was, and this one had a fair chance to (the planner's probe);
        ``"learn"``: not even that, and this was the most informative push
        safe for the goal (see the class's *Learning pushes*).
        """
        return tuple(self._kinds)

    @property
    def next_push_kind(self) -> str | None:
        """Why the planned push (:meth:`next_push`) is made, as :attr:`push_kinds` (None: done)."""
        return None if self._plan is None else self._plan.kind

    @property
    def expected_cost(self) -> float | None:
        """The planned push's expected squared pose error, in tolerances (None: none planned)."""
        return None if self._plan is None else self._plan.expected_cost

    def estimate(self) -> Estimate:
        """The CoM posterior now (as :meth:`ActiveSession.estimate`); ``com`` in the first mask."""
        used = list(range(len(self._log.executed)))
        return self._log.estimate(self._first, self._posterior, used, self.status, pose=self._pose)

    # -- ask / tell ---------------------------------------------------------------------

    def _planned_push(self) -> Action:
        return self._plan.camera_action

    def observe(
        self, mask: Mask | None = None, *, motion=None, out_of_view: bool = False, frames=None
    ):
        """Report what the push from :meth:`next_push` did: exactly one of the three.

        Parameters
        ----------
        mask : Mask, optional
            The camera's mask after the push. One that touches the image border
            means the object left the view: status ``"lost"``.
        motion : Motion or (theta, tx, ty), optional
            The push's motion, camera frame, about the object's centroid before it.
        out_of_view : bool, optional
            True: the camera lost the object (status ``"lost"``).
        frames : sequence of PushFrame, optional
            What the camera saw during the push, as
            :meth:`comcore.ActiveSession.observe` takes them: while the session
            learns the CoM, the object's path along the push is scored with its
            end pose (:mod:`comcore.active._path`).

        Raises
        ------
        SessionError
            If no push is waiting for its observation.
        TypeError, ValueError
            On invalid arguments (named); the session is then unchanged.
        """
        self._check_waiting()
        if not isinstance(out_of_view, (bool, np.bool_)):
            raise TypeError(f"out_of_view must be a bool, got {type(out_of_view).__name__}")
        given = [k for k, v in (("mask", mask), ("motion", motion)) if v is not None]
        given += ["out_of_view"] if out_of_view else []
        if len(given) != 1:
            raise TypeError(
                f"observe() takes exactly one of mask, motion or out_of_view=True, got {given}"
            )
        if frames is not None:
            frames = check_frames(frames)
            if out_of_view:
                raise TypeError("observe(out_of_view=True) takes no frames")
        if mask is not None:
            mask = check_mask(mask)
            if mask.shape != self._first.shape or mask.resolution != self._first.resolution:
                raise ValueError(
                    f"mask must have the first mask's shape {self._first.shape} and resolution "
                    f"{self._first.resolution:g} m/px, got {mask.shape} at {mask.resolution:g}"
                )
        if out_of_view or (mask is not None and touches_border(mask)):
            self._n_pushes += 1
            self._handed_out, self._plan, self._final = False, None, Status.LOST
            return
        record, evidence, pose = self._reading(mask, motion, frames)
        overlap = pusher_overlap(self._first, self._scoring, record, self._gyration)
        self._log.add(record, self._posterior, *evidence, overlap=overlap)
        self._n_pushes += 1
        self._kinds.append(self._plan.kind)
        if self._plan.kind == "learn":  # not offered again (a miss too), as an ActiveSession's
            self._learning.made(self._learning_index)
            self._learning_run, self._min_travel = self._learning_run + 1, 0.0
        elif record.outcome == "miss":  # the same push again would not move it either
            self._learning_run = 0
            travel = np.hypot(*np.subtract(record.action.end, record.action.start))
            self._min_travel = 2 * (travel - STANDOFF_M / self._first.resolution)
        else:
            self._learning_run, self._min_travel = 0, 0.0
        self._pose, self._handed_out = pose, False
        self._update()

    def _reading(self, mask, motion, frames=None):
        """The push's record, its evidence ``(loglik, excess)`` or ``()``, and the new pose."""
        plan = self._plan
        reading = read_pose(self._first, self._pose, mask, motion)  # validates
        base = {
            "index": len(self._log.records),
            "planned": plan.action,
            "camera_action": plan.camera_action,
            "pose_before": self._pose,
        }
        # a symmetric outline's rotation is read to a symmetry angle: the reading nearest the
        # planned push's predicted rotation first (with learning, the best explained is kept)
        branches = symmetric_branches(reading, self._pose)
        branches.sort(key=lambda r: abs(r.pose.theta - plan.expected_pose.theta))
        _, lines = executed_in_object(
            self._first, Motion.identity(), plan.action, self._scoring.mus,
            self._scoring.pusher_radius,
        )
        moved = not is_miss(relative(self._pose, branches[0].pose), self._first.resolution)
        if not moved or lines is None or not self._learn:
            outcome = "evidence" if moved else "miss"
            return self._record(base, branches[0], outcome), (), branches[0].pose
        ctx = PushContext(self._first, self._pose, self._posterior, self._scoring, self._gyration)
        memo = PushMemo()  # the model's predictions for this push, for each reading of it
        branch, loglik, excess = best_branch(ctx, branches, plan.action, lines, memo)
        points, dropped = (), ()
        if frames:
            path = frame_path(ctx, plan.action, frames, branch)
            points, dropped = path.points, path.dropped
            if points and not branch.ambiguous:
                scored = path_of(plan.action, path)
                loglik, excess = branch_evidence(ctx, branch, plan.action, lines, scored, memo=memo)
        record = self._record(base, branch, "evidence", points, dropped)
        return record, (loglik, excess), branch.pose

    def _record(self, base: dict, reading, outcome: str, path=(), dropped=()) -> PushRecord:
        return push_record(
            base, self._pose, base["planned"], reading, outcome, path=path, dropped=dropped
        )
