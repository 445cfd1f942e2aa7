"""Recorded pushes in: pose streams of an object and a pusher to comcore's Actions and Motions.

Most labs record pushing with motion capture or a robot's joint encoders: the
object's pose and the pusher's position over time, in one world frame.
:func:`recording_from_poses` turns such logs, one pair of streams per push,
into what comcore's estimators take: the object's :class:`Mask` drawn from its
outline, and per push the path of the pusher's leading point (an
:class:`Action`, in the object's frame at the push's start) and the object's
rigid :class:`Motion` over a window of pusher travel after first contact.
Pushes that cannot be used are reported (:class:`SkippedPush`), never dropped
silently.

Each stream is sorted by time and its yaw unwrapped (seen from above, ``z`` up,
counter-clockwise ``yaw`` is positive). Per push:

* **First contact** is the first time the pusher's disc comes within
  ``contact_tolerance`` of the outline, the object's pose interpolated at the
  pusher's sample times (and the crossing interpolated between samples). A disc
  that overlaps the outline by more than the tolerance at the first sample
  ``"starts_inside"``; one that never comes that close ``"misses"``.
* **The window** runs from first contact until the pusher's centre is ``travel``
  metres (straight-line distance) from where it was then; both ends are
  interpolated between samples, the object's poses at those times too. A pusher
  that never gets that far is ``"short"``.
* **The action** is the path of the pusher's LEADING point (its centre plus
  ``pusher_radius`` along the direction of travel, as :class:`Action` defines
  it), straight from ``standoff`` metres before its position at first contact to
  its position at the window's end, in the object's frame at first contact, in
  pixels of the mask.
* **The motion** is the object's rigid motion over the window as :class:`Motion`
  defines it: the change of yaw (counter-clockwise seen from above is
  counter-clockwise on screen) and the displacement of the material point under
  the mask's area centroid, in the object's frame at first contact, pixels (see
  :func:`comcore.apply_motion`).

An action whose start falls on the mask is ``"starts_inside"``, one whose disc
misses the drawn mask (:func:`comcore.geometry.disc_contacts`) ``"misses"``. A
kept push whose leading line misses the mask while its disc touches it is kept
with ``line_hits=False`` (its side touched the object).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._mask import Mask
from .._types import Action, Motion, PushFrame, SkippedPush
from .._validation import _as_float_rows, check_point, check_positive
from ..conventions import DEFAULT_RESOLUTION, DEFAULT_TRAVEL_M, rotate_components
from ..geometry._contacts import contacts
from ..geometry._disc_contacts import disc_contacts
from ..geometry._outline import (
    DEFAULT_MARGIN_M,
    OutlineFrame,
    check_outline,
    mask_from_outline,
)
from ._pose_streams import pose_at, push_window, stream, to_frame

__all__ = ["RecordedPush", "Recording", "SkippedPush", "recording_from_poses"]

#: Default distance (metres) the Action starts before the leading point's first-contact position.
DEFAULT_STANDOFF_M = 0.01
#: Default gap (metres) between the pusher's disc and the outline that counts as contact.
DEFAULT_CONTACT_TOLERANCE_M = 0.002
#: Why a push is skipped.
SKIP_REASONS = ("starts_inside", "misses", "short", "no_object_pose")


#: Most frames a second ``recording_from_poses`` keeps (the MIT streams run at 250 Hz).
MAX_FRAME_RATE = 1000.0


class RecordedPush(NamedTuple):
    """One push that was kept: comcore's inputs and what the recording says about them."""

    index: int
    """Position of the push in the input."""
    name: str
    """Its name (the file name for a dataset), or ``""``."""
    action: Action
    """Path of the pusher's leading point, pixels of the mask, object frame at the window start."""
    motion: Motion
    """The object's rigid motion over the window (theta CCW; the mask centroid's shift, px)."""
    line_hits: bool
    """The leading point's line enters the mask (:func:`~comcore.geometry.contacts`): False
    whose disc touches the object with its side only (grazing), which estimators built on
    the leading line cannot score."""
    speed: float
    """Median pusher speed over the window, m/s."""
    start_time: float
    """Time of first contact (the window's start), seconds, in the streams' clock."""
    end_time: float
    """Time the pusher has travelled the window's length past first contact, seconds."""
    path_deviation: float
    """Largest distance (metres) of the pusher's recorded path over the window from the
    straight ``action``."""
    frames: tuple = ()
    """The poses during the window as :class:`comcore.PushFrame` (``recording_from_poses(...,
    frame_rate=...)``; empty without): the pusher's leading point (pixels of the mask) and
    the object's motion since first contact (in the mask's frame, as ``motion``), for
    ``comcore.estimate_posterior(..., frames=...)``."""


@dataclass(frozen=True, eq=False)
class Recording:
    """Recorded pushes of one object as comcore's inputs (see :func:`recording_from_poses`).

    Attributes
    ----------
    mask : Mask
        The object drawn from its outline (:func:`comcore.mask_from_outline`).
    pushes : tuple of RecordedPush
        The pushes kept, in input order.
    skipped : tuple of SkippedPush
        The pushes that could not be used, with the reason.
    com : tuple of float or None
        The true CoM in pixels, where it was given.
    frame : OutlineFrame
        The pixel frame: :meth:`pixels_from_object` and :meth:`object_from_pixels`.
    pusher_radius, travel : float
        Metres, as given.
    time_origin_ns : int or None
        The streams' time 0 as ROS time, nanoseconds since the epoch, where it
        is known (a bag's start, :func:`comcore.recordings.bag.recording_from_bag`);
        ``None`` otherwise.
    """

    mask: Mask
    pushes: tuple[RecordedPush, ...]
    skipped: tuple[SkippedPush, ...]
    com: tuple[float, float] | None
    frame: OutlineFrame
    pusher_radius: float
    travel: float
    time_origin_ns: int | None = None

    @property
    def stamp(self) -> tuple[int, int] | None:
        """ROS time ``(sec, nanosec)`` at which the last kept push's window ends.

        ``None`` where the streams' clock is not known (:attr:`time_origin_ns`) or no
        push was kept.
        """
        if self.time_origin_ns is None or not self.pushes:
            return None
        end = int(self.time_origin_ns) + round(max(p.end_time for p in self.pushes) * 1e9)
        return divmod(end, 1_000_000_000)

    @property
    def actions(self) -> np.ndarray:
        """The kept pushes' actions, shape (n, 4), pixels."""
        return np.array([p.action for p in self.pushes], dtype=float).reshape(-1, 4)

    @property
    def motions(self) -> np.ndarray:
        """Their motions ``(theta, tx, ty)``, shape (n, 3)."""
        return np.array([p.motion for p in self.pushes], dtype=float).reshape(-1, 3)

    @property
    def line_hits(self) -> np.ndarray:
        """Per kept push: the leading point's line enters the mask, shape (n,) bool."""
        return np.array([p.line_hits for p in self.pushes], dtype=bool)

    def pixels_from_object(self, points_m) -> np.ndarray:
        """Object-frame metres (``y`` up) to pixels of :attr:`mask`, shape (n, 2)."""
        return self.frame.pixels_from_object(_as_float_rows(points_m, 2, "points_m", tuple()))

    def object_from_pixels(self, points_px) -> np.ndarray:
        """Pixels of :attr:`mask` to object-frame metres, shape (n, 2)."""
        return self.frame.object_from_pixels(_as_float_rows(points_px, 2, "points_px", tuple()))

    def report(self) -> str:
        """One line per push that was skipped or grazes (kept, but its leading line misses)."""
        lines = [f"{len(self.pushes)} pushes kept, {len(self.skipped)} skipped"]
        lines += [f"skipped {s.index} {s.name}: {s.reason}: {s.detail}" for s in self.skipped]
        lines += [
            f"grazing {p.index} {p.name}: the disc's side touches, the leading line misses"
            for p in self.pushes
            if not p.line_hits
        ]
        return "\n".join(lines)


def recording_from_poses(
    outline,
    pushes,
    pusher_radius: float,
    *,
    travel: float = DEFAULT_TRAVEL_M,
    resolution: float = DEFAULT_RESOLUTION,
    com=None,
    names=None,
    margin: float = DEFAULT_MARGIN_M,
    standoff: float = DEFAULT_STANDOFF_M,
    contact_tolerance: float = DEFAULT_CONTACT_TOLERANCE_M,
    frame_rate: float | None = None,
) -> Recording:
    """Turn recorded pose streams of pushes into comcore's Mask, Actions and Motions.

    Each push is a pair of streams in one world frame, the object's pose and the
    pusher tip's centre; this module's docstring says how each push is read.

    Parameters
    ----------
    outline : array_like, shape (k, 2)
        The object's outline in its own frame, metres (``x`` right, ``y`` up seen
        from above; either orientation).
    pushes : sequence of (object_poses, pusher_poses)
        Per push, the two streams, each array_like of shape (n, 4) with rows
        ``(t, x, y, yaw)``: seconds, metres, metres, radians (the pusher's yaw is
        not used). Cut a long log into pushes first (:func:`split_pushes`).
    pusher_radius : float
        Radius of the round pusher's tip, metres (>= 0).
    travel : float, optional
        The window: metres of pusher travel after first contact (default 3 cm).
    resolution, margin : float, optional
        Metres per pixel of the mask (default 2.5 mm); its empty border (2 cm).
    com : array_like, shape (2,), optional
        The true CoM in the object's frame, metres, where known.
    names : sequence of str, optional
        One name per push, for the reports.
    standoff : float, optional
        How far before the leading point's first-contact position the action
        starts, metres (default 1 cm).
    contact_tolerance : float, optional
        Gap between the disc and the outline that counts as contact (default 2 mm).
    frame_rate : float, optional
        Also keep the poses during each window at this rate (Hz) as
        ``RecordedPush.frames``, for ``estimate_posterior(..., frames=...)``.

    Returns
    -------
    Recording
        ``recording.actions`` and ``recording.motions`` are what the estimators take.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments, each named: a stream that is not (n, 4) finite
        numbers with two distinct times, a bad outline, radius, length or resolution.

    Examples
    --------
    A 6 cm square plate pushed up its bottom edge's normal 1 cm right of its
    centre, turning counter-clockwise; the action goes up the screen:

    >>> import numpy as np, comcore
    >>> square = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> pusher = np.column_stack([t, np.full_like(t, 0.01), -0.034 + 0.04 * t, 0 * t])
    >>> moving = np.clip(t - 0.1, 0, None)  # the object moves once the pusher touches it
    >>> obj = np.column_stack([t, 0 * t, 0.04 * moving, 0.2 * moving])
    >>> rec = comcore.recording_from_poses(square, [(obj, pusher)], 0.004, travel=0.02, com=(0, 0))
    >>> push = rec.pushes[0]
    >>> push.line_hits, np.round(push.action, 2).tolist(), push.motion.theta > 0, rec.com
    (True, [23.5, 35.5, 23.5, 23.5], True, (19.5, 19.5))
    """
    poly = check_outline(outline)
    radius = check_positive(pusher_radius, "pusher_radius", allow_zero=True)
    travel = check_positive(travel, "travel")
    standoff = check_positive(standoff, "standoff")
    tolerance = check_positive(contact_tolerance, "contact_tolerance", allow_zero=True)
    rate = None if frame_rate is None else check_positive(frame_rate, "frame_rate")
    if rate is not None and rate > MAX_FRAME_RATE:
        raise ValueError(
            f"frame_rate must be at most {MAX_FRAME_RATE:g} Hz (frames a second), got {rate:g}"
        )
    mask = mask_from_outline(poly, resolution, margin)
    frame = OutlineFrame(poly, mask.resolution, check_positive(margin, "margin", allow_zero=True))
    if isinstance(pushes, (str, bytes)) or not hasattr(pushes, "__len__"):
        raise TypeError(
            f"pushes must be a sequence of (object_poses, pusher_poses) pairs, got "
            f"{type(pushes).__name__}"
        )
    if names is None:
        names = [""] * len(pushes)
    names = [str(n) for n in names]
    if len(names) != len(pushes):
        raise ValueError(f"names must hold one name per push ({len(pushes)}), got {len(names)}")
    streams = []
    for i, pair in enumerate(pushes):
        if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise TypeError(f"pushes[{i}] must be a pair (object_poses, pusher_poses)")
        streams.append(
            (
                stream(pair[0], f"pushes[{i}] object poses"),
                stream(pair[1], f"pushes[{i}] pusher poses"),
            )
        )
    centroid_m = frame.object_from_pixels(np.array(mask.centroid))[0]
    kept, skipped = [], []
    for i, (obj, pusher) in enumerate(streams):
        window = push_window(poly, obj, pusher, radius, travel, tolerance)
        if isinstance(window[0], str):
            skipped.append(SkippedPush(i, names[i], *window))
            continue
        span = _Window(obj, pusher, *window)
        pushed = _push(frame, span, radius, standoff, centroid_m)
        frames = () if rate is None else _frames(frame, span, radius, centroid_m, rate)
        kept.append((i, *pushed, frames))
    pushes_out = _check_on_mask(mask, kept, radius, names, skipped)
    skipped.sort(key=lambda s: s.index)
    true_com = None
    if com is not None:
        c = frame.pixels_from_object(check_point(com, "com"))[0]
        true_com = (float(c[0]), float(c[1]))
    return Recording(mask, tuple(pushes_out), tuple(skipped), true_com, frame, radius, travel)


class _Window(NamedTuple):
    """One push's two streams and the window of pusher travel the push is taken over."""

    obj: np.ndarray
    """The object's poses, rows ``(t, x, y, yaw)``."""
    pusher: np.ndarray
    """The pusher's, likewise."""
    t_contact: float
    """Time of first contact: the window's start, seconds."""
    t_end: float
    """Time the window ends, seconds."""


def _push(frame, window: _Window, radius, standoff, centroid_m):
    """``(action_px, motion, speed, t_contact, t_end, deviation_m)`` of one push's window."""
    obj, pusher, t_contact, t_end = window
    pose0, pose1 = pose_at(obj, [t_contact, t_end])
    ends = to_frame(pose_at(pusher, [t_contact, t_end])[:, :2], pose0)
    chord = ends[1] - ends[0]
    unit = chord / np.hypot(*chord)
    lead = ends + radius * unit
    start = lead[0] - standoff * unit
    action = frame.pixels_from_object(np.vstack([start, lead[1]])).ravel()
    motion = _motion(frame, pose0, pose1, centroid_m)
    inside = (pusher[:, 0] >= t_contact) & (pusher[:, 0] <= t_end)
    path = to_frame(pusher[inside, 1:3], pose0)
    normal = np.array([-unit[1], unit[0]])
    deviation = float(np.abs((path - ends[0]) @ normal).max(initial=0.0))
    window = pusher[(pusher[:, 0] >= t_contact - 1e-12) & (pusher[:, 0] <= t_end + 1e-12)]
    steps = np.diff(window, axis=0)
    speeds = np.hypot(steps[:, 1], steps[:, 2]) / steps[:, 0]
    speed = float(np.median(speeds)) if len(speeds) else _mean_speed(t_contact, t_end, chord)
    return action, motion, speed, t_contact, t_end, deviation


def _motion(frame, pose0, pose1, centroid_m) -> Motion:
    """The rigid motion from ``pose0`` to ``pose1`` as :class:`Motion` defines it (pixels).

    The material point under the mask's centroid: where it is at ``pose1``, in the
    object's frame at ``pose0`` (metres, y up), then in pixels (y down).
    """
    c1, s1 = math.cos(pose1[2]), math.sin(pose1[2])
    turned = np.array(rotate_components(centroid_m[0], centroid_m[1], c1, s1, inverse=True))
    world1 = pose1[:2] + turned
    moved = to_frame(world1[None], pose0)[0] - centroid_m
    return Motion(pose1[2] - pose0[2], moved[0] / frame.resolution, -moved[1] / frame.resolution)


def _frames(frame, window: _Window, radius, centroid_m, rate) -> tuple:
    """The window's poses at ``rate`` Hz from first contact, as PushFrames (mask's frame)."""
    obj, pusher, t_contact, t_end = window
    times = t_contact + np.arange(1, int((t_end - t_contact) * rate) + 1) / rate
    times = times[times < t_end]
    if not len(times):
        return ()
    pose0 = pose_at(obj, [t_contact])[0]
    ends = to_frame(pose_at(pusher, [t_contact, t_end])[:, :2], pose0)
    unit = (ends[1] - ends[0]) / np.hypot(*(ends[1] - ends[0]))
    lead = to_frame(pose_at(pusher, times)[:, :2], pose0) + radius * unit
    lead_px = frame.pixels_from_object(lead)
    poses = pose_at(obj, times)
    return tuple(
        PushFrame((float(p[0]), float(p[1])), _motion(frame, pose0, pose, centroid_m))
        for p, pose in zip(lead_px, poses)
    )


def _mean_speed(t0: float, t1: float, chord: np.ndarray) -> float:
    """Mean speed over the window when too few samples fall inside it."""
    return float(np.hypot(*chord) / (t1 - t0)) if t1 > t0 else 0.0


def _check_on_mask(mask, kept, radius, names, skipped) -> list[RecordedPush]:
    """The kept pushes whose action starts off the mask and whose disc touches it."""
    if not kept:
        return []
    actions = np.array([k[1] for k in kept])
    line = contacts(mask, actions)
    disc = disc_contacts(mask, actions, radius)
    out = []
    for j, (i, action, motion, speed, t0, t1, deviation, frames) in enumerate(kept):
        if line.starts_inside[j] or disc.starts_inside[j]:
            skipped.append(
                SkippedPush(
                    i,
                    names[i],
                    "starts_inside",
                    "the action's start falls on the mask: use a larger standoff",
                )
            )
        elif not disc.hit[j]:
            skipped.append(
                SkippedPush(
                    i,
                    names[i],
                    "misses",
                    "within the contact tolerance of the outline, but the disc misses the mask "
                    "drawn at this resolution",
                )
            )
        else:
            out.append(
                RecordedPush(
                    i,
                    names[i],
                    Action(*action),
                    motion,
                    bool(line.hit[j]),
                    speed,
                    t0,
                    t1,
                    deviation,
                    frames,
                )
            )
    return out
