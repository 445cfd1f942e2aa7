"""comcore.recordings.bag.images_from_bag: a bag's camera images back as the arrays written."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("rosbags")

import comcore
import comcore.recordings.bag as bag
from tests.bags import BagWriter

T0 = 1_700_000_000_000_000_000  # ns


def _image_msg(writer, stamp_ns, array, encoding, big_endian=False):
    h, w = array.shape[:2]
    data = np.ascontiguousarray(array)
    if big_endian:
        data = data.astype(data.dtype.newbyteorder(">"))
    raw = np.frombuffer(data.tobytes(), dtype=np.uint8)
    step = raw.size // h
    fields = dict(header=writer.header(stamp_ns, "camera"), height=h, width=w,
                  encoding=encoding, is_bigendian=int(big_endian), step=step, data=raw)  # fmt: skip
    return writer.types["sensor_msgs/msg/Image"](**fields)


def _compressed_msg(writer, stamp_ns, array_bgr):
    cv2 = pytest.importorskip("cv2")
    ok, png = cv2.imencode(".png", array_bgr)
    assert ok
    return writer.types["sensor_msgs/msg/CompressedImage"](
        header=writer.header(stamp_ns, "camera"), format="png",
        data=np.frombuffer(png.tobytes(), np.uint8),
    )  # fmt: skip


def _frames(rng, n=4, shape=(24, 32)):
    return [rng.integers(0, 256, size=(*shape, 3), dtype=np.uint8) for _ in range(n)]


@pytest.fixture(params=["rosbag1", "mcap"])
def fmt(request):
    return request.param


def test_raw_images_read_back_as_written_in_rgb_order(tmp_path, fmt):
    rng = np.random.default_rng(0)
    frames = _frames(rng)
    grey = rng.integers(0, 65536, size=(24, 32), dtype=np.uint16)
    path = tmp_path / ("cam.bag" if fmt == "rosbag1" else "cam")
    with BagWriter(path, fmt) as w:
        for k, rgb in enumerate(frames):  # bgr8 on one topic, rgb8 on another, 30 Hz
            ns = T0 + k * 33_333_333
            w.write("/bgr", "sensor_msgs/msg/Image", ns, _image_msg(w, ns, rgb[:, :, ::-1], "bgr8"))
            w.write("/rgb", "sensor_msgs/msg/Image", ns, _image_msg(w, ns, rgb, "rgb8"))
        w.write("/depth", "sensor_msgs/msg/Image", T0,
                _image_msg(w, T0, grey, "16UC1", big_endian=True))  # fmt: skip
    for topic in ("/bgr", "/rgb"):
        read = list(bag.images_from_bag(path, topic))
        assert [r.t for r in read] == pytest.approx([k * 0.033333333 for k in range(4)], abs=1e-9)
        for r, rgb in zip(read, frames):
            np.testing.assert_array_equal(r.image, rgb)
            assert r.frame_id == "camera" and not r.image.flags.writeable
    (depth,) = bag.images_from_bag(path, "/depth")
    assert depth.image.dtype == np.uint16 and depth.image.dtype.byteorder in "=<|"
    np.testing.assert_array_equal(depth.image, grey)


def test_every_start_and_stop_pick_frames(tmp_path):
    rng = np.random.default_rng(1)
    frames = _frames(rng, n=9)
    path = tmp_path / "cam.bag"
    with BagWriter(path, "rosbag1") as w:
        for k, rgb in enumerate(frames):
            ns = T0 + k * 100_000_000  # 10 Hz
            w.write("/rgb", "sensor_msgs/msg/Image", ns, _image_msg(w, ns, rgb, "rgb8"))
    every = list(bag.images_from_bag(path, "/rgb", every=3))
    assert [round(r.t, 6) for r in every] == [0.0, 0.3, 0.6]
    window = list(bag.images_from_bag(path, "/rgb", start=0.25, stop=0.55))
    assert [round(r.t, 6) for r in window] == [0.3, 0.4, 0.5]
    np.testing.assert_array_equal(window[0].image, frames[3])


def test_compressed_images_decode_and_give_the_same_mask(tmp_path, fmt):
    cv2 = pytest.importorskip("cv2")
    image = np.full((60, 80, 3), 40, np.uint8)
    cv2.rectangle(image, (20, 15), (55, 40), (230, 230, 230), -1)  # a bright plate
    path = tmp_path / ("cam.bag" if fmt == "rosbag1" else "cam")
    with BagWriter(path, fmt) as w:
        w.write("/cam/compressed", "sensor_msgs/msg/CompressedImage", T0,
                _compressed_msg(w, T0, image))  # fmt: skip
    (frame,) = bag.images_from_bag(path, "/cam/compressed")
    np.testing.assert_array_equal(frame.image, image[:, :, ::-1])  # PNG is lossless
    mask = comcore.mask_from_image(frame.image, resolution=0.001)
    assert mask.data.sum() == 36 * 26 and mask.data[15:41, 20:56].all()


def test_errors_name_the_topic(tmp_path):
    path = tmp_path / "cam.bag"
    rng = np.random.default_rng(2)
    with BagWriter(path, "rosbag1") as w:
        rgb = _frames(rng, n=1)[0]
        w.write("/yuv", "sensor_msgs/msg/Image", T0, _image_msg(w, T0, rgb, "yuv422"))
        short = _image_msg(w, T0, rgb, "rgb8")
        short.data = short.data[:-10]
        w.write("/short", "sensor_msgs/msg/Image", T0, short)
        pose = w.message("geometry_msgs/msg/PoseStamped", T0, "world", "", 0.0, 0.0, (0, 0, 0, 1))
        w.write("/tip", "geometry_msgs/msg/PoseStamped", T0, pose)
    with pytest.raises(ValueError, match="topic '/yuv': message 0 has the encoding 'yuv422'"):
        list(bag.images_from_bag(path, "/yuv"))
    with pytest.raises(ValueError, match="topic '/short': message 0 is 2294 bytes"):
        list(bag.images_from_bag(path, "/short"))
    with pytest.raises(ValueError, match="topic '/tip' holds geometry_msgs/msg/PoseStamped, not a"):
        list(bag.images_from_bag(path, "/tip"))
    with pytest.raises(ValueError, match="topic '/camera' is not in .*its topics: /short"):
        list(bag.images_from_bag(path, "/camera"))
    with pytest.raises(ValueError, match="every must be an integer >= 1"):
        list(bag.images_from_bag(path, "/yuv", every=0))
