"""What one push tells a session: its record, its evidence, and the object's new pose.

:func:`read_push` is the step between the robot's report (a mask or a motion, an executed
path, or a failure) and the posterior: it reads the pose (:mod:`comcore.camera._pose_tracking`),
decides miss or evidence, chooses among a symmetric outline's readings the one the
posterior explains best, and scores it (:func:`comcore.active._likelihood.push_evidence`). It
validates everything and changes nothing: the session applies the result. Any session on a
moving object (``ActiveSession``, a goal-pushing loop) reads its pushes here.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._mask import Mask
from .._types import Motion, PushRecord
from ..camera._pose_tracking import (
    PoseReading,
    executed_in_object,
    is_miss,
    read_pose,
    relative,
    symmetric_branches,
)
from ..conventions import object_motion_from_camera
from ..geometry._disc_contacts import pusher_contacts
from ._grid import GridPosterior
from ._likelihood import PushMemo, Scoring, push_evidence, tracking_noise
from ._path import (
    OFF_PATH_M,
    FramedPush,
    PushPath,
    check_frames,
    path_from_frames,
    read_path,
)

__all__ = ["PushContext", "best_branch", "object_motion", "push_record", "read_push"]


class PushContext(NamedTuple):
    """What reading a push needs of the session's state (nothing here is changed)."""

    first: Mask
    """The first mask: the object's frame."""
    pose: Motion
    """The object's pose before the push, relative to the first mask."""
    posterior: GridPosterior
    """The posterior before the push."""
    scoring: Scoring
    """The likelihood in pixels of the first mask."""
    gyration_px: float
    """The first mask's radius of gyration (pixels), for the registration's rotation noise."""


def object_motion(pose: Motion, reading: PoseReading) -> np.ndarray:
    """The motion from ``pose`` to the reading's pose, in the object's frame at ``pose``."""
    return object_motion_from_camera(relative(pose, reading.pose), pose.theta)


def push_record(
    base: dict, pose: Motion, action, reading: PoseReading, outcome: str, *, path=(), dropped=()
):
    """A :class:`comcore.PushRecord` of a push read as ``reading`` (``base``: the plan's fields)."""
    residual = reading.residual_px
    return PushRecord(
        action=action,
        motion=tuple(float(v) for v in object_motion(pose, reading)),
        outcome=outcome,
        camera_motion=relative(pose, reading.pose),
        rotation_observed=not reading.ambiguous,
        residual_px=residual if math.isfinite(residual) else None,
        symmetry=reading.symmetry,
        path=path,
        dropped_frames=dropped,
        **base,
    )


def best_branch(
    ctx: PushContext,
    branches,
    action,
    lines,
    memo: PushMemo | None = None,
    tempered: bool = True,
):
    """Of the rotations the masks allow, the one the posterior explains best.

    A symmetric outline (a hexagon) turned by more than half its symmetry
    angle looks like a smaller turn the other way: the reading kept is the
    one of highest marginal likelihood, not merely the nearest. Returns
    ``(branch, loglik, excess)``. ``memo``: the model's predictions for the push,
    shared by its readings (:func:`comcore.active._likelihood.push_evidence`); ``tempered``
    False: ``loglik.tempered`` is ``loglik.full`` alone (the branch is all the caller reads).
    """
    memo = PushMemo() if memo is None else memo
    best = None
    for branch in branches:
        loglik, excess = branch_evidence(ctx, branch, action, lines, memo=memo, tempered=tempered)
        evidence = ctx.posterior.predictive(loglik.full)
        if best is None or evidence > best[0]:
            best = (evidence, branch, loglik, excess)
    return best[1:]


def read_push(
    ctx: PushContext,
    candidates,
    index: int,
    mask,
    motion,
    failed: bool,
    *,
    executed=None,
    frames=None,
):
    """The push's record, its evidence ``(loglik, excess)`` or ``()``, and the new pose.

    ``candidates`` (:class:`comcore.active._choice.Candidates`) and ``index``: the push
    planned; ``mask`` or ``motion``: what the camera or the tracker saw;
    ``failed``: the push could not be made; ``executed``: the path the pusher
    took (camera pixels) or None; ``frames``: what the camera saw during the push
    (:mod:`comcore.active._path`) or None. Validates everything; changes nothing.
    """
    if frames is not None:
        frames = check_frames(frames)
        if failed:
            raise TypeError("observe(failed=True) takes no frames: nothing was executed")
    planned = candidates.actions[index]
    if executed is None and frames:
        near_px = OFF_PATH_M / ctx.first.resolution
        executed = path_from_frames(candidates.in_pose(ctx.pose, [index])[0], frames, near_px)
    done_as = None
    if executed is not None:
        scoring = ctx.scoring
        done_as = executed_in_object(
            ctx.first, ctx.pose, executed, scoring.mus, scoring.pusher_radius
        )
    # an executed path that misses the object is kept as planned: a miss carries no
    # evidence, and a replay (estimate_posterior) needs pushes that hit the first mask
    scored = planned if done_as is None or done_as[1] is None else done_as[0]
    base = {
        "index": index,
        "planned": planned,
        "camera_action": candidates.in_pose(ctx.pose, [index])[0],
        "pose_before": ctx.pose,
    }
    if failed:
        return PushRecord(action=planned, motion=None, outcome="failed", **base), (), None
    reading = read_pose(ctx.first, ctx.pose, mask, motion)
    branches = symmetric_branches(reading, ctx.pose)
    if is_miss(relative(ctx.pose, branches[0].pose), ctx.first.resolution):
        dropped = tuple((i, "miss") for i in range(len(frames or ())))
        record = push_record(base, ctx.pose, scored, branches[0], "miss", dropped=dropped)
        return record, (), branches[0].pose
    action, lines = planned, candidates.lines[index]
    if done_as is not None:
        action, lines = done_as
        if lines is None:
            raise ValueError(
                f"executed {np.asarray(executed, float).ravel().tolist()} misses the "
                "object as the session sees it, but the object moved: pass the path the "
                "pusher took, in camera pixels"
            )
    points, dropped = (), ()
    memo = PushMemo()  # the model's predictions for this push, for each reading of it
    if frames:  # the branch is chosen by its end pose; then its path is scored with it
        branch = branches[0]
        if len(branches) > 1:
            branch = best_branch(ctx, branches, action, lines, memo, tempered=False)[0]
        path = frame_path(ctx, action, frames, branch)
        points, dropped = path.points, path.dropped
        scored_path = path_of(action, path) if points and not branch.ambiguous else None
        loglik, excess = branch_evidence(ctx, branch, action, lines, scored_path, memo=memo)
    else:
        branch, loglik, excess = best_branch(ctx, branches, action, lines, memo)
    record = push_record(base, ctx.pose, scored, branch, "evidence", path=points, dropped=dropped)
    return record, (loglik, excess), branch.pose


def frame_path(ctx: PushContext, action, frames, branch: PoseReading):
    """The frames of a push read along ``action`` (object frame) ending at ``branch``."""
    scoring = ctx.scoring
    contact = pusher_contacts(ctx.first, np.asarray(action, float)[None], scoring.pusher_radius)
    push = FramedPush(
        ctx.first,
        ctx.pose,
        action,
        branch.pose,
        float(contact.travel[0]),
        scoring.tracking,
        scoring.pusher_px,
    )
    return read_path(push, frames)


def path_of(action, path) -> PushPath:
    """The :class:`PushPath` the likelihood scores of a read path (:class:`PathReading`)."""
    return PushPath.of(action, path.points, path.contact_travel, path.tracking)


def branch_evidence(
    ctx: PushContext, branch: PoseReading, action, lines, path=None, *, memo=None, tempered=True
):
    """``(loglik, excess)`` of one reading of the push, with its path where given.

    ``memo`` and ``tempered``: :func:`comcore.active._likelihood.push_evidence`'s.
    """
    return push_evidence(
        ctx.posterior,
        ctx.scoring,
        ctx.first,
        action,
        lines,
        object_motion(ctx.pose, branch),
        rotation_observed=not branch.ambiguous,
        tracking=tracking_noise(ctx.scoring.tracking, branch.residual_px, ctx.gyration_px),
        path=path,
        memo=memo,
        tempered=tempered,
    )
