"""Files of the MIT push dataset (Yu, Bauza, Fazeli, Rodriguez, IROS 2016) as comcore inputs.

Not imported by ``import comcore``; import it explicitly::

    import comcore.recordings.mit_push

The dataset ("More than a million ways to be pushed", MIT MCube lab) records
a robot pushing flat steel plates with a round tip: one file per push, the
tip's and the object's poses (and a force-torque sensor's wrench) at about
250 Hz, as h5 (needs h5py: ``pip install comcore[real]``) or JSON, each with
three tables of rows ``(t, x, y, yaw)`` / ``(t, fx, fy, torque_z)``:
``tip_pose``, ``object_pose`` and ``ft_wrench``. A JSON file is one object
whose keys are those tables, each a list of rows (``{"tip_pose": [[t, x, y,
yaw], ...], ...}``, as the lab's analysis scripts write it), in the h5's units
(seconds of the ROS clock, metres, radians, newtons and newton-metres). The
file name says what the push was (:func:`parse_name`). :func:`load_pushes` turns files into a
:class:`comcore.Recording` through :func:`comcore.recording_from_poses`.
The outlines of the four analytic plates are in :data:`OUTLINES`; others
(``butter``) come from the dataset's ``shape_db.py``. See docs/how-to/recordings.md.

Examples
--------
>>> import comcore.recordings.mit_push as mp
>>> name = mp.parse_name("motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.700_t=-1.047.h5")
>>> name.shape, name.speed, name.side, name.where, name.angle
('rect1', 0.075, 2, 0.7, -1.047)
>>> mp.OUTLINES["rect1"][:2].tolist()
[[0.045, 0.045], [-0.045, 0.045]]
"""

from __future__ import annotations

import json
import os
import re
from typing import NamedTuple

import numpy as np

from ._recording import (
    DEFAULT_CONTACT_TOLERANCE_M,
    DEFAULT_STANDOFF_M,
    DEFAULT_TRAVEL_M,
    Recording,
    recording_from_poses,
)

__all__ = [
    "OUTLINES",
    "PUSHER_RADIUS",
    "PushFile",
    "PushName",
    "load_pushes",
    "parse_name",
    "read_push",
]

#: Radius (metres) of the dataset's pushing tips (``probe_db.py``: probes 3-6).
PUSHER_RADIUS = 0.00475
#: Vertices of an ellipse's outline.
ELLIPSE_VERTICES = 720


def _ellipse(a: float, b: float) -> np.ndarray:
    angle = 2 * np.pi * np.arange(ELLIPSE_VERTICES) / ELLIPSE_VERTICES
    return np.column_stack([a * np.cos(angle), b * np.sin(angle)])


def _hexagon(radius: float) -> np.ndarray:
    angle = np.deg2rad(60.0 * np.arange(6))
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])


#: Outlines (metres, the frame of the files' object poses, counter-clockwise) of the
#: dataset's analytic plates, from its ``shape_db.py``; each plate is uniform, so its CoM is
#: the origin. ``ellip1`` and ``ellip3`` are sampled at 720 vertices.
OUTLINES = {
    "rect1": np.array([[0.045, 0.045], [-0.045, 0.045], [-0.045, -0.045], [0.045, -0.045]]),
    "ellip1": _ellipse(0.0525, 0.0525),
    "ellip3": _ellipse(0.0525, 0.0785),
    "hex": _hexagon(0.0605),
}
for _outline in OUTLINES.values():
    _outline.setflags(write=False)

_NAME = re.compile(
    r"motion_surface=(?P<surface>[^_]+)_shape=(?P<shape>.+?)_a=(?P<a>[-\d.]+)_v=(?P<v>[-\d.]+)"
    r"_i=(?P<i>[-\d.]+)_s=(?P<s>[-\d.]+)_t=(?P<t>[-\d.]+)(?:_rep=(?P<rep>\d+))?\.(?:h5|json)$"
)


class PushName(NamedTuple):
    """What a file's name says about its push (the collection script's fields)."""

    surface: str
    """The table's material (``abs``, ``delrin``, ...)."""
    shape: str
    """The plate (``rect1``, ``ellip1``, ``butter``, ...)."""
    acceleration: float
    """The pusher's acceleration, m/s^2 (0: constant speed)."""
    speed: float
    """The pusher's speed, m/s (the name's ``v`` is in mm/s)."""
    side: int
    """For polygons, the side from vertex ``side`` to ``side + 1``; 0 otherwise."""
    where: float
    """Where on the outline: the fraction along the side, the ellipse's parameter angle as a
    fraction of a turn, or the fraction of the perimeter."""
    angle: float
    """Push angle, radians: the approach direction is the outward normal turned
    counter-clockwise by it; the pusher moves opposite to it."""
    repeat: int | None = None
    """The repeat's number (a name ending ``_rep=NNNN``: one push made again and again), or
    None."""


class PushFile(NamedTuple):
    """The streams of one file, each sorted by time (rows ``(t, ...)``)."""

    object_pose: np.ndarray
    """Rows ``(t, x, y, yaw)`` of the object's frame, world metres and radians."""
    tip_pose: np.ndarray
    """Rows ``(t, x, y, yaw)`` of the pusher tip's centre (yaw: the tool's, not used)."""
    ft_wrench: np.ndarray
    """Rows ``(t, fx, fy, torque_z)`` of the force-torque sensor (empty if absent)."""
    name: PushName | None
    """The parsed file name, or None when it does not follow the dataset's pattern."""


def parse_name(path) -> PushName:
    """The fields of a dataset file's name (the collection script's pattern).

    Raises
    ------
    ValueError
        If the name does not follow
        ``motion_surface=<s>_shape=<s>_a=<a>_v=<v>_i=<i>_s=<s>_t=<t>.h5`` (or ``.json``;
        a repeat's name ends ``_t=<t>_rep=<n>.h5``).
    """
    base = os.path.basename(os.fspath(path))
    m = _NAME.match(base)
    if m is None:
        raise ValueError(
            f"{base!r} is not named like the MIT push dataset's files "
            "(motion_surface=<surface>_shape=<shape>_a=<a>_v=<v>_i=<i>_s=<s>_t=<t>.h5)"
        )
    return PushName(
        m["surface"],
        m["shape"],
        float(m["a"]) / 1000.0,
        float(m["v"]) / 1000.0,
        round(float(m["i"])),
        float(m["s"]),
        float(m["t"]),
        None if m["rep"] is None else int(m["rep"]),
    )


def _table(data, key: str, path) -> np.ndarray:
    if key not in data:
        raise ValueError(f"{os.fspath(path)!r} has no {key!r} table (found {sorted(data)})")
    try:
        arr = np.asarray(data[key], dtype=float)
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"{os.fspath(path)!r}: {key!r} must be a table of numbers, rows (t, x, y, yaw)"
        ) from e
    if arr.size == 0:
        return arr.reshape(0, 4)
    if arr.ndim != 2 or arr.shape[1] != 4:
        raise ValueError(f"{os.fspath(path)!r}: {key!r} must have shape (n, 4), got {arr.shape}")
    return arr[np.argsort(arr[:, 0], kind="stable")]


def read_push(path) -> PushFile:
    """Read one file of the dataset (``.h5``, needs h5py; or ``.json``), streams sorted by time.

    Some files hold ``object_pose`` samples out of order (ROS header stamps):
    every table is sorted by its time column here (stably).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    PushFile

    Raises
    ------
    ImportError
        For an h5 file without h5py (``pip install comcore[real]``).
    ValueError
        If the file cannot be read as JSON (``.json``) or HDF5 (any other
        name), a table is missing or not of shape (n, 4), or a JSON file does
        not hold one object of tables.
    """
    path = os.fspath(path)
    data = _read_json(path) if path.endswith(".json") else _read_h5(path)
    try:
        name = parse_name(path)
    except ValueError:
        name = None
    wrench = _table(data, "ft_wrench", path) if "ft_wrench" in data else np.empty((0, 4))
    return PushFile(_table(data, "object_pose", path), _table(data, "tip_pose", path), wrench, name)


def _read_json(path: str) -> dict:
    """The tables of a JSON file of the dataset, by name."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ValueError(f"path: cannot read {path!r} as JSON: {e}") from e
    if not isinstance(data, dict):
        raise ValueError(
            f"{path!r} must hold one JSON object of tables ({{'tip_pose': [[t, x, y, yaw], "
            f"...], ...}}), got a {type(data).__name__}"
        )
    return data


def _read_h5(path: str) -> dict:
    """The tables of an HDF5 file of the dataset, by name."""
    try:
        import h5py
    except ImportError as e:
        raise ImportError(
            "reading the MIT push dataset's h5 files needs h5py: pip install comcore[real]"
        ) from e
    try:
        with h5py.File(path, "r") as f:
            return {key: f[key][()] for key in f.keys()}
    except OSError as e:
        raise ValueError(
            f"path: cannot read {path!r} as HDF5 (the dataset's files are .h5 or .json): {e}"
        ) from e


def load_pushes(
    paths,
    outline=None,
    *,
    travel: float = DEFAULT_TRAVEL_M,
    resolution: float = 0.0025,
    pusher_radius: float = PUSHER_RADIUS,
    com=(0.0, 0.0),
    standoff: float = DEFAULT_STANDOFF_M,
    contact_tolerance: float = DEFAULT_CONTACT_TOLERANCE_M,
    frame_rate: float | None = None,
) -> Recording:
    """Load pushes of one plate from dataset files into a :class:`comcore.Recording`.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        The files (h5 or JSON), all of one plate; the recording keeps their
        order and names the pushes by their file names.
    outline : array_like, shape (k, 2), optional
        The plate's outline in metres, in the frame of the files' object
        poses. Default: :data:`OUTLINES` of the shape the first file's name
        says (``rect1``, ``ellip1``, ``ellip3`` or ``hex``).
    travel, resolution, standoff, contact_tolerance, frame_rate : float, optional
        As for :func:`comcore.recording_from_poses` (metres; metres per pixel; Hz:
        the pose streams sub-sampled at that rate during each push, for its path).
    pusher_radius : float, optional
        The tip's radius, metres (default 4.75 mm, the dataset's).
    com : array_like, shape (2,) or None, optional
        The true CoM in the object's frame (default the origin: the
        dataset's plates are uniform and centred on their centroid).

    Returns
    -------
    Recording

    Raises
    ------
    ValueError
        If ``paths`` is empty, the files are of several shapes, or no
        outline is given for a shape without one in :data:`OUTLINES`.
    """
    if isinstance(paths, (str, bytes, os.PathLike)):
        paths = [paths]
    paths = [os.fspath(p) for p in paths]
    if not paths:
        raise ValueError("paths must name at least one file")
    files = [read_push(p) for p in paths]
    shapes = sorted({f.name.shape for f in files if f.name is not None})
    if len(shapes) > 1:
        raise ValueError(f"paths must all hold pushes of one plate, got shapes {shapes}")
    if outline is None:
        if not shapes or shapes[0] not in OUTLINES:
            known = sorted(OUTLINES)
            raise ValueError(
                f"outline is needed for shape {shapes[0] if shapes else 'unknown'!r}: only "
                f"{known} are built in (butter's traced outline is in the dataset's shape_db.py)"
            )
        outline = OUTLINES[shapes[0]]
    return recording_from_poses(
        outline,
        [(f.object_pose, f.tip_pose) for f in files],
        pusher_radius,
        travel=travel,
        resolution=resolution,
        com=com,
        names=[os.path.basename(p) for p in paths],
        standoff=standoff,
        contact_tolerance=contact_tolerance,
        frame_rate=frame_rate,
    )
