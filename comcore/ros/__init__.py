"""A ROS cell's side of comcore, with no ROS install: estimates out as ROS messages' fields.

:func:`ros_messages` lays an :class:`comcore.Estimate` out as the fields of
``geometry_msgs/msg/InertiaStamped`` and ``geometry_msgs/msg/PoseWithCovarianceStamped``
(plain dicts; ``_messages`` says each choice: frames, unknown variances, stamps).
:class:`SessionLog` writes a session step by step as an MCAP file of standard ROS 2
messages (frames, mask, posterior, region, pushes, estimate) that Foxglove and Rerun open.
A cell's bags come in through :mod:`comcore.recordings.bag`, beside the other recordings.
Imports numpy only, through the base modules; it may import every layer up to
:mod:`comcore.recordings` and :mod:`comcore.camera`, never :mod:`comcore.active`.
"""

from ._messages import UNKNOWN_VARIANCE, ros_messages, ros_time
from ._session_log import TOPICS, SessionLog, read_session_log

__all__ = [
    "TOPICS",
    "UNKNOWN_VARIANCE",
    "SessionLog",
    "read_session_log",
    "ros_messages",
    "ros_time",
]
