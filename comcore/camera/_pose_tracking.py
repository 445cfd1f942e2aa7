"""The session's pose tracking: where the object is now, read from the camera.

A pose ``(theta, tx, ty)`` is a :class:`comcore.Motion` from the first mask:
the object turned by ``theta`` about the first mask's area centroid ``c0``,
which then moved by ``(tx, ty)`` (pixels). A point ``p`` of the object in the
first mask is at ``apply_motion(p, theta, (tx, ty), c0)`` in the camera now.

A push's motion in the camera frame is about the object's current centroid,
``c0 + (tx, ty)``; composing it with the pose adds the rotations and the
translations (:func:`compose`), and :func:`relative` undoes that.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._types import Action, Motion
from .._validation import check_actions, check_mask, check_motions, check_turns
from ..conventions import apply_motion, rotation_matrix
from ..geometry._disc_contacts import pusher_contacts
from ..vt._voting import push_force_lines
from ._registration import _measure, _measure_near

__all__ = [
    "MAX_AREA_CHANGE",
    "MAX_RESIDUAL_PX",
    "MISS_ROTATION",
    "MISS_TRANSLATION_M",
    "PoseReading",
    "camera_from_object",
    "compose",
    "executed_in_object",
    "is_miss",
    "measure_pose",
    "moved_mask",
    "object_from_camera",
    "read_pose",
    "relative",
    "symmetric_branches",
]

#: A push after which the object turned by less than this (radians, 0.57 deg) ...
MISS_ROTATION = 0.01
#: ... and its centroid moved by less than this (metres) did not move it: a miss.
#: Both sit above a camera tracker's noise on a still object and below the motion of a
#: push that touches it.
MISS_TRANSLATION_M = 0.001
#: A mask whose outline differs from the first mask's, after the rigid motion that matches
#: them best, by more than this (RMS pixels, the registration's ``residual_px``) is not the
#: object moved: above what exact and noisy camera masks of the object give, below what
#: another object's mask put in its place gives (calibrated by
#: benchmarks/accuracy/observe_refusal.py; docs/results/active.md).
MAX_RESIDUAL_PX = 1.5
#: A mask whose area differs from the first mask's by more than this share is not the
#: object moved (calibrated on the same masks).
MAX_AREA_CHANGE = 0.25
#: A session reads a rotation measured to within this predicted std (radians, 2 deg),
#: where :func:`comcore.measure_motion` calls one worse than 1 deg ambiguous. Dropping
#: it would keep the previous rotation, wrong by the whole turn (a small, nearly symmetric
#: outline's turn is read about that loosely), and every later push would be planned and
#: scored in a frame that far off. The registration's residual already widens the
#: reading's error by about that much (:func:`comcore.active._likelihood.tracking_noise`).
SESSION_MAX_THETA_STD = math.radians(2.0)
#: A frame registered from a predicted pose (:func:`measure_pose`'s ``guess``) is read from
#: that one fit when its outline residual (RMS pixels) is at most this: a binary mask's
#: fit of the right rotation leaves a few tenths of a pixel (about one with noisy masks),
#: a fit caught in another rotation's valley a pixel or more. Above it the frame is
#: registered as any mask is, from the coarse scan over every rotation.
WARM_MAX_RESIDUAL_PX = 1.0


class PoseReading(NamedTuple):
    """What the camera says about the pose after a push (internal)."""

    pose: Motion  # relative to the first mask
    ambiguous: bool  # the rotation is not observable from the outline
    residual_px: float  # the registration's RMS outline distance (NaN: not measured)
    symmetry: int = 1  # order of the outline's rotational symmetry (1: none)


def compose(pose: Motion, motion) -> Motion:
    """The pose after a camera-frame ``motion`` about the current centroid.

    Examples
    --------
    >>> compose(Motion(0.1, 2.0, 0.0), (0.2, 1.0, 1.0))
    Motion(theta=0.30000000000000004, tx=3.0, ty=1.0)
    """
    theta, tx, ty = (float(v) for v in motion)
    return Motion(pose.theta + theta, pose.tx + tx, pose.ty + ty)


def relative(before: Motion, after: Motion) -> Motion:
    """The camera-frame motion (about the current centroid) from pose ``before`` to ``after``."""
    return Motion(after.theta - before.theta, after.tx - before.tx, after.ty - before.ty)


def camera_from_object(actions, pose: Motion, centroid) -> np.ndarray:
    """Object-frame actions (n, 4) as the camera sees them with the object at ``pose``."""
    acts = np.asarray(actions, dtype=float)
    if pose == Motion.identity():
        return acts.copy()
    ends = acts.reshape(-1, 2)
    moved = apply_motion(ends, pose.theta, (pose.tx, pose.ty), centroid)
    return moved.reshape(-1, 4)


def object_from_camera(actions, pose: Motion, centroid) -> np.ndarray:
    """Camera-frame actions (n, 4) with the object at ``pose`` in the object's frame.

    The inverse of :func:`camera_from_object`: a camera point ``q`` shows the object
    point ``R(-theta) (q - c - t) + c``.
    """
    acts = np.asarray(actions, dtype=float)
    if pose == Motion.identity():
        return acts.copy()
    ends = acts.reshape(-1, 2) - np.array([pose.tx, pose.ty])
    return apply_motion(ends, -pose.theta, (0.0, 0.0), centroid).reshape(-1, 4)


def moved_mask(first: Mask, pose: Motion) -> Mask | None:
    """The first mask moved to ``pose`` (nearest pixel), or None if it left the image."""
    if pose == Motion.identity():
        return first
    c0 = np.asarray(first.centroid)
    # Camera pixel q shows the object point p = R(-theta)(q - c0 - t) + c0.
    inverse = rotation_matrix(-pose.theta)  # (x, y) order
    swap = np.array([[0, 1], [1, 0]])
    matrix = swap @ inverse @ swap  # the same map in (row, col) order
    shift = c0 - inverse @ (c0 + np.array([pose.tx, pose.ty]))
    data = ndimage.affine_transform(
        first.data.astype(np.uint8), matrix, offset=shift[::-1], order=0, cval=0
    ).astype(bool)
    return Mask(data, resolution=first.resolution) if data.any() else None


def is_miss(motion, resolution: float) -> bool:
    """Whether a push's camera-frame motion is below the noise (the object did not move)."""
    theta, tx, ty = (float(v) for v in motion)
    return abs(theta) < MISS_ROTATION and math.hypot(tx, ty) * resolution < MISS_TRANSLATION_M


def measure_pose(
    first: Mask, mask: Mask, previous: Motion, guess: Motion | None = None
) -> PoseReading:
    """The pose of the object in ``mask`` relative to ``first`` (comcore.measure_motion).

    When the rotation is ambiguous (a disc, or read worse than
    :data:`SESSION_MAX_THETA_STD`) the previous pose's rotation is kept: the
    camera cannot see it turn. For a shape with a rotational
    symmetry the rotation consistent with the masks nearest the previous
    pose's is taken (pushes turn the object far less than a symmetry angle).

    ``guess``: a predicted pose (a frame during a push, between the poses
    before and after it). The mask is then fitted from it alone
    (``comcore.camera._registration._measure_near``), and registered from
    every rotation only if that fit leaves more than
    :data:`WARM_MAX_RESIDUAL_PX`; ``symmetry`` is then 1, the pose the branch
    nearest the guess.
    """
    try:
        m = None
        if guess is not None:
            near = _measure_near(first, mask, guess, SESSION_MAX_THETA_STD, WARM_MAX_RESIDUAL_PX)
            m = None if near is None else near[0]
        if m is None:
            # near the previous pose: for a symmetric shape that has turned past pi / n the
            # smallest consistent rotation is wrong by 2 pi / n
            m, _ = _measure(
                first, mask, near_theta=float(previous.theta), max_theta_std=SESSION_MAX_THETA_STD
            )
    except ValueError as e:  # e.g. the object touches the border: part of it out of view
        raise ValueError(f"mask cannot be registered against the first mask: {e}") from e
    theta = previous.theta if m.ambiguous else float(m.motion.theta)
    pose = Motion(theta, float(m.motion.tx), float(m.motion.ty))
    return PoseReading(pose, bool(m.ambiguous), float(m.residual_px), int(m.symmetry))


def symmetric_branches(reading: PoseReading, previous: Motion) -> list[PoseReading]:
    """The poses a symmetric outline cannot tell apart, nearest the previous pose first.

    An outline with an ``n``-fold symmetry about its centroid looks the same
    turned by ``2 pi / n``; the centroid stays where it is, so only the
    rotation differs. Branches whose push would have turned the object by
    more than half a turn either way are left out (a push turns an object by
    far less).
    """
    n = int(reading.symmetry)
    if n <= 1 or reading.ambiguous:
        return [reading]
    step = 2 * math.pi / n
    base = reading.pose
    out = []
    for k in range(-n, n + 1):
        theta = base.theta + k * step
        if abs(theta - previous.theta) <= math.pi / 2 + 1e-9:
            out.append(reading._replace(pose=Motion(theta, base.tx, base.ty)))
    out.sort(key=lambda r: abs(r.pose.theta - previous.theta))
    return out or [reading]


def read_pose(first: Mask, pose: Motion, mask, motion, guess: Motion | None = None) -> PoseReading:
    """The pose after a push, from the camera's mask or the caller's motion (validated).

    ``motion`` (camera frame, about the current centroid) is composed with
    ``pose``; a ``mask`` (same shape and resolution as ``first``) is
    registered against ``first``. Raises naming the argument; changes nothing.
    A mask that is not the first mask's object moved is refused: its area
    changed by more than :data:`MAX_AREA_CHANGE` (a single pixel, the arm in
    view), or its outline lies more than :data:`MAX_RESIDUAL_PX` from the
    first mask's after the best rigid motion (another object). ``guess``: a
    predicted pose to fit the mask from (:func:`measure_pose`).
    """
    if motion is not None:
        m = check_turns(check_motions(motion, n=1, name="motion"), "motion")[0]
        return PoseReading(compose(pose, m), False, float("nan"))
    mask = check_mask(mask)
    if mask.shape != first.shape:
        raise ValueError(f"mask must have the first mask's shape {first.shape}, got {mask.shape}")
    if mask.resolution != first.resolution:
        raise ValueError(
            f"mask must have the first mask's resolution {first.resolution} m/px, "
            f"got {mask.resolution}"
        )
    from ._registration import _check_pair

    try:  # an object partly out of view is said so first: it is the object, cut
        _check_pair(first, mask)
    except ValueError as e:
        raise ValueError(f"mask cannot be registered against the first mask: {e}") from e
    change = mask.area_px / first.area_px - 1.0
    if abs(change) > MAX_AREA_CHANGE:
        raise ValueError(
            f"mask is not the first mask's object moved: its area is {mask.area_px} px against "
            f"the first mask's {first.area_px} px ({100 * change:+.0f} %, more than "
            f"{100 * MAX_AREA_CHANGE:.0f} %)" + _NOT_THE_OBJECT
        )
    reading = measure_pose(first, mask, pose, guess)
    if reading.residual_px > MAX_RESIDUAL_PX:
        raise ValueError(
            "mask is not the first mask's object moved: after the rigid motion that matches "
            f"them best its outline lies {reading.residual_px:.1f} px (RMS) from the first "
            f"mask's, where the object's own masks differ by at most {MAX_RESIDUAL_PX:g} px"
            + _NOT_THE_OBJECT
        )
    return reading


#: The end of the message for a mask that is not the object (:func:`read_pose`).
_NOT_THE_OBJECT = (
    ": another object, the arm in view or a wrong threshold? The session is unchanged: "
    "observe the object's mask, or observe(failed=True) if the push could not be made"
)


#: How far (metres) an executed push's start is moved back along its line when it lies
#: just inside the object as the session sees it (see executed_in_object).
EXECUTED_BACKOFF_M = 0.005


def executed_in_object(first: Mask, pose: Motion, executed, mus, pusher_radius: float):
    """An executed push (camera frame at ``pose``) in the object's frame, and its force lines.

    Returns ``(action (4,), lines (m, 3))``, or ``(action, None)`` when the
    path misses the object. A start just inside the outline as the session
    sees it (its pose is measured, to a pixel or so) means the pusher met the
    outline where its line enters: the start is moved back along the line, 1 mm
    at a time, at most :data:`EXECUTED_BACKOFF_M`; further inside it is a
    ValueError naming ``executed``.
    """
    acts = check_actions(executed, "executed", allow_empty=False)
    if acts.shape[0] != 1:
        raise ValueError(f"executed must be a single action (4 numbers), got {acts.shape[0]}")
    obj = object_from_camera(acts, pose, first.centroid)
    con = pusher_contacts(first, obj, pusher_radius)
    step = np.asarray(Action(*obj[0]).direction) * (0.001 / first.resolution)
    for _ in range(round(EXECUTED_BACKOFF_M / 0.001)):
        if not con.starts_inside[0]:
            break
        obj[0, :2] -= step
        con = pusher_contacts(first, obj, pusher_radius)
    if con.starts_inside[0]:
        raise ValueError(
            f"executed {acts[0].tolist()} starts inside the object as the session sees it"
        )
    if not con.hit[0]:
        return obj[0], None
    return obj[0], push_force_lines(con, obj, mus)[0]
