"""From camera frames to masks and motions: segmentation, registration, pose tracking.

:func:`mask_from_image` segments the object against the table (its light in
``_light``, the object in ``_object``, the inputs in ``_input``);
:func:`measure_motion` registers two masks into a :class:`MotionMeasurement`
(the fit in ``_registration_fit``); ``_pose_tracking`` keeps a session's pose
against its first mask; ``_tags`` tracks an AprilTag or ArUco marker stuck on
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
            ("TAG_DICTIONARIES", "TagPose", "TagTrack", "centroid_in_tag", "motion_from_tags",
             "track_tag"),
            "_tags",
        ),
    },
)
if TYPE_CHECKING:
    from ._image import mask_from_image
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
    "TagPose",
    "TagTrack",
    "centroid_in_tag",
    "mask_from_image",
    "measure_motion",
    "motion_from_tags",
    "track_tag",
]
