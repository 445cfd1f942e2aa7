"""Pushes of a simulated plate, logged and written to ROS bags with rosbags' own writers.

:func:`simulated_log` pushes a convex plate 20 times with the exact simulator (each push
from where the last left it) and logs the plate's pose at 100 Hz and the pusher tip's
centre at 125 Hz, as one robot's log would: approach, push, retract, then around the plate
at 12 cm to the next push. :func:`write_bag` writes such streams as ROS 1, rosbag2 sqlite3 or
MCAP, in each message type comcore reads. Times are integer nanoseconds throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: A convex plate (metres), centred on its area centroid (the uniform plate's CoM).
PLATE = np.array([(0.05, 0.0), (0.02, 0.045), (-0.04, 0.035), (-0.05, -0.02), (0.01, -0.05)])
RADIUS = 0.005
SPEED = 0.1  # m/s while approaching, pushing and retracting
TRANSFER_SPEED = 0.5  # m/s around the plate
PUSH_M = 0.032  # the leading point's travel past the face (a whole number of blocks)
APPROACH_M = 0.02
STANDOFF_M = 0.01
ORBIT_M = 0.12
OBJECT_PERIOD_NS = 10_000_000  # 100 Hz
PUSHER_PERIOD_NS = 8_000_000  # 125 Hz
BLOCK_NS = 40_000_000  # every segment lasts a whole number of both periods
START_NS = 1_700_000_000_000_000_000
OBJECT_LATENCY_NS = 3_000_000  # header stamp to the bag's receive time
PUSHER_LATENCY_NS = 1_000_000


def centred(poly) -> np.ndarray:
    poly = np.asarray(poly, float)
    cross = poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]
    centroid = ((poly + np.roll(poly, -1, axis=0)) * cross[:, None]).sum(axis=0) / (3 * cross.sum())
    return poly - centroid


OUTLINE = centred(PLATE)


@dataclass
class Log:
    """A simulated log: the streams (ns, x, y, yaw) and what the simulator did."""

    object_ns: np.ndarray  # int64 stamps
    object_poses: np.ndarray  # (n, 3) x, y, yaw
    pusher_ns: np.ndarray
    pusher_xy: np.ndarray  # (m, 2)
    motions: np.ndarray  # (20, 3): the simulator's, in the object's frame at each push's start
    start_poses: np.ndarray  # (20, 3)

    def object_rows(self, origin_ns: int = START_NS) -> np.ndarray:
        return np.column_stack([(self.object_ns - origin_ns) * 1e-9, self.object_poses])

    def pusher_rows(self, origin_ns: int = START_NS) -> np.ndarray:
        t = (self.pusher_ns - origin_ns) * 1e-9
        return np.column_stack([t, self.pusher_xy, np.zeros(len(t))])


def _rot(yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def _duration(length: float, speed: float) -> int:
    """ns for ``length`` at ``speed``, rounded up to whole blocks."""
    return max(1, math.ceil(length / speed * 1e9 / BLOCK_NS)) * BLOCK_NS


class _Path:
    """Piecewise-linear knots (ns, values...) of a stream."""

    def __init__(self, t0: int, value):
        self.t = [t0]
        self.v = [np.asarray(value, float)]

    def to(self, duration: int, value) -> None:
        self.t.append(self.t[-1] + duration)
        self.v.append(np.asarray(value, float))

    def sample(self, period: int, end: int) -> tuple[np.ndarray, np.ndarray]:
        ns = np.arange(self.t[0], end + 1, period, dtype=np.int64)
        knots = np.array(self.t, dtype=np.int64) - self.t[0]
        values = np.array(self.v)
        rel = (ns - self.t[0]).astype(float)
        cols = [np.interp(rel, knots.astype(float), values[:, k]) for k in range(values.shape[1])]
        return ns, np.column_stack(cols)


def simulated_log(n_pushes: int = 20, seed: int = 3) -> Log:
    """Push the plate ``n_pushes`` times with the exact simulator; the log of it all."""
    from tests.extras import require_simulators

    simulators = require_simulators()
    from comcore.conventions import object_motion_from_camera

    sim = simulators.PushSimulator.from_polygon(OUTLINE, mu_contact=0.3, pusher_radius=RADIUS)
    rng = np.random.default_rng(seed)
    pose = np.array([0.3, -0.1, 0.4])
    n_faces = len(OUTLINE)
    tip = _Path(START_NS, [0.0, 0.0])  # replaced below
    plate = _Path(START_NS, pose)
    motions, starts = [], []
    first = True
    for k in range(n_pushes):
        face = (2 * k + int(rng.integers(0, 2))) % n_faces
        a, b = OUTLINE[face], OUTLINE[(face + 1) % n_faces]
        edge = b - a
        inward = np.array([-edge[1], edge[0]]) / np.hypot(*edge)  # CCW outline: inward normal
        contact = a + rng.uniform(0.3, 0.7) * edge
        rot = _rot(pose[2])
        world = lambda p, rot=rot, pose=pose: rot @ p + pose[:2]  # noqa: E731
        approach = world(contact - (RADIUS + APPROACH_M) * inward)
        touch = world(contact - RADIUS * inward)
        if first:
            tip = _Path(START_NS, approach)
            tip.to(5 * BLOCK_NS, approach)  # rests 0.2 s
            first = False
        else:
            _orbit_to(tip, plate.v[-1][:2], approach)
        # the plate rests until contact
        contact_ns = tip.t[-1] + _duration(APPROACH_M, SPEED)
        tip.to(contact_ns - tip.t[-1], touch)
        plate.to(contact_ns - plate.t[-1], pose)
        lead = np.array([world(contact - STANDOFF_M * inward), world(contact + PUSH_M * inward)])
        result = sim.push(sim.to_pixels(lead).ravel(), pose=tuple(pose), record=True)
        traj = np.asarray(result.trajectory)
        steps = len(traj) - 1
        push_ns = _duration(PUSH_M, SPEED)
        assert push_ns == round(PUSH_M / SPEED * 1e9)
        for j in range(1, steps + 1):
            plate.t.append(contact_ns + round(j * push_ns / steps))
            plate.v.append(traj[j])
        direction = rot @ inward
        tip.to(push_ns, touch + PUSH_M * direction)
        tip.to(_duration(APPROACH_M, SPEED), touch + (PUSH_M - APPROACH_M) * direction)
        starts.append(pose.copy())
        motions.append(object_motion_from_camera(result.motion, pose[2]))
        pose = traj[-1].copy()
        plate.t[-1] = contact_ns + push_ns  # exactly
    tip.to(5 * BLOCK_NS, tip.v[-1])
    end = tip.t[-1]
    plate.to(end - plate.t[-1], pose)
    object_ns, object_poses = plate.sample(OBJECT_PERIOD_NS, end)
    pusher_ns, pusher_xy = tip.sample(PUSHER_PERIOD_NS, end)
    return Log(object_ns, object_poses, pusher_ns, pusher_xy, np.array(motions), np.array(starts))


def _orbit_to(tip: _Path, centre, target) -> None:
    """Out to ORBIT_M around ``centre``, along the circle, in to ``target``."""
    here = tip.v[-1]
    out_angle = math.atan2(*(here - centre)[::-1])
    in_angle = math.atan2(*(target - centre)[::-1])
    out = centre + ORBIT_M * np.array([math.cos(out_angle), math.sin(out_angle)])
    tip.to(_duration(np.hypot(*(out - here)), TRANSFER_SPEED), out)
    turn = (in_angle - out_angle + math.pi) % (2 * math.pi) - math.pi
    arc_ns = _duration(abs(turn) * ORBIT_M, TRANSFER_SPEED)
    n = arc_ns // PUSHER_PERIOD_NS
    for j in range(1, n + 1):
        angle = out_angle + turn * j / n
        tip.to(PUSHER_PERIOD_NS, centre + ORBIT_M * np.array([math.cos(angle), math.sin(angle)]))
    tip.to(_duration(np.hypot(*(tip.v[-1] - target)), TRANSFER_SPEED), target)


# -- writing bags ------------------------------------------------------------------------------

FORMATS = ("rosbag1", "sqlite3", "mcap")
POSE_TYPES = {
    "/plate/pose": "geometry_msgs/msg/PoseStamped",
    "/plate/transform": "geometry_msgs/msg/TransformStamped",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/plate/odom": "nav_msgs/msg/Odometry",
}
TIP_TOPIC = "/tip"
TIP_FRAME = "tool"  # the tip's child frame in /tf
PLATE_FRAME = "plate"


def quaternion_z(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


#: A tool pointing down: half a turn about x (its orientation is not used).
DOWN = (1.0, 0.0, 0.0, 0.0)


class BagWriter:
    """``rosbags``' writer for one format, with messages built from pose rows."""

    def __init__(self, path: Path, fmt: str):
        from rosbags.typesys import Stores, get_typestore

        self.fmt = fmt
        self.ros1 = fmt == "rosbag1"
        self.store = get_typestore(Stores.ROS1_NOETIC if self.ros1 else Stores.ROS2_HUMBLE)
        if "tf2_msgs/msg/TFMessage" not in self.store.types:  # not in rosbags' ROS 1 store
            from rosbags.typesys import get_types_from_msg

            self.store.register(
                get_types_from_msg(
                    "geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"
                )
            )
        self.types = self.store.types
        if self.ros1:
            from rosbags.rosbag1 import Writer

            self.writer = Writer(path)
        else:
            from rosbags.rosbag2 import StoragePlugin, Writer

            plugin = StoragePlugin.MCAP if fmt == "mcap" else StoragePlugin.SQLITE3
            self.writer = Writer(path, version=9, storage_plugin=plugin)
        self.connections: dict[str, object] = {}

    def __enter__(self):
        self.writer.open()
        return self

    def __exit__(self, *exc):
        self.writer.close()

    def connect(self, topic: str, msgtype: str):
        if topic not in self.connections:
            self.connections[topic] = self.writer.add_connection(
                topic, msgtype, typestore=self.store
            )
        return self.connections[topic]

    def write(self, topic: str, msgtype: str, received_ns: int, msg) -> None:
        conn = self.connect(topic, msgtype)
        if self.ros1:
            data = self.store.serialize_ros1(msg, msgtype)
        else:
            data = self.store.serialize_cdr(msg, msgtype)
        self.writer.write(conn, int(received_ns), data)

    # message builders
    def header(self, stamp_ns: int, frame_id: str):
        t = self.types
        stamp = t["builtin_interfaces/msg/Time"](
            sec=int(stamp_ns) // 1_000_000_000, nanosec=int(stamp_ns) % 1_000_000_000
        )
        if self.ros1:
            return t["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id=frame_id)
        return t["std_msgs/msg/Header"](stamp=stamp, frame_id=frame_id)

    def pose(self, x, y, q, z=0.0):
        t = self.types
        return t["geometry_msgs/msg/Pose"](
            position=t["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=float(z)),
            orientation=t["geometry_msgs/msg/Quaternion"](
                x=float(q[0]), y=float(q[1]), z=float(q[2]), w=float(q[3])
            ),
        )

    def transform_stamped(self, stamp_ns, frame_id, child, x, y, q, z=0.0):
        t = self.types
        tf = t["geometry_msgs/msg/Transform"](
            translation=t["geometry_msgs/msg/Vector3"](x=float(x), y=float(y), z=float(z)),
            rotation=t["geometry_msgs/msg/Quaternion"](
                x=float(q[0]), y=float(q[1]), z=float(q[2]), w=float(q[3])
            ),
        )
        return t["geometry_msgs/msg/TransformStamped"](
            header=self.header(stamp_ns, frame_id), child_frame_id=child, transform=tf
        )

    def message(self, msgtype, stamp_ns, frame_id, child, x, y, q, z=0.0):
        t = self.types
        if msgtype == "geometry_msgs/msg/PoseStamped":
            return t[msgtype](header=self.header(stamp_ns, frame_id), pose=self.pose(x, y, q, z))
        if msgtype == "geometry_msgs/msg/TransformStamped":
            return self.transform_stamped(stamp_ns, frame_id, child, x, y, q, z)
        if msgtype == "tf2_msgs/msg/TFMessage":
            return t[msgtype](
                transforms=[self.transform_stamped(stamp_ns, frame_id, child, x, y, q, z)]
            )
        if msgtype == "nav_msgs/msg/Odometry":
            cov = np.zeros(36)
            twist = t["geometry_msgs/msg/Twist"](
                linear=t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                angular=t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
            )
            return t[msgtype](
                header=self.header(stamp_ns, frame_id),
                child_frame_id=child,
                pose=t["geometry_msgs/msg/PoseWithCovariance"](
                    pose=self.pose(x, y, q, z), covariance=cov
                ),
                twist=t["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=cov),
            )
        raise ValueError(msgtype)


def write_bag(path, fmt: str, log: Log, *, types=tuple(POSE_TYPES), tip_in_tf: bool = True) -> Path:
    """The log as a bag: the plate on each topic of ``types`` and the tip on /tip (and /tf).

    Header stamps are the log's times; the bag receives each message a latency later.
    Messages are written in receive-time order.
    """
    path = Path(path)
    events = []
    for k, ns in enumerate(log.object_ns):
        x, y, yaw = log.object_poses[k]
        for topic in types:
            events.append(
                (int(ns) + OBJECT_LATENCY_NS, topic, int(ns), PLATE_FRAME, x, y, quaternion_z(yaw))
            )
    for k, ns in enumerate(log.pusher_ns):
        x, y = log.pusher_xy[k]
        events.append((int(ns) + PUSHER_LATENCY_NS, TIP_TOPIC, int(ns), TIP_FRAME, x, y, DOWN))
        if tip_in_tf:
            events.append((int(ns) + PUSHER_LATENCY_NS, "/tf", int(ns), TIP_FRAME, x, y, DOWN))
    events.sort(key=lambda e: e[0])
    with BagWriter(path, fmt) as writer:
        for received, topic, stamp, child, x, y, q in events:
            msgtype = POSE_TYPES.get(topic, "geometry_msgs/msg/PoseStamped")
            msg = writer.message(msgtype, stamp, "world", child, x, y, q, z=0.01)
            writer.write(topic, msgtype, received, msg)
    return path


def bag_start_ns(log: Log, types=tuple(POSE_TYPES)) -> int:
    """The bag's start (its first receive time), as the reader's times count from it."""
    first = [int(log.pusher_ns[0]) + PUSHER_LATENCY_NS]
    if types:
        first.append(int(log.object_ns[0]) + OBJECT_LATENCY_NS)
    return min(first)


def small_bag(path, fmt: str, topics: dict, *, frame_id: str = "world") -> Path:
    """A bag of hand-made messages: ``{topic: (msgtype, [(received_ns, stamp_ns, child, x, y, q), ...])}``."""
    path = Path(path)
    events = [
        (row[0], topic, msgtype, row) for topic, (msgtype, rows) in topics.items() for row in rows
    ]
    events.sort(key=lambda e: e[0])
    with BagWriter(path, fmt) as writer:
        for topic, (msgtype, _) in topics.items():
            writer.connect(topic, msgtype)
        for received, topic, msgtype, (_, stamp, child, x, y, q) in events:
            writer.write(
                topic, msgtype, received, writer.message(msgtype, stamp, frame_id, child, x, y, q)
            )
    return path


#: The recording's window: from first contact (the disc 2 mm from the face, the default
#: contact tolerance) to the push's end, a hair short so that it ends on the push.
TRAVEL = (0.002 + PUSH_M) * (1 - 1e-9)
