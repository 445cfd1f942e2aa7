"""Pose streams of a recorded push: sorted, interpolated, and the window of pusher travel.

Helpers of :func:`comcore.recording_from_poses`. A stream is an array of rows
``(t, x, y, yaw)`` in one world frame (seconds, metres, radians, ``z`` up).
"""

from __future__ import annotations

import math

import numpy as np

from .._validation import _as_float_rows
from ..conventions import rotate_components
from ..geometry._outline import outline_signed_distance

__all__ = ["pose_at", "push_window", "pusher_gaps", "stream", "to_frame"]


def stream(rows, name: str) -> np.ndarray:
    """Rows ``(t, x, y, yaw)`` sorted by time, repeated times dropped, yaw unwrapped."""
    arr = np.array(_as_float_rows(rows, 4, name, tuple()))  # type: ignore[arg-type]
    if len(arr) == 0:
        raise ValueError(
            f"{name} must hold samples at two or more distinct times, got an empty stream"
        )
    arr = arr[np.argsort(arr[:, 0], kind="stable")]
    keep = np.concatenate([[True], np.diff(arr[:, 0]) > 0])
    arr = arr[keep]
    if len(arr) < 2:
        raise ValueError(f"{name} must hold samples at two or more distinct times, got {len(arr)}")
    arr[:, 3] = np.unwrap(arr[:, 3])
    return arr


def pose_at(stream: np.ndarray, t) -> np.ndarray:
    """Poses ``(x, y, yaw)`` interpolated linearly at times ``t`` (within the stream)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    return np.column_stack([np.interp(t, stream[:, 0], stream[:, k]) for k in (1, 2, 3)])


def to_frame(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """World points (n, 2) into the frame of one pose ``(x, y, yaw)``."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    rel = points - pose[:2]
    return np.column_stack(rotate_components(rel[:, 0], rel[:, 1], c, s))  # world to body


def _crossing(t: np.ndarray, value: np.ndarray, level: float, k: int) -> float:
    """Time where ``value`` reaches ``level`` between samples ``k - 1`` and ``k`` (linear)."""
    if k == 0:
        return float(t[0])
    v0, v1 = value[k - 1], value[k]
    f = 0.0 if v1 == v0 else float(np.clip((level - v0) / (v1 - v0), 0.0, 1.0))
    return float(t[k - 1] + f * (t[k] - t[k - 1]))


def pusher_gaps(poly, obj: np.ndarray, pusher: np.ndarray, radius: float):
    """The pusher's rows within the object's time span, and the disc's gap to the outline at each.

    ``poly`` a checked outline, ``obj`` and ``pusher`` streams (:func:`stream`); the gap in
    metres, negative where the disc overlaps the outline.
    """
    pusher = pusher[(pusher[:, 0] >= obj[0, 0]) & (pusher[:, 0] <= obj[-1, 0])]
    if len(pusher) == 0:
        return pusher, np.empty(0)
    poses = pose_at(obj, pusher[:, 0])
    rel = pusher[:, 1:3] - poses[:, :2]
    local = np.column_stack(
        rotate_components(rel[:, 0], rel[:, 1], np.cos(poses[:, 2]), np.sin(poses[:, 2]))
    )
    return pusher, outline_signed_distance(poly, local) - radius


def push_window(outline, obj, pusher, radius, travel, tolerance):
    """``(t_contact, t_end)`` of one push, or ``(reason, detail)`` when it cannot be used."""
    pus, gap = pusher_gaps(outline, obj, pusher, radius)
    if len(pus) == 0:
        return "no_object_pose", "the object's poses do not overlap the pusher's in time"
    if gap[0] < -tolerance:
        return "starts_inside", (
            f"the pusher's disc overlaps the outline by {-gap[0] * 1000:.2f} mm at its first "
            f"sample (tolerance {tolerance * 1000:.2f} mm)"
        )
    touching = np.flatnonzero(gap <= tolerance)
    if not len(touching):
        return "misses", (
            f"the pusher's disc comes no closer than {gap.min() * 1000:.2f} mm to the outline "
            f"(tolerance {tolerance * 1000:.2f} mm)"
        )
    k = int(touching[0])
    t_contact = _crossing(pus[:, 0], gap, tolerance, k)
    p_contact = pose_at(pusher, t_contact)[0, :2]
    after = pusher[pusher[:, 0] > t_contact]
    dist = np.hypot(after[:, 1] - p_contact[0], after[:, 2] - p_contact[1])
    reached = np.flatnonzero(dist >= travel)
    if not len(reached):
        return "short", (
            f"the pusher travels {dist.max(initial=0.0) * 1000:.1f} mm after first contact, "
            f"less than the window's {travel * 1000:.1f} mm"
        )
    j = int(reached[0])
    times = np.concatenate([[t_contact], after[:, 0]])
    t_end = _crossing(times, np.concatenate([[0.0], dist]), travel, j + 1)
    if t_end > obj[-1, 0]:
        return "no_object_pose", (
            f"the object's poses end at {obj[-1, 0] - t_contact:.3f} s after first contact, "
            f"before the window does ({t_end - t_contact:.3f} s)"
        )
    return t_contact, t_end
