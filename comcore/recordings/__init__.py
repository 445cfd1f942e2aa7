"""Recorded pushes in: a :class:`Recording` of pushes cut from pose streams.

:func:`recording_from_poses` cuts pushes from an object's and a pusher's pose
streams (``_pose_streams``) into :class:`RecordedPush` rows, with the windows it
could not use as :class:`SkippedPush`. :mod:`comcore.recordings.mit_push` reads the
MIT push dataset (needs ``h5py``: ``pip install comcore[real]``) and is not
imported by ``import comcore``. May import the base modules and
:mod:`comcore.geometry`.
"""

from ._recording import RecordedPush, Recording, SkippedPush, recording_from_poses

__all__ = ["RecordedPush", "Recording", "SkippedPush", "recording_from_poses"]
