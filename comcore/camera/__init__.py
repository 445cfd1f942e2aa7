"""From camera frames to masks and motions: segmentation, registration, pose tracking.

:func:`mask_from_image` segments the object against the table (its light in
``_light``, the object in ``_object``, the inputs in ``_input``);
:func:`measure_motion` registers two masks into a :class:`MotionMeasurement`
(the fit in ``_registration_fit``); ``_pose_tracking`` keeps a session's pose
against its first mask; ``_table`` calibrates the camera to the table plane
(:func:`calibrate_table`: camera pixels, table metres and the robot's frame,
top-down images through a :class:`TableView`); ``_tags`` tracks an AprilTag or ArUco marker stuck on
the object (:func:`track_tag`, needs opencv) and turns its poses into motions.
May import the base modules, :mod:`comcore.geometry` and
:mod:`comcore.vt`.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports
from ._registration import MotionMeasurement, measure_motion

# Segmentation and tags load on first use: a session registers masks, it needs neither.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "mask_from_image": "_image",
        **dict.fromkeys(
            ("RobotFromTable", "TableCalibration", "TableView", "calibrate_table",
             "fit_robot_from_table"),
            "_table",
        ),
        **dict.fromkeys(
            ("TAG_DICTIONARIES", "TagPose", "TagTrack", "centroid_in_tag", "motion_from_tags",
             "track_tag"),
            "_tags",
        ),
    },
)
if TYPE_CHECKING:
    from ._image import mask_from_image
    from ._table import (
        RobotFromTable,
        TableCalibration,
        TableView,
        calibrate_table,
        fit_robot_from_table,
    )
    from ._tags import (
        TAG_DICTIONARIES,
        TagPose,
        TagTrack,
        centroid_in_tag,
        motion_from_tags,
        track_tag,
    )

__all__ = [
    "TAG_DICTIONARIES",
    "MotionMeasurement",
    "RobotFromTable",
    "TableCalibration",
    "TableView",
    "TagPose",
    "TagTrack",
    "calibrate_table",
    "centroid_in_tag",
    "fit_robot_from_table",
    "mask_from_image",
    "measure_motion",
    "motion_from_tags",
    "track_tag",
]
