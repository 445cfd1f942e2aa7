"""From camera frames to masks and motions: segmentation, registration, pose tracking.

:func:`mask_from_image` segments the object against the table (its light in
``_light``, the object in ``_object``, the inputs in ``_input``);
:func:`measure_motion` registers two masks into a :class:`MotionMeasurement`
(the fit in ``_registration_fit``); ``_pose_tracking`` keeps a session's pose
against its first mask. May import the base modules, :mod:`comcore.geometry` and
:mod:`comcore.vt`.
"""

from ._image import mask_from_image
from ._registration import MotionMeasurement, measure_motion

__all__ = ["MotionMeasurement", "mask_from_image", "measure_motion"]
