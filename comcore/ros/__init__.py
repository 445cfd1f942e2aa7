"""A ROS cell's side of comcore, with no ROS install: estimates out as ROS messages' fields.

:func:`ros_messages` lays an :class:`comcore.Estimate` out as the fields of
``geometry_msgs/msg/InertiaStamped`` and ``geometry_msgs/msg/PoseWithCovarianceStamped``
(plain dicts; ``_messages`` says each choice: frames, unknown variances, stamps).
A cell's bags come in through :mod:`comcore.recordings.bag`, beside the other recordings.
Imports numpy only, through the base modules; it may import every layer up to
:mod:`comcore.recordings` and :mod:`comcore.camera`, never :mod:`comcore.active`.
"""

from ._messages import UNKNOWN_VARIANCE, ros_messages, ros_time

__all__ = ["UNKNOWN_VARIANCE", "ros_messages", "ros_time"]
