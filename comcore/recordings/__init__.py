"""Recorded pushes in: a :class:`Recording` of pushes cut from pose streams.

:func:`recording_from_poses` cuts pushes from an object's and a pusher's pose
streams (``_pose_streams``) into :class:`RecordedPush` rows, with the windows it
could not use as :class:`SkippedPush`; :func:`split_pushes` cuts one long log
into those per-push streams, and :func:`read_outline` reads an object's outline
from a CSV file (or a mesh, with ``comcore[sim]``).
:mod:`comcore.recordings.mit_push` reads the MIT push dataset (needs ``h5py``:
``pip install comcore[real]``) and :mod:`comcore.recordings.bag` ROS bags (needs
``rosbags``: ``pip install comcore[ros]``); neither is imported by
``import comcore``. May import the base modules and :mod:`comcore.geometry`.
"""

from ._outline_file import read_outline
from ._recording import RecordedPush, Recording, SkippedPush, recording_from_poses
from ._splitting import split_pushes

__all__ = [
    "RecordedPush",
    "Recording",
    "SkippedPush",
    "read_outline",
    "recording_from_poses",
    "split_pushes",
]
