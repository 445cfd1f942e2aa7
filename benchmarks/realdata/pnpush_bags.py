"""The pnpush project's preliminary ROS 1 bags through comcore.recordings.bag.

Peter K.-T. Yu's pnpush repository (github.com/peterkty/pnpush) holds 22 bags of an ABB
arm pushing three blocks tracked by Vicon, under
``catkin_ws/src/pnpush_planning/preliminary_push_testing/{Al_block,Plastic_block,St_block}/``,
and the steel block's mesh as ``catkin_ws/src/pnpush_config/models/object_meshes/SteelBlock.stl``.
Extract them anywhere (``git show HEAD:PATH > FILE`` in a clone) and pass the folder: the bags
(any names ending in ``.bag``) and ``SteelBlock.stl`` beside them.

Per bag: the topics' types, rates and frames (:func:`comcore.recordings.bag.poses_from_bag`),
the Vicon quaternions' tilt from vertical, whether ``recording_from_bag`` finds pushes as
recorded, and, with the object's poses moved into the tip's frame by the bag's own ``/tf``
chain (``map`` -> ``/viconworld`` -> ``/world`` or ``/objworld``), the contacts
:func:`comcore.recordings.split_pushes` finds with the steel block's outline and a 4.75 mm
tip. Then every steel-block push, of all bags together, through
:func:`comcore.recording_from_poses` and :func:`comcore.estimate_posterior` (with the limit
surface and with the Voting Theorem alone). The blocks' true CoMs are not in the repository.

Usage::

    PYTHONPATH=. nice -n 10 python benchmarks/realdata/pnpush_bags.py /tmp/pnpush
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

import comcore
import comcore.recordings.bag as bag
from comcore.recordings import read_outline, split_pushes

#: The tip's radius (metres): pnpush's probe2 (push_straight.py: ``probe_radius = 0.004745``).
RADIUS = 0.00475
#: The tip's topic, and the frame its poses are in (its header names none).
TIP_TOPIC = "/tip_pose"
TIP_FRAME = "map"


def vicon_topic(topics: dict) -> str:
    """The Vicon object's topic: ``/vicon/<name>/<name>``."""
    return next(t for t in topics if t.startswith("/vicon/") and t != "/vicon/markers")


def frame_in(path, frame: str, root: str = TIP_FRAME) -> np.ndarray:
    """``(x, y, yaw)`` of ``frame`` in ``root``, composed from the first of each /tf link."""
    from rosbags.highlevel import AnyReader

    links = {}
    with AnyReader([Path(path)]) as reader:
        connections = [c for c in reader.connections if c.topic == "/tf"]
        for connection, _, raw in reader.messages(connections=connections):
            for tr in reader.deserialize(raw, connection.msgtype).transforms:
                links.setdefault(tr.child_frame_id, (tr.header.frame_id, tr.transform))
    pose = np.zeros(3)
    while frame != root:
        if frame not in links:
            raise ValueError(f"{path}: /tf does not link {frame!r} to {root!r}")
        frame, tf = links[frame]
        q = tf.rotation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2))
        c, s = math.cos(yaw), math.sin(yaw)
        x, y = pose[:2]
        pose = np.array([c * x - s * y + tf.translation.x, s * x + c * y + tf.translation.y,
                         pose[2] + yaw])  # fmt: skip
    return pose


def moved(poses: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """Rows ``(t, x, y, yaw)`` moved from a frame whose pose in the root is ``frame``."""
    c, s = math.cos(frame[2]), math.sin(frame[2])
    out = poses.copy()
    out[:, 1] = c * poses[:, 1] - s * poses[:, 2] + frame[0]
    out[:, 2] = s * poses[:, 1] + c * poses[:, 2] + frame[1]
    out[:, 3] = poses[:, 3] + frame[2]
    return out


def tilts(path, topic: str) -> np.ndarray:
    """Degrees of each Vicon quaternion's z axis from vertical (read unchecked)."""
    from rosbags.highlevel import AnyReader

    out = []
    with AnyReader([Path(path)]) as reader:
        connections = [c for c in reader.connections if c.topic == topic]
        for connection, _, raw in reader.messages(connections=connections):
            q = reader.deserialize(raw, connection.msgtype).transform.rotation
            n = math.sqrt(q.x**2 + q.y**2 + q.z**2 + q.w**2)
            out.append(
                math.degrees(math.acos(max(-1.0, min(1.0, 1 - 2 * (q.x**2 + q.y**2) / n**2))))
            )
    return np.array(out)


def reordered(path, topic: str) -> float:
    """Seconds the header stamps go furthest back (0: in order)."""
    from rosbags.highlevel import AnyReader

    times = []
    with AnyReader([Path(path)]) as reader:
        connections = [c for c in reader.connections if c.topic == topic]
        for connection, _, raw in reader.messages(connections=connections):
            stamp = reader.deserialize(raw, connection.msgtype).header.stamp
            times.append(stamp.sec + 1e-9 * stamp.nanosec)
    times = np.array(times)
    return float((np.maximum.accumulate(times) - times).max())


def contact_distance(poses: np.ndarray, tip: np.ndarray) -> float:
    """Median distance (metres, along the block's axes) of the tip's centre from the block's
    centre while the block moves faster than 5 mm/s."""
    speed = np.hypot(*np.diff(poses[:, 1:3], axis=0).T) / np.diff(poses[:, 0])
    moving = np.interp(tip[:, 0], poses[1:, 0], (speed > 0.005).astype(float)) > 0.5
    inside = moving & (tip[:, 0] >= poses[0, 0]) & (tip[:, 0] <= poses[-1, 0])
    if not inside.any():
        return float("nan")
    at = np.column_stack([np.interp(tip[inside, 0], poses[:, 0], poses[:, k]) for k in (1, 2, 3)])
    rel = tip[inside, 1:3] - at[:, :2]
    c, s = np.cos(at[:, 2]), np.sin(at[:, 2])
    local = np.column_stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]])
    return float(np.median(np.abs(local).max(axis=1)))


def rate(times: np.ndarray) -> float:
    return float(1.0 / np.median(np.diff(times)))


def describe(path: Path, outline: np.ndarray) -> tuple[str, list]:
    """One bag's line of figures, and its steel-block pushes (pieces) if it is one."""
    topics = bag.bag_topics(path)
    topic = vicon_topic(topics)
    tilt = tilts(path, topic)
    try:
        obj = bag.poses_from_bag(path, topic)
        refused = ""
    except ValueError as e:
        refused = f" REFUSED ({e})"
        obj = bag.poses_from_bag(path, topic, check_orientation=False)
    tip = bag.poses_from_bag(path, TIP_TOPIC, check_orientation=False)
    steps = np.diff(tip.poses[:, 1:3], axis=0)
    repeats = float(np.mean(np.all(steps == 0, axis=1)))
    try:
        as_recorded = len(bag.recording_from_bag(path, topic, TIP_TOPIC, outline, RADIUS).pushes)
    except ValueError as e:
        as_recorded = f"none ({str(e)[:60]}...)"
    frame = frame_in(path, obj.frame_id)
    poses = moved(obj.poses, frame)
    pieces = split_pushes(outline, poses, tip.poses, RADIUS)
    travel = math.hypot(*(poses[-1, 1:3] - poses[0, 1:3]))
    distance = contact_distance(poses, tip.poses)
    turn = math.degrees(poses[-1, 3] - poses[0, 3])
    line = (
        f"{path.stem}: {topic} {obj.msgtype.split('/')[-1]} {len(obj.poses)} at "
        f"{rate(obj.poses[:, 0]):.1f} Hz in {obj.frame_id!r} (z axis tilt median "
        f"{np.median(tilt):.1f}, max {tilt.max():.1f} deg){refused}; {TIP_TOPIC} "
        f"{len(tip.poses)} at {rate(tip.poses[:, 0]):.1f} Hz in {tip.frame_id!r}, "
        f"{100 * repeats:.0f} % repeating the previous position; the object moves "
        f"{1000 * travel:.0f} mm and turns {turn:.1f} deg (header stamps back by at most "
        f"{1000 * reordered(path, topic):.1f} ms); {obj.frame_id} in map at "
        f"({frame[0]:.4f}, {frame[1]:.4f}) m; while the object moves the tip's centre is "
        f"{1000 * distance:.1f} mm from its centre (median, along its axes); pushes as "
        f"recorded: {as_recorded}; contacts in "
        f"map with the steel block's outline: {len(pieces)}"
    )
    return line, pieces if topic.startswith("/vicon/SteelBlock") else []


def main(argv=None) -> None:
    """Print the figures of each bag, then the steel block's estimate."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the extracted bags and SteelBlock.stl")
    args = parser.parse_args(argv)
    outline = read_outline(args.folder / "SteelBlock.stl")
    print(f"SteelBlock.stl's footprint: {np.ptp(outline, axis=0).round(5).tolist()} m")
    pieces, names = [], []
    for path in sorted(args.folder.glob("*.bag")):
        line, found = describe(path, outline)
        print(line, flush=True)
        pieces += found
        names += [f"{path.stem} {k + 1}" for k in range(len(found))]
    if not pieces:
        print("no steel-block push")
        return
    rec = comcore.recording_from_poses(outline, pieces, RADIUS, com=(0.0, 0.0), names=names)
    print(rec.report())
    print("motions (theta rad, tx px, ty px):", np.round(rec.motions, 3).tolist())
    for label, model in (("limit surface", "default"), ("Voting Theorem alone", None)):
        kw = {} if model == "default" else {"model": None}
        est = comcore.estimate_posterior(rec.mask, rec.actions, rec.motions, pusher_radius=RADIUS,
                                         **kw)  # fmt: skip
        com = rec.object_from_pixels(np.array(est.com))[0]
        print(
            f"estimate_posterior ({label}): status {est.status}, CoM ({1000 * com[0]:.1f}, "
            f"{1000 * com[1]:.1f}) mm in the block's frame, {1000 * math.hypot(*com):.1f} mm "
            f"from its centre; region {int(est.region.sum())} px at {rec.mask.resolution:g} m"
        )


if __name__ == "__main__":
    main()
