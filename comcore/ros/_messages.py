"""Estimates out in the shapes ROS uses: plain dicts, no ROS dependency.

:func:`ros_messages` lays an :class:`comcore.Estimate` out as the fields of two
ROS 2 messages, ``geometry_msgs/msg/InertiaStamped`` (the CoM in metres in a
named frame) and ``geometry_msgs/msg/PoseWithCovarianceStamped`` (the CoM as a
position with its 2x2 covariance in the x/y block of the 6x6), as nested
dicts of floats, ints and strings that :func:`json.dumps` writes as they are and
that a ROS node copies field by field into its messages (docs/how-to/ros-messages.md
shows an ``rclpy`` node doing it).

The choices, made here once:

* **Frame.** With ``frame`` (an object frame, such as a
  :class:`comcore.Recording`'s ``frame``), the CoM is in that frame's metres:
  the frame of the outline and of the object's pose topic, ``x`` and ``y`` on
  the table, ``z`` up. Without it, in the mask frame's metres
  (:mod:`comcore.conventions`: ``resolution * (x, y)``, ``x`` along the
  columns, ``y`` DOWN the rows, so as a right-handed frame ``z`` points into
  the table, as a camera's optical frame does); name that frame in your tf
  tree accordingly.
* **z.** The CoM comcore finds is its projection on the table (pushing sees no
  height): ``com.z = 0`` with an unknown variance.
* **Unknown values.** ROS messages have no field for "unknown". Variances
  comcore does not estimate (z and the three rotations, which a point has
  none of; x/y as well when the estimator gives no covariance, as Alg. 1, Alg. 2
  and the centroid do not) are ``unknown_variance`` (default 1e6 m^2 or
  rad^2, the value ROS's ``diff_drive_controller`` publishes for the degrees
  of freedom it does not measure, so that a fusion node ignores them), never
  ``-1`` on the diagonal (``sensor_msgs/Imu``'s ``-1`` marks a whole matrix
  unknown and is not a covariance). The mass and inertia tensor, which pushing
  without a force sensor does not measure, are 0 unless ``mass`` is given
  (then the inertia tensor stays 0).
* **Stamp.** ``builtin_interfaces/Time`` (``sec``, ``nanosec``) from seconds;
  default 0 (ROS's "no time": tf's latest). ROS 1's ``secs``/``nsecs`` are the
  same numbers.

Nothing else is read from the estimate but ``com``, ``covariance`` and
``status`` (returned beside the messages, since a message cannot say
``inconsistent``: check it before publishing).
"""

from __future__ import annotations

import math

import numpy as np

from comcore._types import Estimate
from comcore._validation import check_physical

__all__ = ["UNKNOWN_VARIANCE", "ros_messages", "ros_time"]

#: Variance (m^2 or rad^2) of what comcore does not estimate, as ROS drivers publish
#: for an unmeasured degree of freedom (diff_drive_controller's 1e6).
UNKNOWN_VARIANCE = 1e6


def ros_time(seconds) -> dict:
    """``builtin_interfaces/Time`` of ``seconds``: ``{"sec": int, "nanosec": int}``.

    Parameters
    ----------
    seconds : float or (int, int)
        Seconds since the epoch (ROS time), or an already split ``(sec, nanosec)``.

    Returns
    -------
    dict
        ``sec`` (int) and ``nanosec`` (int, 0 to 999 999 999).

    Raises
    ------
    ValueError
        If the time is negative or not finite, or ``nanosec`` is out of range.

    Examples
    --------
    >>> ros_time(12.25)
    {'sec': 12, 'nanosec': 250000000}
    >>> ros_time((1700000000, 5))
    {'sec': 1700000000, 'nanosec': 5}
    """
    if isinstance(seconds, (tuple, list)):
        if len(seconds) != 2:
            raise ValueError(f"stamp as (sec, nanosec) needs two integers, got {seconds!r}")
        sec, nanosec = (int(v) for v in seconds)
        if sec < 0 or not 0 <= nanosec < 1_000_000_000:
            raise ValueError(
                f"stamp (sec, nanosec) must have sec >= 0 and 0 <= nanosec < 1e9, got {seconds!r}"
            )
        return {"sec": sec, "nanosec": nanosec}
    if isinstance(seconds, (str, bytes)) or seconds is None:
        raise TypeError(f"stamp must be seconds (float) or (sec, nanosec), got {seconds!r}")
    value = float(seconds)
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"stamp must be finite seconds >= 0, got {seconds!r}")
    sec = math.floor(value)
    nanosec = round((value - sec) * 1e9)
    if nanosec == 1_000_000_000:
        sec, nanosec = sec + 1, 0
    return {"sec": int(sec), "nanosec": int(nanosec)}


def _jacobian(frame, com_px) -> np.ndarray:
    """The (2, 2) map from pixel offsets to the frame's metres at ``com_px`` (affine frames)."""
    points = com_px + np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])
    mapped = np.asarray(frame.object_from_pixels(points), dtype=float).reshape(3, 2)
    return np.column_stack([mapped[1] - mapped[0], mapped[2] - mapped[0]])


def ros_messages(
    estimate: Estimate,
    *,
    frame_id: str,
    resolution: float | None = None,
    frame=None,
    stamp=0.0,
    mass: float | None = None,
    unknown_variance: float = UNKNOWN_VARIANCE,
) -> dict:
    """The estimate as ``InertiaStamped`` and ``PoseWithCovarianceStamped`` fields.

    Parameters
    ----------
    estimate : Estimate
        Any estimator's result.
    frame_id : str
        The ``header.frame_id`` of both messages: the tf frame the CoM is in
        (the object's frame with ``frame``; a frame you publish for the mask
        otherwise). Not empty.
    resolution : float, optional
        The mask's metres per pixel (``mask.resolution``), for the CoM in the
        mask frame's metres; not needed with ``frame``.
    frame : OutlineFrame or Recording, optional
        The object frame to express the CoM in: a :class:`comcore.Recording`
        (its ``frame``) or anything with ``resolution`` and an affine
        ``object_from_pixels(points)``; the covariance is carried through the
        same map.
    stamp : float or (int, int), optional
        The header stamp, seconds or ``(sec, nanosec)`` (:func:`ros_time`);
        default 0.
    mass : float, optional
        The object's mass in kg if you know it (``inertia.m``); default 0,
        unknown.
    unknown_variance : float, optional
        The variance written for what comcore does not estimate (module
        docstring); default :data:`UNKNOWN_VARIANCE`.

    Returns
    -------
    dict
        ``{"inertia_stamped": {...}, "pose_with_covariance_stamped": {...},
        "status": str}``: the two messages' fields by their ROS names (the
        covariance as 36 floats, row-major) and the estimate's status.

    Raises
    ------
    TypeError
        If ``estimate`` is not an :class:`comcore.Estimate` or ``frame`` has no
        ``object_from_pixels``.
    ValueError
        If ``frame_id`` is empty, neither ``resolution`` nor ``frame`` is given,
        or a number is out of range.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> est = comcore.Estimate(com=(40.0, 20.0), com_m=(0.1, 0.05),
    ...                        region=np.ones((3, 3), bool), covariance=[[4.0, 1.0], [1.0, 9.0]])
    >>> msgs = ros_messages(est, frame_id="camera_table", resolution=0.0025, stamp=3.5)
    >>> msgs["inertia_stamped"]["inertia"]["com"]
    {'x': 0.1, 'y': 0.05, 'z': 0.0}
    >>> cov = np.reshape(msgs["pose_with_covariance_stamped"]["pose"]["covariance"], (6, 6))
    >>> cov[:2, :2] * 1e6  # mm^2: 2.5 mm per pixel
    array([[25.  ,  6.25],
           [ 6.25, 56.25]])
    >>> float(cov[5, 5]), msgs["status"]
    (1000000.0, 'ok')
    """
    if not isinstance(estimate, Estimate):
        raise TypeError(f"estimate must be a comcore.Estimate, got {type(estimate).__name__}")
    if not isinstance(frame_id, str) or not frame_id.strip():
        raise ValueError(
            f"frame_id must be the tf frame's name (a non-empty str), got {frame_id!r}"
        )
    unknown = float(unknown_variance)
    if not (math.isfinite(unknown) and unknown > 0):
        raise ValueError(
            f"unknown_variance must be a positive finite number, got {unknown_variance!r}"
        )
    com_px = np.asarray(estimate.com, dtype=float)
    if frame is not None:
        frame = getattr(frame, "frame", frame)  # a Recording carries its frame
        if not callable(getattr(frame, "object_from_pixels", None)):
            raise TypeError(
                "frame must be a Recording or an OutlineFrame (with object_from_pixels), got "
                f"{type(frame).__name__}"
            )
        to_metres = _jacobian(frame, com_px)
        com = np.asarray(frame.object_from_pixels(com_px[None]), dtype=float).reshape(2)
    else:
        if resolution is None:
            raise ValueError(
                "give resolution (the mask's metres per pixel) for the CoM in the mask frame, "
                "or frame (a Recording's) for the object's frame"
            )
        res = check_physical(resolution, "resolution", "resolution")
        to_metres = res * np.eye(2)
        com = to_metres @ com_px
    if mass is None:
        m = 0.0
    else:
        m = float(mass)
        if not (math.isfinite(m) and m > 0):
            raise ValueError(f"mass must be a positive number of kg, got {mass!r}")
    covariance = np.diag([unknown] * 6)
    if estimate.covariance is not None:
        covariance[:2, :2] = to_metres @ np.asarray(estimate.covariance, float) @ to_metres.T
    header = {"stamp": ros_time(stamp), "frame_id": frame_id}
    x, y = (float(v) for v in com)
    point = {"x": x, "y": y, "z": 0.0}
    inertia = {"m": m, "com": dict(point)}
    inertia.update({k: 0.0 for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")})
    pose = {
        "position": dict(point),
        "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
    }
    return {
        "inertia_stamped": {"header": dict(header), "inertia": inertia},
        "pose_with_covariance_stamped": {
            "header": {"stamp": dict(header["stamp"]), "frame_id": frame_id},
            "pose": {"pose": pose, "covariance": [float(v) for v in covariance.ravel()]},
        },
        "status": str(estimate.status),
    }
