"""What a push is worth to the goal planner: the pose cost, the model's error, a follow-up.

* :func:`pose_cost`: the squared pose error in tolerances.
* :func:`model_variance`: the motion model's own error on a push's outcome,
  in the same units, added to every particle's cost: the likelihood's scales
  (:meth:`comcore.Likelihood.model_error_scales`: a push whose line passes
  near the CoM turns the object unpredictably), the rotation's grown with the
  push's travel as :data:`MODEL_ERROR_TRAVEL` and :data:`MODEL_ERROR_POWER`
  say (fitted against the exact engine with the true CoM and friction by
  benchmarks/accuracy/goal_model_error.py; docs/results/goal.md).
* :func:`follow_ups`: the least expected cost of one more push from many poses
  at once (the planner's two-step lookahead), and :func:`spread_picks`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._mask import Mask
from .._types import Motion
from ..active._likelihood import Likelihood
from ..camera._pose_tracking import MISS_ROTATION, MISS_TRANSLATION_M
from ..conventions import rotate_components
from ._translation import STANDOFF_M, _cross_offsets, line_pushes, predict_motions
from ._types import Goal

__all__ = [
    "PlanningContext",
    "follow_ups",
    "model_variance",
    "pose_cost",
    "reached",
    "spread_picks",
    "turn_outside",
]

#: Directions (evenly spaced in the object's frame) of the follow-up pushes.
FOLLOW_DIRECTIONS = 8
#: The share of a follow-up's cost taken from its pose's own particle (the rest: the mixture).
FOLLOW_LEARNED = 0.5
#: Fractions of the allowed travel of the follow-up pushes.
FOLLOW_LENGTHS = (1.0, 0.5, 0.25, 0.1)
#: The motion model's own error (besides the posterior's spread) is counted in a push's cost:
#: the likelihood's scales (:meth:`comcore.Likelihood.model_error_scales`), its rotation
#: scale grown with the push's travel after contact as ``(travel / MODEL_ERROR_TRAVEL) **
#: MODEL_ERROR_POWER`` above its floor (calibrated by benchmarks/accuracy/goal_model_error.py
#: against the exact engine, the true CoM and friction).
MODEL_ERROR_TRAVEL, MODEL_ERROR_POWER = 0.05, 1.8
_SCALES = Likelihood()


#: Offsets evenly spaced across the object per direction (the posterior's three added).
N_OFFSETS = 5


class PlanningContext(NamedTuple):
    """What the goal planner scores every push of one step against (internal).

    The pose and the CoM particles are passed beside it: the planner scores
    pushes from several poses, over a few particles and over all of them.
    """

    first: Mask
    """The first mask: the object's frame, the camera's view and its resolution."""
    goal: Goal
    """The goal the pushes are scored against."""
    target_px: tuple[float, float] | None
    """The goal's ``(tx, ty)``, pixels (None: the goal sets no position)."""
    model: object
    """The motion model that predicts the pushes
    (:func:`comcore.goal._translation.planning_model`)."""
    max_travel_px: float
    """The longest travel after contact the robot allows a push, pixels."""
    pusher_radius: float
    """The pusher's radius, metres."""
    reach_px: float = 0.0
    """The object's radius about its centroid, pixels: a push must keep that disc in view."""
    allowed: np.ndarray | None = None
    """The camera directions (radians) the robot may push along (None: any)."""
    scales: Likelihood = _SCALES
    """The session's likelihood, whose model-error scales the cost counts."""
    turn: tuple[float, float, float] | None = None
    """None, or ``(low, high, limit)`` radians: no push is offered whose mean predicted
    orientation lies more than ``limit`` outside ``[low, high]`` (the goal's ``max_turn``)."""


def pose_cost(goal: Goal, target_px, resolution: float, theta, tx, ty) -> np.ndarray:
    """The squared pose error in tolerances of poses ``(theta, tx, ty)`` (arrays, px)."""
    cost = np.zeros(np.broadcast(theta, tx, ty).shape)
    if target_px is not None:
        dist_m = np.hypot(tx - target_px[0], ty - target_px[1]) * resolution
        cost = cost + (dist_m / goal.position_tolerance) ** 2
    if goal.orientation is not None:
        cost = cost + ((theta - goal.orientation) / goal.orientation_tolerance) ** 2
    return cost


def turn_outside(theta, band) -> np.ndarray:
    """How far (radians, >= 0) orientations ``theta`` lie outside ``band`` = (low, high)."""
    low, high = band
    return np.maximum(np.maximum(low - theta, theta - high), 0.0)


def reached(goal: Goal, target_px, resolution: float, pose: Motion, margin=(0.0, 0.0)) -> bool:
    """Whether ``pose`` is within the goal's tolerances less ``margin`` (radians, metres).

    The margin is what the camera's reading of the pose may be off by; it
    takes at most half of a tolerance.
    """
    if target_px is not None:
        dist = math.hypot(pose.tx - target_px[0], pose.ty - target_px[1]) * resolution
        tol = goal.position_tolerance
        if dist > tol - min(margin[1], 0.5 * tol):
            return False
    if goal.orientation is not None:
        tol = goal.orientation_tolerance
        if abs(pose.theta - goal.orientation) > tol - min(margin[0], 0.5 * tol):
            return False
    return True


def model_variance(
    goal: Goal, first: Mask, actions, coms, motions, scales: Likelihood = _SCALES
) -> np.ndarray:
    """The motion model's own error on each push's outcome, in the cost's units (n_h, a).

    The variance of the rotation (its scale from the CoM's lever about the
    push line and the travel, see :data:`MODEL_ERROR_POWER`) over the squared
    orientation tolerance, plus that of the centroid's displacement (two axes)
    over the squared position tolerance, each where the goal sets it. The
    scales are ``scales``' (the session's likelihood; default ``Likelihood()``).
    """
    res = first.resolution
    start, delta = actions[:, :2], actions[:, 2:] - actions[:, :2]
    length = np.hypot(*delta.T)
    unit = delta / np.maximum(length, 1e-12)[:, None]
    rel = coms[:, None, :] - start[None]  # (n_h, a, 2)
    lever = np.abs(rel[..., 0] * unit[:, 1] - rel[..., 1] * unit[:, 0]) * res
    travel = np.maximum(length * res - STANDOFF_M, 0.0) / MODEL_ERROR_TRAVEL
    moved = np.hypot(motions[..., 1], motions[..., 2]) * res
    theta_s, moved_s = scales.model_error_scales(lever, moved)
    floor = scales.theta_noise[0]
    theta_s = floor + (theta_s - floor) * travel**MODEL_ERROR_POWER
    out = np.zeros(lever.shape)
    if goal.orientation is not None:
        out += (theta_s / goal.orientation_tolerance) ** 2
    if goal.has_position:
        out += 2 * (moved_s / goal.position_tolerance) ** 2
    return out


def follow_ups(context: PlanningContext, poses, hyps, directions, owner) -> np.ndarray:
    """The least expected cost of one more push from each pose (inf: none), coarse.

    ``poses`` is ``(theta, tx, ty)``, three arrays of shape (P,); ``owner``
    (P,) the particle of ``hyps`` each pose is the outcome of (its own
    prediction then counts :data:`FOLLOW_LEARNED`, as if the first push had
    taught the posterior), or None.
    The follow-ups are pushes along ``directions`` of the object's own frame
    (radians), up to the context's travel: their motions do not depend on the
    pose, so one prediction serves every pose (the view is not checked for
    them). The context's ``turn`` leaves out the follow-ups whose mean
    predicted orientation lies more than its limit outside its band.
    """
    first, goal, target_px, turn = context.first, context.goal, context.target_px, context.turn
    travel_px = context.max_travel_px
    offsets = np.stack(
        [_cross_offsets(first, a, hyps, N_OFFSETS, halves=False) for a in directions]
    )
    lengths = [f * travel_px for f in FOLLOW_LENGTHS if f * travel_px >= 2.0]
    actions, _ = line_pushes(
        first, Motion.identity(), directions, offsets, lengths, context.pusher_radius
    )
    if len(actions) == 0:
        return np.full(len(poses[0]), np.inf)
    raw = predict_motions(context.model, first, actions, hyps)
    extra = model_variance(goal, first, actions, hyps.coms, raw, context.scales)
    weights = hyps.weights[:, None]
    moves = np.hypot(raw[..., 1], raw[..., 2]) * first.resolution >= MISS_TRANSLATION_M
    moves |= np.abs(raw[..., 0]) >= MISS_ROTATION
    valid = (weights * moves).sum(axis=0) >= 0.5
    # every pose at once: (P, h, a) motions turned into the camera frame of each pose
    theta, tx, ty = (np.asarray(v, float)[:, None, None] for v in poses)
    c, s = np.cos(theta), np.sin(theta)
    mx, my = raw[None, ..., 1], raw[None, ..., 2]
    x, y = rotate_components(mx, my, c, s, origin=(tx, ty))  # the poses after the pushes
    each = pose_cost(goal, target_px, first.resolution, theta + raw[None, ..., 0], x, y) + extra
    cost = (weights[None] * each).sum(axis=1)  # (P, a)
    if turn is not None:  # the goal's max_turn, as for the first push
        outside = turn_outside(theta + raw[None, ..., 0], turn[:2])
        cost = np.where((weights[None] * outside).sum(axis=1) <= turn[2] + 1e-9, cost, np.inf)
    if FOLLOW_LEARNED and owner is not None:  # the pose's own particle, as if taught
        own = each[np.arange(len(owner)), owner]
        cost = FOLLOW_LEARNED * own + (1 - FOLLOW_LEARNED) * cost
    if not valid.any():
        return np.full(len(theta), np.inf)
    return cost[:, valid].min(axis=1)


def spread_picks(cost: np.ndarray, travel: np.ndarray, n: int) -> np.ndarray:
    """The ``n`` least costs and the least of each travel (finite), as indices."""
    order = np.argsort(cost, kind="stable")
    picks = set(order[:n].tolist())
    for t in np.unique(np.round(travel, 3)):
        mine = order[np.round(travel[order], 3) == t]
        picks.add(int(mine[0]))
    picks = np.array(sorted(picks), dtype=int)
    return picks[np.isfinite(cost[picks])]
