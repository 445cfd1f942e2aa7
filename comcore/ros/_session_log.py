"""A session, step by step, as an MCAP file of standard ROS 2 messages (for Foxglove, Rerun).

:class:`SessionLog` writes what a session sees and believes after each push into a
rosbag2 folder whose one file is MCAP: the camera's frame, the mask, the posterior over
the CoM, its credible region, the pushes so far and the estimate with its covariance.
Every topic is a standard ROS 2 message, so the file opens as it is in Foxglove (its
Image, 3D and Raw Messages panels), in Rerun (``rerun run.mcap``, which reads MCAP's ROS 2
messages) and replays with ``ros2 bag play`` into RViz; :func:`read_session_log` reads
it back into numpy for a test or a figure.

The choice of MCAP over a viewer's own SDK: one open file format that both viewers labs
use open, that a ROS cell already records and replays, with no package beyond the
``ros`` extra (``rosbags`` writes it; ``pip install comcore[ros]``). A live view is the
same messages published (``ros2 bag play`` while the session runs, or a node that
publishes each step's messages).

Frames and units (:mod:`comcore.conventions`): images are the camera's pixels (the frame
as passed; mask, posterior and region in the first mask's pixels); markers and the
estimate are in the first mask's metres (``x`` along the columns, ``y`` down the rows, so
``z`` points into the table, as a camera's optical frame), frame id ``frame_id``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from .._mask import Mask
from .._types import Estimate
from ._messages import UNKNOWN_VARIANCE

__all__ = ["TOPICS", "SessionLog", "read_session_log"]

#: The topics a :class:`SessionLog` writes, and their ROS 2 message types.
TOPICS = {
    "/comcore/camera": "sensor_msgs/msg/Image",
    "/comcore/mask": "sensor_msgs/msg/Image",
    "/comcore/posterior": "sensor_msgs/msg/Image",
    "/comcore/region": "sensor_msgs/msg/Image",
    "/comcore/pushes": "visualization_msgs/msg/MarkerArray",
    "/comcore/estimate": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/comcore/status": "std_msgs/msg/String",
}


def _typestore():
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError as e:
        raise ImportError("SessionLog needs rosbags: pip install comcore[ros]") from e
    return get_typestore(Stores.ROS2_HUMBLE)


class SessionLog:
    """Write a session's steps to ``path`` (a rosbag2 folder holding one MCAP file).

    Parameters
    ----------
    path : str or os.PathLike
        The folder to create (it must not exist: a log is never overwritten).
    frame_id : str, optional
        The frame id of the images' and markers' headers (the first mask's frame).

    Raises
    ------
    ValueError
        If ``path`` exists.
    ImportError
        Without rosbags (``pip install comcore[ros]``).

    Examples
    --------
    A session's loop, with one call after each observation (``frame``: the camera's
    image, optional; ``time``: seconds, e.g. the camera's stamp)::

        with comcore.ros.SessionLog("run1") as log:
            log.step(session, mask=mask, frame=image, time=t0)
            while not session.done:
                robot.execute(session.next_push())
                mask = camera_mask()
                session.observe(mask)
                log.step(session, mask=mask, frame=image, time=t)
    """

    def __init__(self, path, *, frame_id: str = "comcore_mask"):
        if not isinstance(frame_id, str) or not frame_id:
            raise TypeError(f"frame_id must be a non-empty string, got {frame_id!r}")
        self.path = Path(path)
        if self.path.exists():
            raise ValueError(f"path {str(self.path)!r} exists: a SessionLog writes a new folder")
        self.frame_id = frame_id
        self._store = _typestore()
        from rosbags.rosbag2 import StoragePlugin, Writer

        self._writer = Writer(self.path, version=8, storage_plugin=StoragePlugin.MCAP)
        self._writer.open()
        self._connections = {
            topic: self._writer.add_connection(topic, kind, typestore=self._store)
            for topic, kind in TOPICS.items()
        }
        self._steps = 0
        self._last_ns = -1

    def __enter__(self) -> SessionLog:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Finish the file (idempotent)."""
        if self._writer is not None:
            self._writer.close()
            self._writer = None

    @property
    def steps(self) -> int:
        """How many steps were written."""
        return self._steps

    def step(self, session, *, mask: Mask | None = None, frame=None, time=None) -> None:
        """Write the session's state now: its estimate, pushes, and the images given.

        Parameters
        ----------
        session : ActiveSession or GoalSession or Estimate
            What to log: a session (its :meth:`estimate` and pushes) or an estimate.
        mask : Mask, optional
            The mask just observed (the camera's pixels).
        frame : array_like, shape (H, W) or (H, W, 3), optional
            The camera's image (uint8 grey or RGB).
        time : float, optional
            Seconds (the camera's stamp); default: the step's index. Must increase.
        """
        if self._writer is None:
            raise ValueError("the SessionLog is closed")
        estimate = session if isinstance(session, Estimate) else session.estimate()
        if not isinstance(estimate, Estimate):
            raise TypeError(
                "session must be an ActiveSession, a GoalSession or an Estimate, "
                f"got {type(session).__name__}"
            )
        stamp_ns = self._stamp(time)
        header = self._header(stamp_ns)
        if frame is not None:
            self._write("/comcore/camera", _image(self._store, header, frame, "frame"), stamp_ns)
        if mask is not None:
            if not isinstance(mask, Mask):
                raise TypeError(f"mask must be a comcore.Mask, got {type(mask).__name__}")
            self._write("/comcore/mask", _image(self._store, header, mask.data, "mask"), stamp_ns)
        details = estimate.posterior
        if details is not None:
            peak = float(np.max(details.image)) if details.image.size else 0.0
            scaled = details.image / peak if peak > 0 else details.image
            post = _image(self._store, header, scaled, "posterior")
            self._write("/comcore/posterior", post, stamp_ns)
        region = _image(self._store, header, estimate.region, "region")
        self._write("/comcore/region", region, stamp_ns)
        resolution = mask.resolution if mask is not None else _resolution(estimate)
        pushes = _push_markers(self._store, header, estimate, session, resolution)
        self._write("/comcore/pushes", pushes, stamp_ns)
        self._write("/comcore/estimate", _estimate(self._store, header, estimate), stamp_ns)
        self._write("/comcore/status", _status(self._store, estimate, self._steps), stamp_ns)
        self._steps += 1

    def _stamp(self, time) -> int:
        seconds = float(self._steps if time is None else time)
        if not math.isfinite(seconds) or seconds < 0:
            raise ValueError(f"time must be finite seconds >= 0, got {time!r}")
        ns = round(seconds * 1e9)
        if ns <= self._last_ns:
            raise ValueError(f"time must increase from step to step, got {time!r} after "
                             f"{self._last_ns / 1e9:g} s")
        self._last_ns = ns
        return ns

    def _header(self, stamp_ns: int):
        types = self._store.types
        stamp = types["builtin_interfaces/msg/Time"](
            sec=stamp_ns // 1_000_000_000, nanosec=stamp_ns % 1_000_000_000
        )
        return types["std_msgs/msg/Header"](stamp=stamp, frame_id=self.frame_id)

    def _write(self, topic: str, message, stamp_ns: int) -> None:
        data = self._store.serialize_cdr(message, TOPICS[topic])
        self._writer.write(self._connections[topic], stamp_ns, data)


def _image(store, header, image, name: str):
    """A ``sensor_msgs/Image`` of a bool, float (0..1) or uint8 image (mono8 or rgb8)."""
    array = np.asarray(image)
    if array.ndim not in (2, 3) or (array.ndim == 3 and array.shape[2] != 3):
        raise ValueError(f"{name} must have shape (H, W) or (H, W, 3), got {array.shape}")
    if array.dtype == bool:
        array = array.astype(np.uint8) * 255
    elif array.dtype != np.uint8:
        values = array.astype(float)
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{name} must be finite")
        array = np.clip(np.rint(values * 255.0 if values.max() <= 1.0 else values), 0, 255)
        array = array.astype(np.uint8)
    height, width = array.shape[:2]
    channels = 1 if array.ndim == 2 else 3
    return store.types["sensor_msgs/msg/Image"](
        header=header, height=height, width=width,
        encoding="mono8" if channels == 1 else "rgb8", is_bigendian=0,
        step=width * channels, data=np.ascontiguousarray(array).reshape(-1),
    )


def _point(store, x: float, y: float):
    return store.types["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=0.0)


def _push_markers(store, header, estimate: Estimate, session, resolution: float):
    """One arrow per push so far (the first mask's metres), as a ``MarkerArray``."""
    types = store.types
    actions = getattr(session, "actions", None)
    if actions is None:
        actions = [r.action for r in estimate.pushes]
    markers = []
    for i, action in enumerate(np.asarray(actions, dtype=float).reshape(-1, 4)):
        start, end = action[:2] * resolution, action[2:] * resolution
        markers.append(types["visualization_msgs/msg/Marker"](
            header=header, ns="comcore_pushes", id=i, type=0, action=0,
            pose=_pose(store, 0.0, 0.0),
            scale=types["geometry_msgs/msg/Vector3"](x=0.002, y=0.004, z=0.004),
            color=types["std_msgs/msg/ColorRGBA"](r=1.0, g=0.5, b=0.0, a=1.0),
            lifetime=types["builtin_interfaces/msg/Duration"](sec=0, nanosec=0),
            frame_locked=False, points=[_point(store, *start), _point(store, *end)],
            colors=[], texture_resource="",
            texture=types["sensor_msgs/msg/CompressedImage"](
                header=header, format="", data=np.zeros(0, np.uint8)),
            uv_coordinates=[], text=f"push {i + 1}", mesh_resource="",
            mesh_file=types["visualization_msgs/msg/MeshFile"](
                filename="", data=np.zeros(0, np.uint8)),
            mesh_use_embedded_materials=False,
        ))
    return types["visualization_msgs/msg/MarkerArray"](markers=markers)


def _resolution(estimate: Estimate) -> float:
    com, com_m = np.asarray(estimate.com, float), np.asarray(estimate.com_m, float)
    scale = com_m / np.where(com == 0, np.nan, com)
    scale = scale[np.isfinite(scale)]
    return float(scale[0]) if scale.size else 1.0


def _pose(store, x: float, y: float):
    types = store.types
    return types["geometry_msgs/msg/Pose"](
        position=_point(store, x, y),
        orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
    )


def _estimate(store, header, estimate: Estimate):
    """The CoM (the first mask's metres) with its covariance in the x/y block."""
    covariance = np.diag([UNKNOWN_VARIANCE] * 6)
    if estimate.covariance is not None:
        covariance[:2, :2] = np.asarray(estimate.covariance, float)
    types = store.types
    pose = types["geometry_msgs/msg/PoseWithCovariance"](
        pose=_pose(store, *estimate.com_m), covariance=covariance.reshape(-1)
    )
    return types["geometry_msgs/msg/PoseWithCovarianceStamped"](header=header, pose=pose)


def _status(store, estimate: Estimate, step: int):
    """The step's status, as a JSON ``std_msgs/String``."""
    details = estimate.posterior
    text = json.dumps({
        "step": step,
        "status": str(estimate.status),
        "com_px": [float(v) for v in estimate.com],
        "com_m": [float(v) for v in estimate.com_m],
        "n_pushes": len(estimate.pushes),
        "credible_radius_px": None if details is None else float(details.credible_radius_px),
    })
    return store.types["std_msgs/msg/String"](data=text)


def read_session_log(path) -> list[dict]:
    """A :class:`SessionLog`'s steps, read back: one dict per step, in time order.

    Each dict maps ``"time"`` (seconds) and each topic's short name (``"camera"``,
    ``"mask"``, ``"posterior"``, ``"region"``: numpy images; ``"pushes"``: an (n, 4)
    array of the pushes' start and end in metres; ``"estimate"``: ``(x, y)`` metres
    and ``"covariance"``: its 2 x 2 block; ``"status"``: the decoded JSON) to what the
    step holds.

    Raises
    ------
    ValueError
        If ``path`` is not a rosbag2 folder (or its MCAP file).
    """
    store = _typestore()
    from rosbags.rosbag2 import Reader

    folder = Path(path)
    if not (folder / "metadata.yaml").is_file():
        raise ValueError(f"path must be a SessionLog's folder (with metadata.yaml), got {path!r}")
    steps: dict[int, dict] = {}
    with Reader(folder) as reader:
        for connection, stamp_ns, raw in reader.messages():
            message = store.deserialize_cdr(raw, connection.msgtype)
            step = steps.setdefault(stamp_ns, {"time": stamp_ns / 1e9})
            _decode(step, connection.topic.rsplit("/", 1)[-1], message)
    return [steps[k] for k in sorted(steps)]


def _decode(step: dict, name: str, message) -> None:
    if name in ("camera", "mask", "posterior", "region"):
        channels = 3 if message.encoding == "rgb8" else 1
        shape = (message.height, message.width) + ((3,) if channels == 3 else ())
        step[name] = np.asarray(message.data, dtype=np.uint8).reshape(shape)
    elif name == "pushes":
        step[name] = np.array(
            [[m.points[0].x, m.points[0].y, m.points[1].x, m.points[1].y] for m in message.markers]
        ).reshape(-1, 4)
    elif name == "estimate":
        position = message.pose.pose.position
        step[name] = (position.x, position.y)
        step["covariance"] = np.asarray(message.pose.covariance).reshape(6, 6)[:2, :2]
    elif name == "status":
        step[name] = json.loads(message.data)
