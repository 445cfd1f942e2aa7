"""The frames of a push: read into the object's path along it, each dropped frame with its reason.

Open this file to change what the camera's frames during a push tell a session.

**Reading** (:func:`read_path`). Each frame is a :class:`comcore.PushFrame`: where the
pusher's leading point was (camera pixels) and the camera's mask then (registered
against the first mask, as the session's masks are) or the object's motion since the
push began. The pusher's position is read as its *travel* along the push as scored
(the planned path, or the executed one where the robot said so); the frame's pose as
the object's motion since the push began, in the object's frame. A frame is dropped,
with a record of why (``PushRecord.dropped_frames``), when

* its mask cannot be registered (``"registration: ..."``: the arm biting the mask,
  another object, the object cut by the image border),
* it was taken before the pusher touched the object or within a pixel of the push's
  end (``"before_contact"``, ``"at_end"``: nothing the end pose does not say),
* its pose jumps: it lies more than :data:`JUMP_M` (or :data:`JUMP_TURN`) off the
  straight line between its kept neighbours' poses, and more than six tracking
  standard deviations (``"jump"``: a registration fault, the pusher's shadow),
* it is not among the :data:`MAX_PATH_FRAMES` read, evenly spread in travel over
  those between contact and the end (``"thinned"``: nearby frames tell little more,
  and each one read costs a registration).

Frames given out of order, or with the pusher off the push's path by more than
:data:`OFF_PATH_M`, are the caller's mistake: a ValueError naming the frame.

**Scoring**: :mod:`comcore.active._motion_term` (the path's density given the end
pose), :class:`PushPath` what it reads.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._checks import check_point
from .._mask import Mask
from .._types import Motion, PathPoint, PushFrame
from .._validation import check_motions, check_turns
from ..camera._pose_tracking import (
    object_from_camera,
    read_pose,
    relative,
    symmetric_branches,
)
from ..conventions import ccw_cross, object_motion_from_camera
from ._likelihood import gyration_px, tracking_noise

__all__ = [
    "JUMP_M",
    "JUMP_TURN",
    "MAX_FRAMES",
    "MAX_PATH_FRAMES",
    "OFF_PATH_M",
    "PATH_SPAN_PX",
    "FramedPush",
    "PathReading",
    "PushPath",
    "check_frames",
    "path_from_frames",
    "path_tracking",
    "read_path",
]

#: Most frames kept per push (evenly spread in travel); the rest are ``"thinned"``. Chosen
#: among 4, 8 and 16 on seed-1 trials of ``comcore bench``'s ``active-robot`` at 10 Hz
#: (exact, pymunk, noisy masks): 4 erred no more and held the CoM as often as 8 or more
#: often, at half the registrations; 16 held it less often (docs/explanation/calibration.md).
MAX_PATH_FRAMES = 4
#: Most frames one push may be given (a 10 s push at 100 Hz): more is a mistake of units.
MAX_FRAMES = 1000
#: A frame whose pusher lies farther than this (metres) off the push's path is refused:
#: the pusher's position in another frame, or another point of the arm.
OFF_PATH_M = 0.01
#: A frame whose pose lies this far (metres, the centroid) off its neighbours' line jumps ...
JUMP_M = 0.003
#: ... or whose rotation lies this far (radians) off it.
JUMP_TURN = 0.05
#: ... and in either case more than this many tracking standard deviations.
JUMP_STDS = 6.0


class PathReading(NamedTuple):
    """A push's frames as read: the kept poses and the dropped frames (internal)."""

    points: tuple  # PathPoint, kept, in travel order
    dropped: tuple  # (index, reason)
    tracking: tuple  # (rad, px) mean tracking std of the kept frames
    contact_travel: float  # the pusher's travel (px) to first contact along the push


class PushPath(NamedTuple):
    """What the likelihood reads of a push's path (internal)."""

    points: tuple  # PathPoint, in travel order, each after contact and before the end
    fractions: np.ndarray  # (J,) travel after contact over the push's, in (0, 1)
    tracking: tuple  # (rad, px) the frames' tracking standard deviations

    @classmethod
    def of(cls, action, points, contact_travel: float, tracking) -> PushPath:
        """The path of ``points`` along ``action`` (object frame), first touching it there."""
        act = np.asarray(action, dtype=float)
        length = float(np.hypot(*(act[2:] - act[:2])))
        travel = np.array([p.travel for p in points], float)
        span = max(length - contact_travel, 1e-9)
        fractions = np.clip((travel - contact_travel) / span, 1e-6, 1 - 1e-6)
        return cls(tuple(points), fractions, tuple(tracking))


def check_frames(frames) -> list:
    """``frames`` as a list of ``(pusher (2,), view)``, or a named error (nothing is read)."""
    if isinstance(frames, (str, bytes, Mask, dict)) or not hasattr(frames, "__len__"):
        raise TypeError(
            "frames must be a sequence of comcore.PushFrame (pusher, view) pairs, "
            f"got {type(frames).__name__}"
        )
    if len(frames) > MAX_FRAMES:
        raise ValueError(f"frames must hold at most {MAX_FRAMES} frames, got {len(frames)}")
    out = []
    for i, frame in enumerate(frames):
        if isinstance(frame, (str, bytes, Mask)) or not hasattr(frame, "__len__"):
            raise TypeError(
                f"frames[{i}] must be a comcore.PushFrame (pusher, view), got "
                f"{type(frame).__name__}"
            )
        if len(frame) != 2:
            raise ValueError(f"frames[{i}] must be a pair (pusher, view), got {len(frame)} items")
        pusher = check_point(frame[0], f"frames[{i}].pusher")
        view = frame[1]
        if not isinstance(view, (Mask, Motion)) and not _motion_like(view):
            raise TypeError(
                f"frames[{i}].view must be a comcore.Mask or a comcore.Motion, got "
                f"{type(view).__name__}"
            )
        if not isinstance(view, Mask):
            name = f"frames[{i}].view"
            view = Motion(*check_turns(check_motions(view, n=1, name=name), name)[0])
        out.append(PushFrame((float(pusher[0]), float(pusher[1])), view))
    return out


def _motion_like(view) -> bool:
    try:
        arr = np.asarray(view, dtype=float)
    except (TypeError, ValueError):
        return False
    return arr.shape == (3,)


#: The frames' pusher positions tell the path the pusher took when they span this much of
#: the push (pixels along it) and are at least three.
PATH_SPAN_PX = 4.0


def path_from_frames(camera_action, frames, near_px: float):
    """The pusher's path as its frames show it (camera pixels), or None if they cannot tell.

    ``camera_action``: the push as planned, in camera pixels; ``frames``: checked
    (:func:`check_frames`).

    The line fitted (least squares) through the frames' pusher positions, from the
    planned start's foot on it to the planned end's: where the robot reports where its
    pusher went, the push is scored as it went (as ``observe(executed=...)``); where it
    reports the commanded positions, this is the planned path. None when the line's
    ends lie more than ``near_px`` from the planned ones (the frames are then checked,
    and refused, against the planned path: :func:`read_path`).
    """
    points = np.array([f.pusher for f in frames], dtype=float)
    act = np.asarray(camera_action, dtype=float)
    direction = (act[2:] - act[:2]) / np.hypot(*(act[2:] - act[:2]))
    along = (points - act[:2]) @ direction
    if len(points) < 3 or np.ptp(along) < PATH_SPAN_PX:
        return None
    centre = points.mean(axis=0)
    axis = np.linalg.svd(points - centre)[2][0]
    axis = axis if axis @ direction > 0 else -axis
    start = centre + ((act[:2] - centre) @ axis) * axis
    end = centre + ((act[2:] - centre) @ axis) * axis
    if max(np.hypot(*(start - act[:2])), np.hypot(*(end - act[2:]))) > near_px:
        return None
    return np.concatenate([start, end])


class FramedPush(NamedTuple):
    """A push whose frames are read (internal): where it ran, from what pose to what pose."""

    first: Mask
    """The first mask (the object's frame)."""
    pose: Motion
    """The object's pose before the push, relative to the first mask."""
    action: np.ndarray
    """The push as scored (object frame), shape (4,)."""
    end_pose: Motion
    """The pose after the push, as read."""
    contact_travel: float
    """The pusher's travel (pixels) along the push to first contact."""
    tracking: tuple
    """The motion noise ``(rad, px)`` of a frame without a registration residual."""
    pusher_px: float = 0.0
    """The pusher's error across its path (pixels): widens how far off it a frame's pusher
    may be."""


def read_path(push: FramedPush, frames: list) -> PathReading:
    """The poses the frames show along the push (object frame), and the frames dropped.

    ``frames``: checked (:func:`check_frames`), in the order they were taken. A frame
    whose pusher lies off the push's path, behind the frame before it or past the push's
    end is a ValueError naming it.
    """
    dropped: list = []  # (index, reason)
    candidates = _between_contact_and_end(push, frames, dropped)
    if len(candidates) > MAX_PATH_FRAMES:  # thinned before registering: a frame costs that
        chosen = _evenly(np.array([t for _, t in candidates]), MAX_PATH_FRAMES)
        dropped.extend((c[0], "thinned") for j, c in enumerate(candidates) if j not in chosen)
        candidates = [c for j, c in enumerate(candidates) if j in chosen]
    gyration = gyration_px(push.first)
    kept = []  # (index, travel, motion, tracking, residual)
    for i, travel in candidates:
        pose = _frame_pose(push, i, frames[i].view, travel, dropped)
        if pose is None:
            continue
        motion = object_motion_from_camera(relative(push.pose, pose[0]), push.pose.theta)
        residual = pose[1] if math.isfinite(pose[1]) else None
        noise = tracking_noise(push.tracking, residual, gyration)
        kept.append((i, travel, Motion(*motion), noise, residual))
    kept = _without_jumps(kept, push, dropped)
    dropped.sort()
    points = tuple(PathPoint(t, m, r) for _, t, m, _, r in kept)
    tracking = path_tracking(points, push.tracking, push.first)
    return PathReading(points, tuple(dropped), tracking, float(push.contact_travel))


def _push_line(push: FramedPush) -> tuple[np.ndarray, np.ndarray, float]:
    """The push's start (pixels), its unit direction and its length (pixels)."""
    act = np.asarray(push.action, dtype=float)
    start, end = act[:2], act[2:]
    length = float(np.hypot(*(end - start)))
    return start, (end - start) / length, length


def _between_contact_and_end(push: FramedPush, frames, dropped: list) -> list:
    """``(index, travel)`` of the frames between first contact and the push's end.

    The others are added to ``dropped`` (``"before_contact"``, ``"at_end"``); a frame
    whose pusher lies off the path, behind the frame before or past the end is a
    ValueError naming it.
    """
    start, direction, length = _push_line(push)
    off_px = OFF_PATH_M / push.first.resolution + 3.0 * push.pusher_px + 2.0
    candidates: list = []
    last_travel = -math.inf
    for i, frame in enumerate(frames):
        q = object_from_camera(np.tile(frame.pusher, 2)[None], push.pose, push.first.centroid)
        travel = float(np.dot(q[0, :2] - start, direction))
        across = float(abs(ccw_cross(direction, q[0, :2] - start)))
        if across > off_px:
            raise ValueError(
                f"frames[{i}].pusher {list(frame.pusher)} lies {across:.1f} px off the push's "
                f"path (at most {off_px:.1f} px): is it the pusher's leading point, in this "
                "camera's pixels?"
            )
        if travel < last_travel - 1.0:
            raise ValueError(
                f"frames[{i}].pusher is {last_travel - travel:.1f} px behind the frame before "
                "it along the push: frames must be given in the order they were taken"
            )
        last_travel = max(last_travel, travel)
        if travel > length + off_px:
            raise ValueError(
                f"frames[{i}].pusher is {travel - length:.1f} px past the push's end: is it the "
                "pusher of this push?"
            )
        if travel <= push.contact_travel + 1.0:
            dropped.append((i, "before_contact"))
        elif travel >= length - 1.0:
            dropped.append((i, "at_end"))
        else:
            candidates.append((i, travel))
    return candidates


def _frame_pose(push: FramedPush, index: int, view, travel: float, dropped: list):
    """``(pose, residual_px)`` of frame ``index``'s view, or None (then added to ``dropped``).

    A mask is registered from the pose in proportion along the push; one that cannot
    be is dropped (``"registration: ..."``); a motion that cannot be read is a ValueError.
    """
    try:
        if isinstance(view, Mask):
            length = _push_line(push)[2]
            guess = _between(push.pose, push.end_pose, travel, push.contact_travel, length)
            reading = read_pose(push.first, push.pose, view, None, guess=guess)
        else:
            reading = read_pose(push.first, push.pose, None, view)
    except ValueError as e:
        if not isinstance(view, Mask):
            raise ValueError(f"frames[{index}].view: {e}") from e
        dropped.append((index, f"registration: {e}"))
        return None
    return _nearest_turn(reading, push.pose, push.end_pose), reading.residual_px


def _between(before: Motion, after: Motion, travel, contact_travel, length) -> Motion:
    """The pose a frame at ``travel`` is registered from: ``before`` to ``after`` in proportion.

    The pusher's travel since contact over the push's (the object moves only after
    contact); each of theta, tx and ty in proportion, the guess the fit starts from.
    """
    span = length - contact_travel
    f = min(max((travel - contact_travel) / span, 0.0), 1.0) if span > 0 else 1.0
    return Motion(*((1 - f) * np.asarray(before, float) + f * np.asarray(after, float)))


def path_tracking(points, tracking, first: Mask) -> tuple[float, float]:
    """The frames' tracking standard deviations (rad, px): the RMS over the points of each's."""
    if not points:
        return tuple(tracking)
    gyration = gyration_px(first)
    noise = np.array([tracking_noise(tracking, p.residual_px, gyration) for p in points])
    rms = np.sqrt(np.mean(np.square(noise), axis=0))
    return float(rms[0]), float(rms[1])


def _nearest_turn(reading, before: Motion, after: Motion) -> Motion:
    """The pose, of those a symmetric outline allows, whose turn lies nearest the push's own.

    The poses are :func:`comcore.camera._pose_tracking.symmetric_branches`'; the push's
    turn runs from ``before``'s to ``after``'s.
    """
    lo, hi = sorted((before.theta, after.theta))
    branches = symmetric_branches(reading, before)
    return min(branches, key=lambda r: max(lo - r.pose.theta, r.pose.theta - hi, 0.0)).pose


def _without_jumps(kept: list, push: FramedPush, dropped: list) -> list:
    """``kept`` without the frames whose pose jumps off the line between their neighbours.

    Each frame dropped is added to ``dropped`` (``"jump"``).
    """
    end = object_motion_from_camera(relative(push.pose, push.end_pose), push.pose.theta)
    contact_travel, length = push.contact_travel, _push_line(push)[2]
    jump_px = JUMP_M / push.first.resolution
    changed = True
    while changed and kept:
        changed = False
        travel = [contact_travel] + [k[1] for k in kept] + [length]
        poses = [np.zeros(3)] + [np.asarray(k[2], float) for k in kept] + [np.asarray(end)]
        worst, worst_j = 0.0, None
        for j, (_, t, _, noise, _) in enumerate(kept, start=1):
            lo, hi = travel[j - 1], travel[j + 1]
            f = (t - lo) / (hi - lo) if hi > lo else 0.5
            line = (1 - f) * poses[j - 1] + f * poses[j + 1]
            off = poses[j] - line
            turn, shift = abs(off[0]), float(np.hypot(off[1], off[2]))
            score = max(
                (turn - max(JUMP_TURN, JUMP_STDS * noise[0])) / JUMP_TURN,
                (shift - max(jump_px, JUMP_STDS * noise[1])) / jump_px,
            )
            if score > worst:
                worst, worst_j = score, j - 1
        if worst_j is not None:
            dropped.append((kept[worst_j][0], "jump"))
            kept = kept[:worst_j] + kept[worst_j + 1 :]
            changed = True
    return kept


def _evenly(travel: np.ndarray, n: int) -> set:
    """Indices of ``n`` of the travels nearest ``n`` evenly spaced ones."""
    targets = np.linspace(travel[0], travel[-1], n)
    chosen: set = set()
    for t in targets:
        order = np.argsort(np.abs(travel - t))
        chosen.add(int(next(j for j in order if int(j) not in chosen)))
    return chosen
