"""comcore.ros: an Estimate as ROS messages' fields, checked against ROS's own definitions."""

from __future__ import annotations

import json

import numpy as np
import pytest

import comcore
from comcore.geometry._outline import OutlineFrame
from comcore.ros import UNKNOWN_VARIANCE, ros_messages, ros_time


def _estimate(covariance=((4.0, 1.5), (1.5, 9.0)), com=(40.0, 20.0)):
    return comcore.Estimate(
        com=com, com_m=(0.0025 * com[0], 0.0025 * com[1]), region=np.ones((3, 3), bool),
        covariance=None if covariance is None else np.array(covariance),
    )  # fmt: skip


def _covariance(msgs) -> np.ndarray:
    return np.reshape(msgs["pose_with_covariance_stamped"]["pose"]["covariance"], (6, 6))


def test_mask_frame_com_is_the_estimates_metres_and_covariance_scales_by_resolution_squared():
    est = _estimate()
    msgs = ros_messages(est, frame_id="table_camera", resolution=0.0025)
    com = msgs["inertia_stamped"]["inertia"]["com"]
    assert (com["x"], com["y"], com["z"]) == pytest.approx((*est.com_m, 0.0), abs=1e-15)
    position = msgs["pose_with_covariance_stamped"]["pose"]["pose"]["position"]
    assert position == com
    cov = _covariance(msgs)
    np.testing.assert_allclose(cov[:2, :2], 0.0025**2 * est.covariance, rtol=1e-12)
    np.testing.assert_array_equal(np.diag(cov)[2:], UNKNOWN_VARIANCE)
    assert np.count_nonzero(cov - np.diag(np.diag(cov))) == 2  # only the x/y cross terms
    assert msgs["status"] == "ok"


def test_object_frame_flips_y_and_carries_the_covariance_through_the_frame():
    outline = np.array([(-0.04, -0.03), (0.05, -0.03), (0.05, 0.03), (-0.04, 0.03)])
    frame = OutlineFrame(outline, resolution=0.002, margin=0.02)
    true_object = np.array([0.011, -0.007])  # metres, y up
    est = _estimate(com=tuple(frame.pixels_from_object(true_object)[0]))
    msgs = ros_messages(est, frame_id="block", frame=frame, stamp=(17, 5))
    com = msgs["inertia_stamped"]["inertia"]["com"]
    assert (com["x"], com["y"]) == pytest.approx(tuple(true_object), abs=1e-12)
    cov = _covariance(msgs)
    flip = 0.002 * np.diag([1.0, -1.0])  # pixel y down is the object's y up
    np.testing.assert_allclose(cov[:2, :2], flip @ est.covariance @ flip.T, rtol=1e-12)
    assert cov[0, 1] < 0 < est.covariance[0, 1]
    assert msgs["inertia_stamped"]["header"] == {
        "stamp": {"sec": 17, "nanosec": 5}, "frame_id": "block"
    }  # fmt: skip


def test_a_recording_stands_for_its_frame():
    outline = [(0.0, 0.0), (0.06, 0.0), (0.06, 0.04), (0.0, 0.04)]
    frame = OutlineFrame(np.array(outline), resolution=0.0025, margin=0.01)

    class Holder:  # what ros_messages reads of a Recording: its frame
        pass

    holder = Holder()
    holder.frame = frame
    est = _estimate()
    assert ros_messages(est, frame_id="o", frame=holder) == ros_messages(
        est, frame_id="o", frame=frame
    )


def test_no_covariance_means_every_variance_unknown():
    msgs = ros_messages(_estimate(covariance=None), frame_id="m", resolution=0.001)
    np.testing.assert_array_equal(_covariance(msgs), UNKNOWN_VARIANCE * np.eye(6))


def test_mass_unknown_is_zero_and_given_is_written():
    est = _estimate()
    assert ros_messages(est, frame_id="m", resolution=0.001)["inertia_stamped"]["inertia"]["m"] == 0
    given = ros_messages(est, frame_id="m", resolution=0.001, mass=0.25)
    assert given["inertia_stamped"]["inertia"]["m"] == 0.25


def test_the_dicts_are_strict_json():
    msgs = ros_messages(_estimate(), frame_id="m", resolution=0.001, stamp=1.5)
    assert json.loads(json.dumps(msgs, allow_nan=False)) == msgs


@pytest.mark.parametrize(
    ("seconds", "expected"),
    [
        (0.0, (0, 0)),
        (12.25, (12, 250_000_000)),
        (1.9999999999, (2, 0)),
        ((3, 999_999_999), (3, 999_999_999)),
    ],
)
def test_ros_time(seconds, expected):
    assert ros_time(seconds) == {"sec": expected[0], "nanosec": expected[1]}


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"frame_id": "", "resolution": 0.001}, ValueError, "frame_id"),
        ({"frame_id": "m"}, ValueError, "give resolution"),
        ({"frame_id": "m", "resolution": 2.5}, ValueError, "millimetres"),
        ({"frame_id": "m", "frame": object()}, TypeError, "OutlineFrame"),
        ({"frame_id": "m", "resolution": 0.001, "stamp": -1.0}, ValueError, "stamp"),
        (
            {"frame_id": "m", "resolution": 0.001, "stamp": (1, 2_000_000_000)},
            ValueError,
            "nanosec",
        ),
        ({"frame_id": "m", "resolution": 0.001, "stamp": "now"}, TypeError, "stamp"),
        ({"frame_id": "m", "resolution": 0.001, "mass": -1}, ValueError, "mass"),
        ({"frame_id": "m", "resolution": 0.001, "unknown_variance": -1}, ValueError, "unknown_var"),
    ],
)
def test_bad_arguments_are_named(kwargs, error, match):
    with pytest.raises(error, match=match):
        ros_messages(_estimate(), **kwargs)


def test_not_an_estimate():
    with pytest.raises(TypeError, match="comcore.Estimate"):
        ros_messages({"com": (1, 2)}, frame_id="m", resolution=0.001)


def _message(store, msgtype: str, value):
    """Build a rosbags message of ``msgtype`` from a dict, failing on any unknown or missing key."""
    _, fields = store.fielddefs[msgtype]
    names = [name for name, _ in fields]
    assert sorted(value) == sorted(names), (msgtype, sorted(value), sorted(names))
    built = {}
    for name, (kind, sub) in fields:
        if kind.name == "NAME":
            built[name] = _message(store, sub, value[name])
        elif kind.name in ("ARRAY", "SEQUENCE"):
            built[name] = np.asarray(value[name], dtype=np.float64)
        else:
            built[name] = value[name]
    return store.types[msgtype](**built)


def test_the_fields_are_ros2s_own_and_serialise():
    rosbags = pytest.importorskip("rosbags.typesys")
    store = rosbags.get_typestore(rosbags.Stores.ROS2_HUMBLE)
    msgs = ros_messages(_estimate(), frame_id="block", resolution=0.0025, stamp=4.5)
    for key, msgtype in (
        ("inertia_stamped", "geometry_msgs/msg/InertiaStamped"),
        ("pose_with_covariance_stamped", "geometry_msgs/msg/PoseWithCovarianceStamped"),
    ):
        message = _message(store, msgtype, msgs[key])
        back = store.deserialize_cdr(store.serialize_cdr(message, msgtype), msgtype)
        assert back.header.frame_id == "block" and back.header.stamp.nanosec == 500_000_000
    pose = store.deserialize_cdr(
        store.serialize_cdr(_message(store, msgtype, msgs[key]), msgtype), msgtype
    )
    np.testing.assert_array_equal(pose.pose.covariance, msgs[key]["pose"]["covariance"])
