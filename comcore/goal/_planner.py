"""The goal planner: one push, chosen by its predicted outcome over the CoM posterior.

A lookahead of two pushes; docs/tutorials/goal.md explains it with examples.

**Candidates**: pushes along :data:`N_DIRECTIONS` camera directions and the direction to the
goal (fanned by :data:`GOAL_FAN`), at offsets across the object (evenly spaced, and at the
hypotheses' mean CoM and +-1 standard deviation), for lengths of :data:`LENGTH_FRACTIONS` of
the allowed travel (at least 2 px) and :data:`LEFT_FRACTIONS` of the distance left. Pushes
that would start or end outside the image, carry the object's bounding disc out of it (mean
prediction), or that most particles say would not move the object (a miss, as
:func:`comcore.camera._pose_tracking.is_miss` reads one) are not offered; after a miss the
session asks for twice its travel at least.

**Cost**: the motion model predicts every candidate for every (CoM, friction) particle
(:func:`comcore.goal._translation.predict_motions`), and each candidate is scored by the
expected remaining pose error over the particles (:mod:`comcore.goal._costs`)::

    cost = (position error / position tolerance)^2
         + (orientation error / orientation tolerance)^2
         + the motion model's own error variance, in the same units

each term only where the goal sets it. An expected square is the squared mean plus the
variance, so a push whose outcome spreads under the posterior loses to one that surely does
not; the model's own error (:func:`comcore.goal._costs.model_variance`) grows with the push's
length and its line's distance from the CoM, so near a tight tolerance shorter or more
predictable pushes win.

**Two steps**: the best :data:`LOOKAHEAD` pushes and the best of each length are scored again
by the least expected cost of one more push (:func:`comcore.goal._costs.follow_ups`) from
where each coarse particle says the push leaves the object (half with the mixture's
prediction, half with the particle's own); a push's value is the least of its own cost and
that. The push of least value is chosen if it cuts the cost by :data:`MIN_GAIN`. Else a
**probe**: the push of least expected cost among those at least :data:`PROBE_LENGTH` of the
travel long that bring the object closer under at least :data:`PROBE_CHANCE` of the
posterior's mass. Else none: a learning :class:`comcore.GoalSession` makes a **learning push**
(the most informative of an :class:`comcore.ActiveSession`'s candidates among those
:func:`learning_safe` keeps) and plans again, or says ``"stuck"``.

**Speed**: every candidate is first scored over :data:`COARSE_PARTICLES` particles, and the
best :data:`KEPT` and the best of each length again over all of them; the follow-ups are pushes
along directions of the object's own frame, whose predictions serve every pose (with
``push_directions``, those directions as the object lies now). A step's time is measured by
``benchmarks/accuracy/goal_bench.py --timing``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._types import Action, Motion
from ..camera._pose_tracking import MISS_ROTATION, MISS_TRANSLATION_M, camera_from_object
from ._costs import (
    FOLLOW_DIRECTIONS,
    N_OFFSETS,
    PlanningContext,
    follow_ups,
    model_variance,
    pose_cost,
    reached,
    spread_picks,
    turn_outside,
)
from ._translation import (
    STANDOFF_M,
    _cross_offsets,
    camera_motions,
    line_pushes,
    predict_motions,
)
from ._types import CoMHypotheses, Goal, _systematic

__all__ = [
    "LEARNING_SLACK",
    "MIN_GAIN",
    "N_DIRECTIONS",
    "Plan",
    "PlanningContext",
    "learning_safe",
    "plan_push",
    "pose_cost",
    "reached",
]

#: Camera directions tried at every step (evenly spaced), besides the goal's direction.
N_DIRECTIONS = 8
#: Directions about the goal's (radians): an object on a slanted edge moves at an angle to
#: the push.
GOAL_FAN = np.radians([-30.0, 0.0, 30.0])
#: Fractions of the distance left to the goal tried as lengths (the object often moves
#: less than the pusher: it slides along the contact).
LEFT_FRACTIONS = (0.5, 1.0, 1.5)
#: Fractions of the allowed travel tried (the distance left to the goal is added).
LENGTH_FRACTIONS = (1.0, 0.5, 0.25, 0.1, 0.04)
#: Particles of the first, coarse pass over every candidate, and the candidates it keeps
#: for the full pass over all particles.
COARSE_PARTICLES, KEPT = 6, 12
#: A push is only worth making if it is expected to cut the cost by this share ...
MIN_GAIN = 0.02
#: ... or, where none is, if the posterior gives it at least this chance of bringing the
#: object closer (a probe; it is evidence too).
PROBE_CHANCE = 0.25
#: A probe travels at least this share of the allowed travel after contact (a shorter one
#: teaches little, and the model's small motions are its least accurate).
PROBE_LENGTH = 0.1
#: Two-step lookahead: the best pushes of the full pass whose follow-up is sought, and the
#: weight of the follow-up's expected cost (1: trusted as the push's own).
LOOKAHEAD, LOOKAHEAD_WEIGHT = 4, 1.0
#: Where no push passes the rule above, :class:`comcore.GoalSession` may make a *learning*
#: push (the most informative, as :class:`comcore.ActiveSession` chooses it) that leaves the
#: object, on average over the particles, at most this many tolerances farther from the goal
#: than it is: its position tolerance where the goal sets a position (1 cm by default), else
#: its orientation tolerance (:func:`learning_safe`).
LEARNING_SLACK = 1.0


#: Why a push was made (:attr:`comcore.GoalSession.push_kinds`): ``"goal"``, expected to bring
#: the object closer; ``"probe"``, a fair chance to (the planner's probe); ``"learn"``, none
#: passes either rule and the push is the most informative one that is safe for the goal.
PUSH_KINDS = ("goal", "probe", "learn")


class Plan(NamedTuple):
    """The push the planner chose and what it expects (internal)."""

    action: np.ndarray  # (4,) first mask's frame
    camera_action: Action
    expected_cost: float
    cost_now: float
    expected_pose: Motion  # the particles' mean pose after the push
    kind: str = "goal"  # one of PUSH_KINDS


def _candidates(context: PlanningContext, pose: Motion, hyps: CoMHypotheses, goal_angle, left_px):
    """The candidate pushes from ``pose`` (first mask's frame) and their direction, offset, length.

    ``goal_angle`` the camera direction to the goal (None: none), ``left_px``
    the distance left to it (None: free).
    """
    first, max_travel_px = context.first, context.max_travel_px
    if context.allowed is not None:
        directions = np.asarray(context.allowed, float)
    else:
        directions = np.linspace(0, 2 * np.pi, N_DIRECTIONS, endpoint=False)
        if goal_angle is not None:
            directions = np.append(directions, goal_angle + GOAL_FAN)
    offsets = np.stack(
        [_cross_offsets(first, a + pose.theta, hyps, N_OFFSETS, halves=False) for a in directions]
    )
    lengths = [f * max_travel_px for f in LENGTH_FRACTIONS]
    if left_px is not None:
        lengths += [f * left_px for f in LEFT_FRACTIONS if f * left_px < max_travel_px]
    lengths = np.unique(np.round([v for v in lengths if v >= 2.0], 6))
    return line_pushes(first, pose, directions, offsets, lengths, context.pusher_radius)


def _expected(context: PlanningContext, pose: Motion, hyps: CoMHypotheses, actions):
    """Expected cost of each candidate (inf: out of view, or past the turn bound), poses."""
    first, goal, target_px = context.first, context.goal, context.target_px
    reach_px = context.reach_px
    raw = predict_motions(context.model, first, actions, hyps)
    motions = camera_motions(raw, pose)  # (n_h, a, 3)
    theta = pose.theta + motions[..., 0]
    tx, ty = pose.tx + motions[..., 1], pose.ty + motions[..., 2]
    weights = hyps.weights[:, None]
    each = pose_cost(goal, target_px, first.resolution, theta, tx, ty)
    each = each + model_variance(goal, first, actions, hyps.coms, raw, context.scales)
    cost = (weights * each).sum(axis=0)
    h, w = first.shape
    cx = first.centroid[0] + (weights * tx).sum(axis=0)
    cy = first.centroid[1] + (weights * ty).sum(axis=0)
    keeps_view = (cx - reach_px > 0) & (cx + reach_px < w - 1)
    keeps_view &= (cy - reach_px > 0) & (cy + reach_px < h - 1)
    # a push the model says moves the object less than the camera can tell is a miss
    moves = np.hypot(motions[..., 1], motions[..., 2]) * first.resolution >= MISS_TRANSLATION_M
    moves |= np.abs(motions[..., 0]) >= MISS_ROTATION
    keeps_view &= (weights * moves).sum(axis=0) >= 0.5
    if context.turn is not None:  # the goal's max_turn: the mean predicted turn outside the band
        low, high, limit = context.turn
        keeps_view &= (weights * turn_outside(theta, (low, high))).sum(axis=0) <= limit + 1e-9
    return np.where(keeps_view, cost, np.inf), (theta, tx, ty, each)


def _coarse(context: PlanningContext, pose: Motion, hyps: CoMHypotheses, least: float):
    """Every candidate from ``pose`` in view, and its expected cost over ``hyps`` (or None).

    ``least``: the least travel after contact (pixels) a candidate may have.
    """
    first, target_px = context.first, context.target_px
    goal_angle = left = None
    if target_px is not None:
        dx, dy = target_px[0] - pose.tx, target_px[1] - pose.ty
        left = math.hypot(dx, dy)
        goal_angle = math.atan2(dy, dx) if left > 0.5 else None
    actions, _ = _candidates(context, pose, hyps, goal_angle, left)
    if len(actions) == 0:
        return None
    cam_actions = camera_from_object(actions, pose, first.centroid)
    h, w = first.shape
    x, y = cam_actions[:, 0::2], cam_actions[:, 1::2]
    in_view = ((x >= 0) & (x <= w - 1) & (y >= 0) & (y <= h - 1)).all(axis=1)
    travel = np.hypot(*(actions[:, 2:] - actions[:, :2]).T) - STANDOFF_M / first.resolution
    in_view &= travel >= least - 1e-6
    actions, cam_actions = actions[in_view], cam_actions[in_view]
    if len(actions) == 0:
        return None
    cost, _ = _expected(context, pose, hyps, actions)
    return actions, cam_actions, cost


def plan_push(
    context: PlanningContext, pose: Motion, hyps: CoMHypotheses, min_travel_px: float = 0.0
) -> Plan | None:
    """The push of least expected remaining pose error, or None when none gets closer.

    ``context`` holds what the step is planned against (the first mask, the
    goal, the model, the travel, the view, the allowed directions, the
    model-error scales and the turn bound: :class:`PlanningContext`); ``pose``
    the object's pose now; ``hyps`` the (CoM, friction) particles;
    ``min_travel_px`` the least travel after contact (the session raises it
    after a push that did not move the object).
    """
    first, goal, target_px = context.first, context.goal, context.target_px
    cost_now = float(pose_cost(goal, target_px, first.resolution, pose.theta, pose.tx, pose.ty))
    # a coarse pass over every candidate with a few particles, then the best few again
    index, share = _systematic(hyps.weights, COARSE_PARTICLES)
    coarse = CoMHypotheses(hyps.coms[index], hyps.mus[index], share)
    found = _coarse(context, pose, coarse, min_travel_px)
    if found is None:
        return None
    actions, cam_actions, cost = found
    keep = spread_picks(cost, np.hypot(*(actions[:, 2:] - actions[:, :2]).T), KEPT)
    if len(keep) == 0:
        return None
    actions, cam_actions = actions[keep], cam_actions[keep]
    cost, (theta, tx, ty, each) = _expected(context, pose, hyps, actions)
    weights = hyps.weights[:, None]
    means = [(weights * v).sum(axis=0) for v in (theta, tx, ty)]
    after = tuple(v[index] for v in (theta, tx, ty))  # where each coarse particle leaves it
    value = _closed_loop(context, pose, coarse, actions, cost, after)
    best, kind = int(np.argmin(value)), "goal"
    if not np.isfinite(value[best]) or value[best] > cost_now * (1.0 - MIN_GAIN):
        # a probe: no push is expected to help on average (a wide posterior), but one the
        # posterior gives a fair chance to help is made (and teaches it)
        likely = (weights * (each < cost_now)).sum(axis=0) >= PROBE_CHANCE
        travel = np.hypot(*(actions[:, 2:] - actions[:, :2]).T) - STANDOFF_M / first.resolution
        likely &= travel >= PROBE_LENGTH * context.max_travel_px - 1e-6
        if not (likely & np.isfinite(cost)).any():
            return None
        best, kind = int(np.argmin(np.where(likely, cost, np.inf))), "probe"
    return Plan(
        actions[best].copy(),
        Action(*cam_actions[best]),
        float(cost[best]),
        cost_now,
        Motion(*(float(v[best]) for v in means)),
        kind,
    )


def _closed_loop(context: PlanningContext, pose: Motion, coarse, actions, cost, after):
    """Each push's value: the least of its cost and what its best follow-up leads to.

    Two steps: the best :data:`LOOKAHEAD` pushes and the best push of each
    length (a long push a wide posterior spreads may still lead closer than a
    creep) are each followed by the best push from where each of the
    ``coarse`` particles says it leaves the object (``after``: ``(theta, tx,
    ty)``, each (particles, pushes)); the expected cost after that follow-up,
    over the particles, is the push's closed-loop value.
    """
    value = cost.copy()
    travel = np.hypot(*(actions[:, 2:] - actions[:, :2]).T)
    order = spread_picks(cost, travel, LOOKAHEAD) if LOOKAHEAD else []
    if not len(order):
        return value
    n = len(coarse.weights)
    poses = tuple(v[:, order].ravel() for v in after)
    owner = np.repeat(np.arange(n), len(order))
    if context.allowed is None:
        directions = np.linspace(0, 2 * np.pi, FOLLOW_DIRECTIONS, endpoint=False)
    else:  # the robot's directions, in the object's frame as it is now
        directions = np.asarray(context.allowed, float) + pose.theta
    follow = follow_ups(context, poses, coarse, directions, owner).reshape(n, len(order))
    closed = coarse.weights @ follow
    value[order] = np.minimum(cost[order], LOOKAHEAD_WEIGHT * closed)
    return value


def _error_in_tolerances(goal: Goal, target_px, resolution: float, theta, tx, ty):
    """How far poses are from the goal in tolerances: the position's, else the orientation's."""
    if target_px is not None:
        dist_m = np.hypot(tx - target_px[0], ty - target_px[1]) * resolution
        return dist_m / goal.position_tolerance
    return np.abs(theta - goal.orientation) / goal.orientation_tolerance


def learning_safe(context: PlanningContext, pose: Motion, hyps: CoMHypotheses, actions):
    """Which of ``actions`` (first mask's frame) are safe to make to learn, and what each expects.

    Safe: the push keeps the object's bounding disc in view and moves it
    (under at least half the particles' mass), keeps within the goal's
    ``max_turn`` (the context's ``turn``, as :func:`plan_push`), and leaves the
    object on average over the particles at most :data:`LEARNING_SLACK`
    tolerances farther from the goal than it is now (the position where the
    goal sets one, else the orientation). Returns ``(safe, cost, poses)``: a
    bool per action, its expected cost (as :func:`plan_push` scores one) and
    the particles' mean pose ``(theta, tx, ty)`` after each, arrays.
    """
    first, goal, target_px = context.first, context.goal, context.target_px
    res = first.resolution
    now = float(_error_in_tolerances(goal, target_px, res, pose.theta, pose.tx, pose.ty))
    if len(actions) == 0:
        empty = np.zeros(0)
        return np.zeros(0, bool), empty, (empty, empty, empty)
    cost, (theta, tx, ty, _) = _expected(context, pose, hyps, actions)
    weights = hyps.weights[:, None]
    after = (weights * _error_in_tolerances(goal, target_px, res, theta, tx, ty)).sum(axis=0)
    safe = np.isfinite(cost) & (after <= now + LEARNING_SLACK + 1e-9)
    means = tuple((weights * v).sum(axis=0) for v in (theta, tx, ty))
    return safe, cost, means
