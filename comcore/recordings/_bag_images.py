"""A bag's camera images: ``sensor_msgs/Image`` and ``CompressedImage`` to arrays and masks.

Decoding is the part of a camera topic that is ROS's own: ``Image`` carries raw
rows (``height``, ``width``, ``step``, an ``encoding`` such as ``mono8``,
``bgr8`` or ``16UC1``, ``is_bigendian``), ``CompressedImage`` a PNG or JPEG
(``format``), decoded with OpenCV. Colour comes out in RGB order, as
:func:`comcore.mask_from_image` reads it: ``mask_from_image(frame.image,
resolution=...)`` makes a frame's mask (the resolution is the camera's
calibration, which a bag does not hold). Times are those of the pose topics
(seconds since the bag's start; the header stamp when nonzero, else the
receive time).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..conventions import check_image_size
from ._bag_reader import _Open, _topic_type

__all__ = ["IMAGE_TYPES", "BagImage", "images_from_bag"]

#: The message types an image topic may hold (rosbags' names).
IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
#: ``Image`` encodings: (numpy dtype, channels, channel order to RGB(A)); others are refused.
ENCODINGS = {
    "mono8": ("u1", 1, None),
    "8UC1": ("u1", 1, None),
    "mono16": ("u2", 1, None),
    "16UC1": ("u2", 1, None),
    "rgb8": ("u1", 3, None),
    "bgr8": ("u1", 3, [2, 1, 0]),
    "8UC3": ("u1", 3, [2, 1, 0]),  # OpenCV's default order
    "rgba8": ("u1", 4, None),
    "bgra8": ("u1", 4, [2, 1, 0, 3]),
    "rgb16": ("u2", 3, None),
    "bgr16": ("u2", 3, [2, 1, 0]),
}


class BagImage(NamedTuple):
    """One camera image of a bag, as :func:`images_from_bag` yields it."""

    t: float
    """Seconds since the bag's start (the header stamp, or the receive time if it is zero)."""
    image: np.ndarray
    """The image, (H, W) grey or (H, W, 3|4) in RGB(A) order, uint8 or uint16, read-only."""
    frame_id: str
    """The camera's frame (the header's ``frame_id``)."""


def _decode_raw(msg, topic: str, index: int) -> np.ndarray:
    encoding = str(msg.encoding)
    if encoding not in ENCODINGS:
        raise ValueError(
            f"topic {topic!r}: message {index} has the encoding {encoding!r}; comcore reads "
            f"{', '.join(ENCODINGS)} (or a CompressedImage)"
        )
    kind, channels, order = ENCODINGS[encoding]
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    check_image_size((h, w), f"topic {topic!r}: message {index}'s image")
    dtype = np.dtype(kind).newbyteorder(">" if msg.is_bigendian else "<")
    row = w * channels * dtype.itemsize
    data = np.asarray(msg.data, dtype=np.uint8)
    if step < row or data.size < h * step:
        raise ValueError(
            f"topic {topic!r}: message {index} is {data.size} bytes for {h} rows of step {step} "
            f"({encoding}, {w} px wide: at least {row} bytes a row)"
        )
    rows = data[: h * step].reshape(h, step)[:, :row]
    image = rows.copy().view(dtype).reshape((h, w, channels) if channels > 1 else (h, w))
    if order is not None:
        image = image[:, :, order]
    return np.ascontiguousarray(image.astype(dtype.newbyteorder("="), copy=False))


def _decode_compressed(msg, topic: str, index: int) -> np.ndarray:
    try:
        import cv2
    except ImportError as e:
        raise ImportError(
            "decoding a CompressedImage needs opencv: pip install comcore[sim]"
        ) from e
    image = cv2.imdecode(np.asarray(msg.data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise ValueError(
            f"topic {topic!r}: message {index} ({msg.format!r}) is not an image OpenCV decodes"
        )
    check_image_size(image.shape, f"topic {topic!r}: message {index}'s image")
    if image.ndim == 3:  # OpenCV decodes to BGR(A)
        image = image[:, :, [2, 1, 0, 3][: image.shape[2]]]
    return np.ascontiguousarray(image)


def images_from_bag(path, topic: str, *, every: int = 1, start: float = 0.0, stop=None):
    """Yield the camera images of one topic, in the bag's order, as :class:`BagImage`.

    Parameters
    ----------
    path : str or os.PathLike
        A ROS 1 ``.bag`` file, or a rosbag2 folder (sqlite3 or MCAP).
    topic : str
        A topic of :data:`IMAGE_TYPES`.
    every : int, optional
        Keep every ``every``-th image (default 1: all): a 30 Hz camera read
        at 10 Hz is ``every=3``.
    start, stop : float, optional
        Keep the images whose time (seconds since the bag's start) is at
        least ``start`` and below ``stop`` (default: all).

    Yields
    ------
    BagImage

    Raises
    ------
    ValueError
        Naming the topic: not in the bag, not an image type, an encoding
        comcore does not read, a message shorter than its rows, an image
        OpenCV cannot decode or over :data:`comcore.conventions.MAX_IMAGE_PIXELS`.
    ImportError
        Without rosbags (``pip install comcore[ros]``); for a
        ``CompressedImage``, without opencv (``pip install comcore[sim]``).
    """
    if not isinstance(topic, str):
        raise TypeError(f"topic must be a str, got {type(topic).__name__}")
    if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 1:
        raise ValueError(f"every must be an integer >= 1, got {every!r}")
    stop = np.inf if stop is None else float(stop)
    if not (np.isfinite(float(start)) and float(start) < stop):
        raise ValueError(f"start must be finite and below stop, got {start!r} and {stop!r}")
    with _Open(path) as reader:
        msgtype = _topic_type(reader, path, topic, IMAGE_TYPES, "a camera image")
        decode = _decode_raw if msgtype == IMAGE_TYPES[0] else _decode_compressed
        begin = int(reader.start_time)
        connections = [c for c in reader.connections if c.topic == topic]
        for index, (connection, received, raw) in enumerate(
            reader.messages(connections=connections)
        ):
            if index % every:
                continue
            msg = reader.deserialize(raw, connection.msgtype)
            stamp = int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec)
            t = ((stamp if stamp else int(received)) - begin) * 1e-9
            if not start <= t < stop:
                continue
            image = decode(msg, topic, index)
            image.setflags(write=False)
            yield BagImage(t, image, str(msg.header.frame_id))
