"""ROS bags (ROS 1 ``.bag``, rosbag2 in sqlite3 or MCAP) as comcore inputs.

Not imported by ``import comcore`` (needs rosbags: ``pip install comcore[ros]``). A robot that
pushes records the object's pose (motion capture, a tracker) and the pusher tip's on two topics
of :data:`SUPPORTED_TYPES`. :func:`poses_from_bag` reads one topic into rows ``(t, x, y, yaw)``,
checked; :func:`recording_from_bag` reads both, cuts the log into pushes
(:func:`comcore.recordings.split_pushes`) and makes a :class:`comcore.Recording`
(:func:`comcore.recording_from_poses`); :func:`bag_topics` lists a bag's topics;
:func:`images_from_bag` reads a camera topic (:data:`IMAGE_TYPES`) into arrays, for
:func:`comcore.mask_from_image` or a tag tracker. See docs/how-to/bag.md.

**Times** are seconds since the bag's first message's receive time, from the integer
nanoseconds. ``time="auto"`` (default) takes a topic's ``header.stamp`` (each transform's own in
a ``tf2_msgs/TFMessage``) when every one is nonzero, else the receive times; ``"header"`` or
``"receive"`` chooses. Times out of order by at most :data:`MAX_REORDER` are sorted; further
back, or repeated, they are refused. The object's pose is interpolated at the pusher's times.

**Poses** are read from above: the position's ``x``, ``y`` and the orientation's yaw about
``z``, unwrapped. The object's quaternions must have unit norm (within
:data:`QUATERNION_NORM_TOLERANCE`) and ``z`` within :data:`MAX_TILT` of vertical; the pusher's
orientation is neither used nor checked. Positions spanning more than :data:`MAX_SPAN` or
farther than :data:`MAX_DISTANCE` from the origin are refused as millimetres.

Examples
--------
:func:`recording_from_bag` on four pushes, ROS 2 messages written to MCAP (a 6 cm square plate
that does not move here; the tip comes from 2 cm away and goes 1.2 cm in, four times):

>>> import pathlib, tempfile, numpy as np
>>> from rosbags.rosbag2 import StoragePlugin, Writer
>>> from rosbags.typesys import Stores, get_typestore
>>> import comcore.recordings.bag as bag
>>> store = get_typestore(Stores.ROS2_HUMBLE)
>>> ros, kind = store.types, "geometry_msgs/msg/PoseStamped"
>>> def pose(ns, x, y):
...     stamp = ros["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
...     header = ros["std_msgs/msg/Header"](stamp=stamp, frame_id="world")
...     point = ros["geometry_msgs/msg/Point"](x=x, y=y, z=0.0)
...     turn = ros["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
...     body = ros["geometry_msgs/msg/Pose"](position=point, orientation=turn)
...     return store.serialize_cdr(ros[kind](header=header, pose=body), kind)
>>> path = pathlib.Path(tempfile.mkdtemp()) / "pushes"
>>> t = np.arange(801) / 100  # 8 s at 100 Hz
>>> tip_y = -0.054 + 0.015 * (1 - np.cos(np.pi * t))  # 3 cm up and back, 4 times
>>> with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
...     plate, tip = (writer.add_connection(c, kind, typestore=store) for c in ("/plate", "/tip"))
...     for ti, y in zip(t, tip_y):
...         ns = 10**9 + round(ti * 1e9)
...         writer.write(plate, ns, pose(ns, 0.0, 0.0))
...         writer.write(tip, ns, pose(ns, 0.01, float(y)))
>>> square = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
>>> rec = bag.recording_from_bag(path, "/plate", "/tip", square, 0.004, travel=0.01)
>>> len(rec.pushes), rec.pushes[1].name, rec.pushes[1].action.direction
(4, 'push 2 at 1.51 s', (0.0, -1.0))
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import NamedTuple

import numpy as np

from ..geometry._outline import check_outline
from ._bag_images import IMAGE_TYPES, BagImage, images_from_bag
from ._bag_reader import _Open, _topic_type
from ._outline_file import read_outline
from ._pose_streams import pusher_gaps, stream
from ._recording import DEFAULT_CONTACT_TOLERANCE_M, Recording, recording_from_poses
from ._splitting import DEFAULT_SEPARATION_M, split_pushes

__all__ = [
    "IMAGE_TYPES",
    "MAX_DISTANCE",
    "MAX_REORDER",
    "MAX_SPAN",
    "MAX_TILT",
    "QUATERNION_NORM_TOLERANCE",
    "SUPPORTED_TYPES",
    "TIME_SOURCES",
    "BagImage",
    "BagPoses",
    "bag_topics",
    "images_from_bag",
    "poses_from_bag",
    "recording_from_bag",
]

#: The message types a pose topic may hold (rosbags' names; ROS 1's are the same without
#: ``msg/``).
SUPPORTED_TYPES = (
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/TransformStamped",
    "tf2_msgs/msg/TFMessage",
    "nav_msgs/msg/Odometry",
)
#: Types whose messages name a child frame (``child_frame_id``).
_CHILD_FRAME_TYPES = SUPPORTED_TYPES[1:]
#: Where a topic's times come from (``time=``): the default first.
TIME_SOURCES = ("auto", "header", "receive")
#: Largest tilt (radians, 20 degrees) of the object's z axis from vertical: a flat object on a
#: table, tracked in a z-up frame, tilts by a few degrees at most.
MAX_TILT = math.radians(20.0)
#: Largest time (seconds) a message's stamp may lie before an earlier message's: within it the
#: messages are sorted by time (a tracker's stamps jitter by a few milliseconds), beyond it
#: the times are refused as not increasing (a clock that jumped back).
MAX_REORDER = 0.1
#: Largest difference of a quaternion's norm from 1 (they are written normalised).
QUATERNION_NORM_TOLERANCE = 1e-3
#: Largest span (metres) of a topic's positions along x or y: a tabletop, a lab.
MAX_SPAN = 10.0
#: Largest distance (metres) of a topic's position from its frame's origin.
MAX_DISTANCE = 100.0


class BagPoses(NamedTuple):
    """One topic's poses, as :func:`poses_from_bag` reads them."""

    poses: np.ndarray
    """Rows ``(t, x, y, yaw)``, shape (n, 4), read-only: seconds since the bag's start,
    metres, radians (counter-clockwise seen from above, unwrapped)."""
    frame_id: str
    """The frame the poses are in (the headers' ``frame_id``)."""
    child_frame_id: str
    """The frame whose poses they are, for types that name it; ``""`` otherwise."""
    msgtype: str
    """The topic's message type (one of :data:`SUPPORTED_TYPES`)."""
    time_source: str
    """``"header"`` or ``"receive"``: where the times came from."""
    start_ns: int = 0
    """The bag's start (its first message's receive time), nanoseconds since the epoch: the
    time 0 of ``poses``."""


def bag_topics(path) -> dict[str, str]:
    """The topics of a bag and their message types, sorted by topic.

    Parameters
    ----------
    path : str or os.PathLike
        A ROS 1 ``.bag`` file, or a rosbag2 folder (sqlite3 or MCAP).

    Returns
    -------
    dict of str to str
        ``{topic: message type}``, in rosbags' names (``geometry_msgs/msg/PoseStamped``).

    Raises
    ------
    ValueError
        If there is no such bag, or it cannot be read.
    ImportError
        Without rosbags (``pip install comcore[ros]``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from rosbags.rosbag1 import Writer
    >>> from rosbags.typesys import Stores, get_typestore
    >>> import comcore.recordings.bag as bag
    >>> store = get_typestore(Stores.ROS1_NOETIC)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "empty.bag"
    >>> with Writer(path) as writer:
    ...     _ = writer.add_connection("/tip", "geometry_msgs/msg/PoseStamped", typestore=store)
    >>> bag.bag_topics(path)
    {'/tip': 'geometry_msgs/msg/PoseStamped'}
    """
    with _Open(path) as reader:
        return {topic: reader.topics[topic].msgtype for topic in sorted(reader.topics)}


def _entries(msg, msgtype: str):
    """``(stamp_ns, frame_id, child_frame_id, position, orientation)`` of one message's poses."""
    if msgtype == "tf2_msgs/msg/TFMessage":
        for tr in msg.transforms:
            yield from _entries(tr, "geometry_msgs/msg/TransformStamped")
        return
    if msgtype == "geometry_msgs/msg/PoseStamped":
        child, position, orientation = "", msg.pose.position, msg.pose.orientation
    elif msgtype == "geometry_msgs/msg/TransformStamped":
        child, position, orientation = (
            msg.child_frame_id,
            msg.transform.translation,
            msg.transform.rotation,
        )
    else:  # nav_msgs/msg/Odometry
        pose = msg.pose.pose
        child, position, orientation = msg.child_frame_id, pose.position, pose.orientation
    stamp = msg.header.stamp
    yield (
        int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec),
        msg.header.frame_id,
        child,
        (position.x, position.y),
        (orientation.x, orientation.y, orientation.z, orientation.w),
    )


def _same_frame(a: str, b: str) -> bool:
    """Frame names equal but for a leading ``/`` (ROS 1's ``/world`` is ``world``)."""
    return a.lstrip("/") == b.lstrip("/")


def poses_from_bag(
    path,
    topic: str,
    *,
    child_frame: str | None = None,
    check_orientation: bool = True,
    time: str = "auto",
) -> BagPoses:
    """Read one topic's poses as rows ``(t, x, y, yaw)``, checked (see the module's docstring).

    Parameters
    ----------
    path : str or os.PathLike
        A ROS 1 ``.bag`` file, or a rosbag2 folder (sqlite3 or MCAP).
    topic : str
        A topic holding one of :data:`SUPPORTED_TYPES`.
    child_frame : str, optional
        For transforms and odometry: the ``child_frame_id`` to read (a leading
        ``/`` does not matter); needed when the topic carries several (``/tf``).
    check_orientation : bool, optional
        Check the quaternions (default True; :func:`recording_from_bag` does not
        check the pusher's). A zero quaternion unchecked gives the yaw 0.
    time : {"auto", "header", "receive"}, optional
        Where the times come from (:data:`TIME_SOURCES`; default ``"auto"``).

    Returns
    -------
    BagPoses
        With ``start_ns``, the bag's start: time 0 of the rows.

    Raises
    ------
    ValueError
        Each naming the topic: not in the bag, of a type not supported, empty,
        a child frame needed or not seen, poses in several frames, times not
        increasing, millimetres, a quaternion not of unit norm or not about ``z``.
    ImportError
        Without rosbags (``pip install comcore[ros]``).

    Examples
    --------
    >>> import pathlib, tempfile  # a tip's pose at 100 Hz, to a ROS 1 bag and back
    >>> from rosbags.rosbag1 import Writer
    >>> from rosbags.typesys import Stores, get_typestore
    >>> import comcore.recordings.bag as bag
    >>> store = get_typestore(Stores.ROS1_NOETIC)
    >>> ros, path = store.types, pathlib.Path(tempfile.mkdtemp()) / "tip.bag"
    >>> with Writer(path) as writer:
    ...     tip = writer.add_connection("/tip", "geometry_msgs/msg/PoseStamped", typestore=store)
    ...     for k in range(3):
    ...         ns = 1_700_000_000_000_000_000 + 10_000_000 * k
    ...         stamp = ros["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
    ...         header = ros["std_msgs/msg/Header"](seq=k, stamp=stamp, frame_id="world")
    ...         point = ros["geometry_msgs/msg/Point"](x=0.01 * k, y=0.2, z=0.0)
    ...         turn = ros["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
    ...         pose = ros["geometry_msgs/msg/Pose"](position=point, orientation=turn)
    ...         msg = ros["geometry_msgs/msg/PoseStamped"](header=header, pose=pose)
    ...         data = store.serialize_ros1(msg, "geometry_msgs/msg/PoseStamped")
    ...         writer.write(tip, ns, data)
    >>> read = bag.poses_from_bag(path, "/tip")
    >>> read.poses.round(3).tolist(), read.frame_id, read.time_source, read.start_ns
    ([[0.0, 0.0, 0.2, 0.0], [0.01, 0.01, 0.2, 0.0], [0.02, 0.02, 0.2, 0.0]], 'world', 'header', 1700000000000000000)
    >>> bag.poses_from_bag(path, "/object")
    Traceback (most recent call last):
    ...
    ValueError: topic '/object' is not in ...tip.bag; its topics: /tip (geometry_msgs/msg/PoseStamped)
    """  # noqa: E501
    if time not in TIME_SOURCES:
        raise ValueError(f"time must be one of {TIME_SOURCES}, got {time!r}")
    if not isinstance(topic, str):
        raise TypeError(f"topic must be a str, got {type(topic).__name__}")
    if child_frame is not None and not isinstance(child_frame, str):
        raise TypeError(f"child_frame must be a str or None, got {type(child_frame).__name__}")
    with _Open(path) as reader:
        msgtype = _topic_type(reader, path, topic, SUPPORTED_TYPES, "a pose comcore reads")
        if child_frame is not None and msgtype not in _CHILD_FRAME_TYPES:
            raise ValueError(
                f"child_frame is for topics of transforms or odometry; topic {topic!r} holds "
                f"{msgtype}, which names no child frame"
            )
        start = int(reader.start_time)
        rows: list[tuple] = []
        connections = [c for c in reader.connections if c.topic == topic]
        for connection, received, raw in reader.messages(connections=connections):
            msg = reader.deserialize(raw, connection.msgtype)
            rows.extend((int(received), *e) for e in _entries(msg, msgtype))
    if not rows:
        raise ValueError(f"topic {topic!r} holds no message")
    rows = _of_child(rows, topic, child_frame, msgtype)
    return _poses(rows, topic, msgtype, start, check_orientation, time)


def _of_child(rows: list, topic: str, child_frame: str | None, msgtype: str) -> list:
    """The rows of the child frame asked for (or the only one)."""
    if msgtype not in _CHILD_FRAME_TYPES:
        return rows
    seen = sorted({r[3] for r in rows})
    if child_frame is None:
        if len(seen) > 1:
            raise ValueError(
                f"topic {topic!r} carries the poses of {len(seen)} child frames: give the child "
                f"frame to read (child_frame=, --object-child-frame, --pusher-child-frame), one "
                f"of {seen}"
            )
        return rows
    chosen = [r for r in rows if _same_frame(r[3], child_frame)]
    if not chosen:
        raise ValueError(
            f"topic {topic!r} carries no pose of the child frame {child_frame!r}; the child "
            f"frames it carries: {seen}"
        )
    return chosen


def _poses(rows, topic, msgtype, start, check_orientation, time) -> BagPoses:
    """The checked rows ``(t, x, y, yaw)`` of ``(received, stamp, frame, child, xy, q)``."""
    frames = sorted({r[2] for r in rows})
    if len({f.lstrip("/") for f in frames}) > 1:
        raise ValueError(f"topic {topic!r} holds poses in several frames: {frames}")
    t, order, source = _times(rows, topic, start, time)
    rows = [rows[i] for i in order]
    xy = np.array([r[4] for r in rows], dtype=float)
    bad = np.flatnonzero(~np.isfinite(xy).all(axis=1))
    if len(bad):
        raise ValueError(
            f"topic {topic!r}: the position of message {int(order[bad[0]])} is not finite "
            f"({xy[bad[0]].tolist()}); {len(bad)} message(s) so"
        )
    _check_metres(xy, topic)
    q = np.array([r[5] for r in rows], dtype=float)
    if check_orientation:
        _check_quaternions(q, topic, order)
    norm = np.linalg.norm(q, axis=1)
    usable = np.isfinite(norm) & (norm > 0)  # unchecked, a zero or NaN quaternion: yaw 0
    unit = np.where(usable[:, None], q, [0.0, 0.0, 0.0, 1.0]) / np.where(usable, norm, 1.0)[:, None]
    x, y, z, w = unit.T
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    poses = np.column_stack([t, xy, np.unwrap(yaw)])
    poses.setflags(write=False)
    child = rows[0][3] if msgtype in _CHILD_FRAME_TYPES else ""
    return BagPoses(poses, frames[0], child, msgtype, source, start)


def _times(rows, topic: str, start: int, time: str) -> tuple[np.ndarray, np.ndarray, str]:
    """Seconds since ``start`` of each row, sorted; the order; the source (header, receive)."""
    received = np.array([r[0] for r in rows], dtype=np.int64)
    stamps = np.array([r[1] for r in rows], dtype=np.int64)
    source = time
    if time == "auto":
        source = "header" if np.all(stamps != 0) else "receive"
    elif time == "header" and np.any(stamps == 0):
        raise ValueError(
            f"topic {topic!r}: {int(np.sum(stamps == 0))} of its header stamps are zero "
            "(time='receive' uses the bag's receive times)"
        )
    t = ((stamps if source == "header" else received) - start) * 1e-9
    hint = " (time='receive' uses the bag's receive times)" if source == "header" else ""
    behind = np.maximum.accumulate(t) - t
    if behind.max() > MAX_REORDER:
        k = int(np.argmax(behind > MAX_REORDER))
        raise ValueError(
            f"topic {topic!r}: its {source} times are not increasing: message {k} is at "
            f"{t[k]:.9f} s, {behind[k]:.3g} s before an earlier message's (out of order by "
            f"at most {MAX_REORDER:g} s is sorted){hint}"
        )
    order = np.argsort(t, kind="stable")
    t = t[order]
    repeated = np.flatnonzero(np.diff(t) == 0)
    if len(repeated):
        k = int(order[repeated[0] + 1])
        raise ValueError(
            f"topic {topic!r}: its {source} times are not increasing: message {k} repeats the "
            f"time {t[repeated[0]]:.9f} s ({len(repeated)} repeated){hint}"
        )
    return t, order, source


def _check_metres(xy: np.ndarray, topic: str) -> None:
    """Refuse positions that look like millimetres (:data:`MAX_SPAN`, :data:`MAX_DISTANCE`)."""
    span = float(np.ptp(xy, axis=0).max())
    distance = float(np.hypot(xy[:, 0], xy[:, 1]).max())
    if span > MAX_SPAN or distance > MAX_DISTANCE:
        raise ValueError(
            f"topic {topic!r}: its positions span {span:.4g} m and lie up to {distance:.4g} m "
            f"from the frame's origin (at most {MAX_SPAN:g} m and {MAX_DISTANCE:g} m are "
            "believed): are they in millimetres? comcore reads metres"
        )


def _check_quaternions(q: np.ndarray, topic: str, index: np.ndarray) -> None:
    """Unit norm, and a rotation about z (the object's z axis near vertical).

    ``index``: each row's message number in the bag, for the messages.
    """
    norm = np.linalg.norm(q, axis=1)
    bad = np.flatnonzero(~(np.abs(norm - 1.0) <= QUATERNION_NORM_TOLERANCE))  # NaN too
    if len(bad):
        k = int(bad[0])
        raise ValueError(
            f"topic {topic!r}: the orientation of message {int(index[k])} has norm "
            f"{norm[k]:.6g}, not 1 "
            f"(x, y, z, w = {', '.join(f'{v:.6g}' for v in q[k])}); {len(bad)} message(s) so"
        )
    x, y = q[:, 0] / norm, q[:, 1] / norm
    tilt = np.arccos(np.clip(1 - 2 * (x * x + y * y), -1.0, 1.0))  # the z axis from vertical
    bad = np.flatnonzero(tilt > MAX_TILT)
    if len(bad):
        k = int(bad[0])
        axis = "x" if abs(x[k]) >= abs(y[k]) else "y"
        raise ValueError(
            f"topic {topic!r}: the orientation of message {int(index[k])} tilts the object's z "
            f"axis {math.degrees(tilt[k]):.1f} degrees from vertical (at most "
            f"{math.degrees(MAX_TILT):g}): its rotation is about {axis}, not z: is the frame "
            f"z-up? ({len(bad)} message(s) so)"
        )


def recording_from_bag(
    path,
    object_topic: str,
    pusher_topic: str,
    outline,
    pusher_radius: float,
    *,
    object_child_frame: str | None = None,
    pusher_child_frame: str | None = None,
    time: str = "auto",
    separation: float = DEFAULT_SEPARATION_M,
    **options,
) -> Recording:
    """Read a bag's object and pusher poses into a :class:`comcore.Recording`.

    The two topics are read by :func:`poses_from_bag` (the object's
    orientation checked, the pusher's not used), cut into pushes where the
    pusher is more than ``separation`` from the object
    (:func:`comcore.recordings.split_pushes`), and turned into the mask,
    actions and motions by :func:`comcore.recording_from_poses`, which
    interpolates the object's pose linearly at the pusher's times. Pushes are
    named ``"push <k> at <t> s"`` (``k`` from 1, ``t`` the piece's first
    pusher time since the bag's start).

    Parameters
    ----------
    path : str or os.PathLike
        A ROS 1 ``.bag`` file, or a rosbag2 folder (sqlite3 or MCAP).
    object_topic, pusher_topic : str
        The topics of the object's pose and of the pusher tip's centre, in one
        frame (``z`` up, metres).
    outline : array_like, shape (k, 2), or str or os.PathLike
        The object's outline in its own frame (the frame of the object
        topic's poses), metres, or a file :func:`comcore.recordings.read_outline`
        reads (a polygon CSV or a mesh).
    pusher_radius : float
        Radius of the round pusher's tip, metres (>= 0).
    object_child_frame, pusher_child_frame : str, optional
        The child frames to read, for topics of transforms (``/tf``) that carry several.
    time : {"auto", "header", "receive"}, optional
        Where the times come from (see :func:`poses_from_bag`).
    separation : float, optional
        Gap (metres) past which the pusher has left the object: where the log
        is cut (default 5 mm).
    **options
        Passed to :func:`comcore.recording_from_poses`: ``travel``,
        ``resolution``, ``com``, ``margin``, ``standoff``, ``contact_tolerance``
        (the last is the splitting's too).

    Returns
    -------
    Recording
        With ``time_origin_ns``, the bag's start (its ``stamp``: the end of the
        last push kept, in ROS time). The module's docstring has an example.

    Raises
    ------
    ValueError
        As :func:`poses_from_bag`, naming the topic; if the two topics' frames
        differ, or the pusher never touches the object.
    TypeError
        For an option :func:`comcore.recording_from_poses` does not take, or ``names``.
    ImportError
        Without rosbags (``pip install comcore[ros]``).
    """
    if "names" in options:
        raise TypeError("recording_from_bag names the pushes itself: names is not an option")
    if isinstance(outline, (str, os.PathLike)):
        outline = read_outline(outline)
    poly = check_outline(outline)
    obj = poses_from_bag(path, object_topic, child_frame=object_child_frame, time=time)
    pusher = poses_from_bag(
        path, pusher_topic, child_frame=pusher_child_frame, check_orientation=False, time=time
    )
    if obj.frame_id and pusher.frame_id and not _same_frame(obj.frame_id, pusher.frame_id):
        raise ValueError(
            f"the object's poses (topic {object_topic!r}) are in the frame {obj.frame_id!r}, the "
            f"pusher's (topic {pusher_topic!r}) in {pusher.frame_id!r}: comcore takes both in "
            "one frame"
        )
    tolerance = options.get("contact_tolerance", DEFAULT_CONTACT_TOLERANCE_M)
    pieces = split_pushes(
        poly,
        obj.poses,
        pusher.poses,
        pusher_radius,
        separation=separation,
        contact_tolerance=tolerance,
    )
    if not pieces:
        _, gap = pusher_gaps(poly, stream(obj.poses, "object"), pusher.poses, pusher_radius)
        closest = f"{gap.min():.3g} m" if len(gap) else "nothing: no time in common"
        raise ValueError(
            f"the pusher (topic {pusher_topic!r}) never comes within contact_tolerance "
            f"({tolerance:g} m) of the object's outline (topic {object_topic!r}) while the "
            f"object's poses last (the closest: {closest}): are both in one frame, and the "
            "outline in the object's?"
        )
    names = [f"push {k + 1} at {round(p[0, 0], 2) + 0.0:.2f} s" for k, (_, p) in enumerate(pieces)]
    rec = recording_from_poses(poly, pieces, pusher_radius, names=names, **options)
    return dataclasses.replace(rec, time_origin_ns=obj.start_ns)
