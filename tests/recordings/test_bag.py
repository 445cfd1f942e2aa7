"""comcore.recordings.bag: ROS bags written with rosbags' own writers, read back into Recordings."""

import math
import sys

import numpy as np
import pytest

pytest.importorskip("rosbags")

import comcore
import comcore.recordings.bag as bag
from tests import bags

POSE = "geometry_msgs/msg/PoseStamped"
S = 1_000_000_000


@pytest.fixture(scope="module")
def log():
    return bags.simulated_log()


@pytest.fixture(scope="module")
def written(log, tmp_path_factory):
    """The log in each format: /plate/pose and /tip (and /tf's tool frame)."""
    folder = tmp_path_factory.mktemp("bags")
    return {
        fmt: bags.write_bag(
            folder / ("log.bag" if fmt == "rosbag1" else f"log-{fmt}"), fmt, log,
            types=("/plate/pose",), tip_in_tf=False,
        )
        for fmt in bags.FORMATS
    }  # fmt: skip


@pytest.fixture(scope="module")
def every_type(log, tmp_path_factory):
    """The log in a ROS 1 bag, the plate on a topic of each message type, the tip in /tf too."""
    return bags.write_bag(tmp_path_factory.mktemp("types") / "types.bag", "rosbag1", log)


def test_read_back_poses_equal_the_written_ones(log, written):
    start = bags.bag_start_ns(log)
    for fmt, path in written.items():
        plate = bag.poses_from_bag(path, "/plate/pose")
        tip = bag.poses_from_bag(path, "/tip", check_orientation=False)
        assert np.abs(plate.poses - log.object_rows(start)).max() < 1e-9, fmt
        assert np.abs(tip.poses[:, :3] - log.pusher_rows(start)[:, :3]).max() < 1e-9, fmt
        assert plate.frame_id == tip.frame_id == "world" and plate.time_source == "header"
        assert plate.msgtype == POSE and plate.child_frame_id == ""
        assert not plate.poses.flags.writeable
        # 100 Hz and 125 Hz, as written
        assert np.median(np.diff(plate.poses[:, 0])) == pytest.approx(0.01, abs=1e-12)
        assert np.median(np.diff(tip.poses[:, 0])) == pytest.approx(0.008, abs=1e-12)


@pytest.mark.parametrize("topic", list(bags.POSE_TYPES))
def test_every_message_type_reads_the_written_poses(log, every_type, topic):
    child = bags.PLATE_FRAME if topic == "/tf" else None
    read = bag.poses_from_bag(every_type, topic, child_frame=child)
    assert read.msgtype == bags.POSE_TYPES[topic]
    assert np.abs(read.poses - log.object_rows(bags.bag_start_ns(log))).max() < 1e-9
    named = read.msgtype != POSE
    assert read.child_frame_id == (bags.PLATE_FRAME if named else "")
    assert bag.bag_topics(every_type)[topic] == bags.POSE_TYPES[topic]


def test_the_recording_gives_the_simulators_motions(log, written):
    rec = bag.recording_from_bag(
        written["rosbag1"], "/plate/pose", "/tip", bags.OUTLINE, bags.RADIUS, travel=bags.TRAVEL
    )
    assert len(rec.pushes) == 20 and rec.skipped == ()
    assert np.abs(rec.motions - log.motions).max() < 1e-6
    assert rec.pushes[0].name == "push 1 at 0.00 s"
    # the same as recording_from_poses on the written streams, cut by split_pushes
    start = bags.bag_start_ns(log)
    pieces = comcore.recordings.split_pushes(
        bags.OUTLINE, log.object_rows(start), log.pusher_rows(start), bags.RADIUS
    )
    direct = comcore.recording_from_poses(
        bags.OUTLINE, pieces, bags.RADIUS, travel=bags.TRAVEL, names=[p.name for p in rec.pushes]
    )
    assert np.abs(rec.motions - direct.motions).max() < 1e-9
    assert np.abs(rec.actions - direct.actions).max() < 1e-9
    assert np.array_equal(rec.mask.data, direct.mask.data)


def test_ros1_sqlite3_and_mcap_give_identical_recordings(written):
    paths = [*written.values(), next(written["mcap"].glob("*.mcap"))]  # the MCAP file alone too
    recs = [
        bag.recording_from_bag(path, "/plate/pose", "/tip", bags.OUTLINE, bags.RADIUS)
        for path in paths
    ]
    assert len(recs[0].pushes) == 20
    for rec in recs[1:]:
        assert rec.pushes == recs[0].pushes and rec.skipped == recs[0].skipped
        assert np.array_equal(rec.mask.data, recs[0].mask.data)


def test_one_tf_topic_carries_both_the_plate_and_the_tip(every_type):
    plain = bag.recording_from_bag(
        every_type, "/plate/pose", "/tip", bags.OUTLINE, bags.RADIUS, travel=bags.TRAVEL
    )
    from_tf = bag.recording_from_bag(
        every_type, "/tf", "/tf", bags.OUTLINE, bags.RADIUS, object_child_frame=bags.PLATE_FRAME,
        pusher_child_frame=bags.TIP_FRAME, travel=bags.TRAVEL,
    )  # fmt: skip
    assert len(plain.pushes) == 20 and from_tf.pushes == plain.pushes


def test_options_reach_recording_from_poses_and_an_outline_file(written, tmp_path):
    path = written["mcap"]
    csv = tmp_path / "plate.csv"
    csv.write_text("x,y\n" + "\n".join(f"{x!r},{y!r}" for x, y in bags.OUTLINE.tolist()))
    outline = bags.OUTLINE.copy()
    a = bag.recording_from_bag(path, "/plate/pose", "/tip", outline, bags.RADIUS,
                               resolution=0.002, margin=0.01, travel=0.02, com=(0, 0))  # fmt: skip
    b = bag.recording_from_bag(path, "/plate/pose", "/tip", csv, bags.RADIUS,
                               resolution=0.002, margin=0.01, travel=0.02, com=(0, 0))  # fmt: skip
    assert np.array_equal(outline, bags.OUTLINE)  # not mutated
    assert a.pushes == b.pushes and a.mask.resolution == 0.002 and a.travel == 0.02
    assert a.com is not None
    with pytest.raises(TypeError, match="names"):
        bag.recording_from_bag(path, "/plate/pose", "/tip", outline, bags.RADIUS, names=["a"])
    with pytest.raises(TypeError, match="bogus"):
        bag.recording_from_bag(path, "/plate/pose", "/tip", outline, bags.RADIUS, bogus=1)


# -- errors, on small hand-made bags ----------------------------------------------------------


def rows(n=20, *, x=0.0, y=0.0, q=(0.0, 0.0, 0.0, 1.0), child="plate", step=0.001, t0=S):
    """``n`` messages at 100 Hz: received 1 ms after their stamps, moving ``step`` along x."""
    period = 10_000_000
    return [
        (t0 + k * period + 1_000_000, t0 + k * period, child, x + step * k, y, q) for k in range(n)
    ]


def small(folder, topics, fmt="rosbag1", **kw):
    folder.mkdir(parents=True, exist_ok=True)
    name = "small.bag" if fmt == "rosbag1" else "small"
    return bags.small_bag(folder / name, fmt, topics, **kw)


def test_a_missing_topic_lists_the_bags_topics(tmp_path):
    path = small(tmp_path, {"/tip": (POSE, rows())})
    with pytest.raises(
        ValueError,
        match=r"topic '/plate' is not in .*its topics: /tip \(geometry_msgs/msg/PoseStamped\)",
    ):
        bag.poses_from_bag(path, "/plate")
    with pytest.raises(ValueError, match="no such bag"):
        bag.poses_from_bag(tmp_path / "none.bag", "/tip")
    (tmp_path / "text.bag").write_text("not a bag")
    (tmp_path / "folder").mkdir()
    for bad in ("text.bag", "folder"):
        with pytest.raises(ValueError, match=rf"path: cannot read .*{bad} as a bag"):
            bag.bag_topics(tmp_path / bad)


def test_an_unsupported_type_names_the_topic_its_type_and_the_supported(tmp_path):
    path = small(tmp_path, {"/tip": (POSE, rows())})
    with bags.BagWriter(tmp_path / "odd.bag", "rosbag1") as w:
        w.write("/plate", "std_msgs/msg/String", S, w.types["std_msgs/msg/String"](data="hi"))
    with pytest.raises(
        ValueError,
        match=r"topic '/plate' holds std_msgs/msg/String, not a pose.*supported: geometry_msgs/msg/PoseStamped, .*nav_msgs/msg/Odometry",
    ):
        bag.poses_from_bag(tmp_path / "odd.bag", "/plate")
    with pytest.raises(
        ValueError, match=r"child_frame is for .*topic '/tip' holds geometry_msgs/msg/PoseStamped"
    ):
        bag.poses_from_bag(path, "/tip", child_frame="tool")


def test_an_empty_topic_is_named(tmp_path):
    path = small(tmp_path, {"/plate": (POSE, []), "/tip": (POSE, rows())}, fmt="mcap")
    with pytest.raises(ValueError, match="topic '/plate' holds no message"):
        bag.poses_from_bag(path, "/plate")


def test_tf_with_several_child_frames_needs_one_and_lists_them(tmp_path):
    tf = "tf2_msgs/msg/TFMessage"
    path = small(tmp_path, {"/tf": (tf, rows(child="plate") + rows(child="/tool", y=0.1))})
    with pytest.raises(
        ValueError,
        match=r"topic '/tf' carries the poses of 2 child frames: .*one of \['/tool', 'plate'\]",
    ):
        bag.poses_from_bag(path, "/tf")
    with pytest.raises(
        ValueError,
        match=r"topic '/tf' carries no pose of the child frame 'cup'.*\['/tool', 'plate'\]",
    ):
        bag.poses_from_bag(path, "/tf", child_frame="cup")
    tool = bag.poses_from_bag(path, "/tf", child_frame="tool")  # a leading / does not matter
    assert tool.child_frame_id == "/tool" and np.all(tool.poses[:, 2] == 0.1)


def test_millimetres_are_refused(tmp_path):
    mm = [
        (r[0], r[1], r[2], 1000 * r[3] + 400.0, 1000 * r[4] - 250.0, r[5]) for r in rows(step=0.05)
    ]
    path = small(tmp_path, {"/plate": (POSE, mm)})
    with pytest.raises(
        ValueError, match=r"topic '/plate': its positions span .* are they in millimetres\?"
    ):
        bag.poses_from_bag(path, "/plate")


@pytest.mark.parametrize(("axis", "q"), [("x", (math.sin(0.3), 0.0, 0.0, math.cos(0.3))),
                                         ("y", (0.0, math.sin(0.4), 0.0, math.cos(0.4)))])  # fmt: skip
def test_a_rotation_not_about_z_is_refused(tmp_path, axis, q):
    path = small(tmp_path, {"/plate": (POSE, rows(q=q))})
    with pytest.raises(
        ValueError,
        match=rf"topic '/plate': .*tilts the object's z axis .*its rotation is about {axis}, not z: is the frame z-up\?",
    ):
        bag.poses_from_bag(path, "/plate")
    # the pusher's orientation is not checked
    assert bag.poses_from_bag(path, "/plate", check_orientation=False).poses.shape == (20, 4)


def test_non_finite_values_are_refused_where_they_are_used(tmp_path):
    msgs = rows()
    msgs[7] = (*msgs[7][:3], float("nan"), *msgs[7][4:])
    path = small(tmp_path, {"/plate": (POSE, msgs)})
    with pytest.raises(
        ValueError, match=r"topic '/plate': the position of message 7 is not finite"
    ):
        bag.poses_from_bag(path, "/plate")
    nan_q = (float("nan"),) * 4
    path = small(tmp_path / "second", {"/tip": (POSE, rows(q=nan_q))}, fmt="mcap")
    with pytest.raises(
        ValueError, match=r"topic '/tip': the orientation of message 0 has norm nan"
    ):
        bag.poses_from_bag(path, "/tip")
    tip = bag.poses_from_bag(path, "/tip", check_orientation=False)  # the tip's yaw: not used
    assert np.all(tip.poses[:, 3] == 0.0) and np.all(np.isfinite(tip.poses))


def test_a_non_unit_quaternion_is_refused(tmp_path):
    path = small(tmp_path, {"/plate": (POSE, rows(q=(0.0, 0.0, 0.5, 0.5)))})
    with pytest.raises(
        ValueError, match=r"topic '/plate': the orientation of message 0 has norm 0.707107, not 1"
    ):
        bag.poses_from_bag(path, "/plate")


def test_stamps_a_little_out_of_order_are_sorted(tmp_path):
    msgs = rows()
    msgs[5], msgs[6] = (
        (msgs[5][0], msgs[6][1], *msgs[5][2:]),
        (msgs[6][0], msgs[5][1], *msgs[6][2:]),
    )
    read = bag.poses_from_bag(small(tmp_path, {"/plate": (POSE, msgs)}), "/plate")
    assert np.all(np.diff(read.poses[:, 0]) > 0)
    assert read.poses[5, 1] == pytest.approx(0.006) and read.poses[6, 1] == pytest.approx(0.005)


def test_times_not_increasing_are_refused_and_receive_times_can_be_chosen(tmp_path):
    back = rows()
    back[10] = (back[10][0], back[10][1] - S, *back[10][2:])  # a clock one second back
    path = small(tmp_path, {"/plate": (POSE, back)})
    with pytest.raises(
        ValueError,
        match=r"topic '/plate': its header times are not increasing: message 10 is at -0.901000000 s, 0.99 s before an earlier message's .*time='receive'",
    ):
        bag.poses_from_bag(path, "/plate")
    read = bag.poses_from_bag(path, "/plate", time="receive")
    assert read.time_source == "receive"
    assert np.allclose(read.poses[:, 0], 0.01 * np.arange(20), atol=1e-12)  # from the bag's start
    repeated = rows()
    repeated[5] = (repeated[5][0], repeated[4][1], *repeated[5][2:])
    path = small(tmp_path / "second", {"/plate": (POSE, repeated)}, fmt="mcap")
    with pytest.raises(
        ValueError, match=r"topic '/plate': .* not increasing: message 5 repeats the time"
    ):
        bag.poses_from_bag(path, "/plate")
    with pytest.raises(TypeError, match="topic must be a str"):
        bag.poses_from_bag(path, 3)
    with pytest.raises(TypeError, match="child_frame must be a str or None, got int"):
        bag.poses_from_bag(path, "/plate", child_frame=3)
    with pytest.raises(ValueError, match="time must be one of"):
        bag.poses_from_bag(path, "/plate", time="wall")


def test_zero_stamps_fall_back_to_receive_times(tmp_path):
    msgs = [(r[0], 0, *r[2:]) for r in rows()]
    path = small(tmp_path, {"/plate": (POSE, msgs)}, fmt="sqlite3")
    read = bag.poses_from_bag(path, "/plate")
    assert read.time_source == "receive" and read.poses[0, 0] == 0.0
    with pytest.raises(ValueError, match="topic '/plate': 20 of its header stamps are zero"):
        bag.poses_from_bag(path, "/plate", time="header")


def test_recording_errors_name_the_topics(tmp_path):
    square = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
    far = small(tmp_path, {"/plate": (POSE, rows(step=0.0)), "/tip": (POSE, rows(x=0.5))})
    with pytest.raises(
        ValueError,
        match=r"the pusher \(topic '/tip'\) never comes within .*\(topic '/plate'\) .*\(the closest: 0.4[0-9]* m\)",
    ):
        bag.recording_from_bag(far, "/plate", "/tip", square, 0.004)
    frames = tmp_path / "frames"
    frames.mkdir()
    path = bags.small_bag(frames / "a.bag", "rosbag1", {"/plate": (POSE, rows())}, frame_id="world")
    with bags.BagWriter(frames / "b.bag", "rosbag1") as w:
        for received, stamp, _, x, y, q in rows():
            w.write("/plate", POSE, received, w.message(POSE, stamp, "world", "", x, y, q))
            w.write("/tip", POSE, received, w.message(POSE, stamp, "/map", "", x, y, q))
    with pytest.raises(
        ValueError,
        match=r"topic '/plate'\) are in the frame 'world', the pusher's \(topic '/tip'\) in '/map'",
    ):
        bag.recording_from_bag(frames / "b.bag", "/plate", "/tip", square, 0.004)
    assert path.exists()


def test_without_rosbags_the_error_says_what_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[ros\]") as info:
        bag.bag_topics(tmp_path)
    assert isinstance(info.value.__cause__, ImportError)
