"""Tag-tracked objects: an AprilTag or ArUco marker's planar pose per frame, and the motions.

A tag stuck flat on the object gives its pose in every frame more precisely than the object's
outline does (four sharp corners against a staircase of pixels). :func:`track_tag` detects one
marker with OpenCV's ``cv2.aruco.ArucoDetector`` (``pip install comcore[sim]``) and returns its
:class:`TagPose` per frame in comcore's pixel frame (:mod:`comcore.conventions`);
:meth:`TagTrack.motions` turns the poses into :class:`comcore.Motion` s about the object's
area centroid before each push, as :func:`comcore.measure_motion` reports them and
:meth:`comcore.ActiveSession.observe` takes them (``motion=``). How to: docs/how-to/tags.md.

* **The camera** is one homography, ``pixels_from_image``, from the image's pixels (undistorted
  first with ``camera_matrix`` and ``distortion``) to the masks' frame, of the plane the tag
  lies in (a tag on a tall object needs its own plane's); no 3-D tag pose is needed.
* **The corners**: OpenCV finds the marker; each outer edge of its black border is then fitted
  with a line (the sub-pixel crossings of halfway between dark and light, total least squares,
  outliers dropped) and the corners are where adjacent lines meet; a side without enough edge
  points keeps OpenCV's corners (precision: docs/results/camera.md).
* **The pose**: ``(x, y)`` the mean of the mapped corners, ``theta`` the least-squares
  rotation of the upright square onto them (0: the marker upright, its top edge along +x).
* **The offset** ``centroid_in_tag`` places the object about the tag: measured once from the
  first frame's mask (:func:`centroid_in_tag`) or given.
* **Lost frames are said, never filled**: a frame where the marker is missing, seen twice (so
  every frame is searched whole) or of the wrong size has no pose; its status says why, it is
  in :attr:`TagTrack.lost`, and a motion that needs it is ``None``.

Examples
--------
A square object carrying AprilTag 36h11 #3 turns 0.2 rad counter-clockwise
on screen about its centroid ``c0`` and slides 5 px right between two
frames (``simulators.tag_frames`` renders them); in a third the tag is
hidden:

>>> import numpy as np
>>> from comcore.conventions import apply_motion
>>> from simulators.tag_frames import render_tag_frame
>>> square = np.array([(100, 80), (220, 80), (220, 180), (100, 180)], float)
>>> c0 = square.mean(axis=0)
>>> frames = []
>>> for theta, shift in ((0.0, (0.0, 0.0)), (0.2, (5.0, 0.0))):
...     outline = apply_motion(square, theta, shift, c0)
...     centre = apply_motion([140.0, 130.0], theta, shift, c0)
...     frames.append(render_tag_frame(outline, centre, theta, 48, tag_id=3, rng=0))
>>> hidden = frames[1].copy()
>>> hidden[100:160, 110:170] = 60  # the arm over the tag
>>> track = track_tag([*frames, hidden], 3)
>>> track.status, track.lost
(('found', 'found', 'missing'), (2,))
>>> round(track.poses[1].theta, 2)  # counter-clockwise on screen: positive
0.2
>>> offset = centroid_in_tag(track.poses[0], c0)  # or the first frame's Mask
>>> first, second = track.motions(offset)
>>> [round(v, 1) for v in first], second
([0.2, 5.0, 0.0], None)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._types import Motion
from .._validation import check_point, check_positive
from ..conventions import ccw_cross, rotation_matrix

__all__ = [
    "TAG_DICTIONARIES",
    "TagPose",
    "TagTrack",
    "centroid_in_tag",
    "motion_from_tags",
    "track_tag",
]

#: The marker dictionaries :func:`track_tag` knows: OpenCV's predefined ones, named
#: without ``DICT_`` and in lower case (``"apriltag_36h11"`` is ``DICT_APRILTAG_36h11``).
TAG_DICTIONARIES = (
    "apriltag_16h5",
    "apriltag_25h9",
    "apriltag_36h10",
    "apriltag_36h11",
    "aruco_mip_36h12",
    "aruco_original",
    *(f"{n}x{n}_{k}" for n in (4, 5, 6, 7) for k in (50, 100, 250, 1000)),
)
#: A found marker whose mean side differs from ``tag_size`` by more than this share is
#: refused (status ``"wrong_size"``): a marker in another plane or a false detection.
SIZE_TOLERANCE = 0.15
#: A profile across the marker's edge reaches this many cells inside and outside it.
EDGE_REACH_CELLS = (0.5, 1.0)
#: A side whose light and dark levels differ by less than this (grey levels) keeps
#: OpenCV's corners: no edge to fit.
MIN_EDGE_CONTRAST = 20.0

#: What a frame's status can be.
STATUSES = ("found", "missing", "ambiguous", "wrong_size")

#: The upright marker's corners about its centre, per unit side, in cv2.aruco's order.
_UNIT_CORNERS = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])


class TagPose(NamedTuple):
    """The planar pose of a marker in one frame, in comcore's pixel frame."""

    x: float
    """Column of the marker's centre (pixels)."""
    y: float
    """Row of the marker's centre (pixels, down the screen)."""
    theta: float
    """Rotation (radians, counter-clockwise on screen) from upright, in (-pi, pi]."""
    side: float
    """Mean length of the marker's four sides (pixels)."""


@dataclass(frozen=True)
class TagTrack:
    """One marker tracked over frames: its pose where it was found, and why not elsewhere.

    :func:`track_tag` makes one; a lost frame has no pose, and the motions
    that need it are ``None``.

    Examples
    --------
    >>> track = TagTrack(
    ...     (TagPose(50.0, 40.0, 0.0, 30.0), None, TagPose(60.0, 40.0, 0.1, 30.0)),
    ...     ("found", "missing", "found"),
    ...     (1,),
    ... )
    >>> track.motions((0.0, 0.0))
    (None, None)
    >>> track.motion(0, 2, (0.0, 0.0))
    Motion(theta=0.1, tx=10.0, ty=0.0)
    >>> track.motion(0, 1, (0.0, 0.0))
    Traceback (most recent call last):
    ...
    ValueError: after frame 1 has no tag pose (status 'missing'): its motion cannot be measured
    """

    poses: tuple[TagPose | None, ...]
    """One per frame: the marker's pose, or None where it was not found."""
    status: tuple[str, ...]
    """One per frame: ``"found"``, ``"missing"`` (no marker of the id: occluded, out of
    view), ``"ambiguous"`` (the id seen more than once) or ``"wrong_size"`` (its side is
    more than :data:`SIZE_TOLERANCE` off ``tag_size``)."""
    lost: tuple[int, ...]
    """Indices of the frames without a pose (status other than ``"found"``)."""

    def motion(self, before: int, after: int, centroid_in_tag) -> Motion:
        """The object's motion from frame ``before`` to frame ``after``.

        Parameters
        ----------
        before, after : int
            Frame indices.
        centroid_in_tag : array_like, shape (2,)
            The object's area centroid in the tag's frame (:func:`centroid_in_tag`).

        Returns
        -------
        Motion
            As :func:`motion_from_tags`.

        Raises
        ------
        ValueError
            If either frame has no pose (its status is named), or an index is
            out of range.
        """
        for name, i in (("before", before), ("after", after)):
            if isinstance(i, bool) or not isinstance(i, (int, np.integer)):
                raise TypeError(f"{name} must be a frame index (int), got {type(i).__name__}")
            if not -len(self.poses) <= i < len(self.poses):
                raise ValueError(f"{name} must be a frame index below {len(self.poses)}, got {i}")
            if self.poses[i] is None:
                raise ValueError(
                    f"{name} frame {i} has no tag pose (status {self.status[i]!r}): "
                    "its motion cannot be measured"
                )
        return motion_from_tags(self.poses[before], self.poses[after], centroid_in_tag)

    def motions(self, centroid_in_tag) -> tuple[Motion | None, ...]:
        """The motions between consecutive frames, ``None`` where either frame is lost.

        Parameters
        ----------
        centroid_in_tag : array_like, shape (2,)
            The object's area centroid in the tag's frame (:func:`centroid_in_tag`).

        Returns
        -------
        tuple of Motion or None, length ``len(poses) - 1``
        """
        offset = check_point(centroid_in_tag, "centroid_in_tag")
        return tuple(
            None if a is None or b is None else _motion(a, b, offset)
            for a, b in zip(self.poses[:-1], self.poses[1:])
        )


def _cv2():
    try:
        import cv2
        import cv2.aruco
    except ImportError as e:
        raise ImportError(
            "tracking a tag needs opencv (cv2.aruco): pip install comcore[sim]"
        ) from e
    return cv2


def _aruco_dictionary(dictionary):
    """``(cv2, the predefined dictionary)`` for a name of :data:`TAG_DICTIONARIES`."""
    if not isinstance(dictionary, str):
        raise TypeError(
            f"dictionary must be a name (str) of {list(TAG_DICTIONARIES)}, "
            f"got {type(dictionary).__name__}"
        )
    name = dictionary.lower().removeprefix("dict_")
    if name not in TAG_DICTIONARIES:
        raise ValueError(f"dictionary must be one of {list(TAG_DICTIONARIES)}, got {dictionary!r}")
    cv2 = _cv2()
    code = getattr(cv2.aruco, "DICT_" + name.upper())
    return cv2, cv2.aruco.getPredefinedDictionary(code)


def _check_matrix(value, name: str, shape: tuple[int, ...]) -> np.ndarray:
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers, got {type(value).__name__}")
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be an array of numbers; {e}") from e
    if arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite, got NaN or inf")
    return arr


def _check_homography(value, name: str) -> np.ndarray:
    h = _check_matrix(value, name, (3, 3))
    scale = np.abs(h).max()
    if scale == 0 or abs(np.linalg.det(h / scale)) < 1e-12:
        raise ValueError(f"{name} must be an invertible homography, got a singular matrix")
    return h / scale


def _check_images(images) -> list[np.ndarray]:
    if isinstance(images, np.ndarray) and images.ndim == 2:
        raise ValueError("images must be a sequence of frames, got one 2-D image: pass [image]")
    try:
        frames = list(images)
    except TypeError as e:
        raise TypeError(
            f"images must be a sequence of uint8 images, got {type(images).__name__}"
        ) from e
    if not frames:
        raise ValueError("images must hold at least one frame, got none")
    out = []
    for i, image in enumerate(frames):
        arr = np.asarray(image)
        if arr.dtype != np.uint8:
            raise TypeError(
                f"images[{i}] must be a uint8 image, got dtype {arr.dtype} "
                "(np.clip(image, 0, 255).astype(np.uint8))"
            )
        if arr.ndim == 3 and arr.shape[2] in (3, 4):
            arr = np.rint(arr[..., :3].mean(axis=2)).astype(np.uint8)
        if arr.ndim != 2 or min(arr.shape) < 8:
            raise ValueError(
                f"images[{i}] must be a (H, W) grey or (H, W, 3) colour image, got {arr.shape}"
            )
        out.append(np.ascontiguousarray(arr))
    return out


def _apply(h: np.ndarray, points: np.ndarray) -> np.ndarray:
    q = points @ h[:, :2].T + h[:, 2]
    return q[..., :2] / q[..., 2:]


def _pose_from_corners(corners: np.ndarray) -> TagPose:
    """The pose of a marker from its four corners (4, 2) in comcore pixels."""
    centre = corners.mean(axis=0)
    p = corners - centre
    q = _UNIT_CORNERS
    cross = ccw_cross(q, p).sum()  # > 0: the corners turned CCW on screen from upright
    dot = (q * p).sum()
    side = float(np.linalg.norm(corners - np.roll(corners, -1, axis=0), axis=1).mean())
    return TagPose(float(centre[0]), float(centre[1]), math.atan2(cross, dot), side)


def _wrap(theta: float) -> float:
    return float(math.remainder(theta, 2 * math.pi))


def track_tag(
    images,
    tag_id: int,
    *,
    pixels_from_image=None,
    dictionary: str = "apriltag_36h11",
    camera_matrix=None,
    distortion=None,
    tag_size: float | None = None,
    resolution: float | None = None,
) -> TagTrack:
    """Find one marker in each frame and return its planar pose, or why not.

    Parameters
    ----------
    images : sequence of numpy.ndarray, each uint8 (H, W) or (H, W, 3)
        The camera's frames, in order (a colour frame is averaged to grey).
    tag_id : int
        The object's marker id in ``dictionary``.
    pixels_from_image : array_like, shape (3, 3), optional
        Homography from image pixels (undistorted, with ``camera_matrix``) to
        comcore's pixel frame, the masks' frame; default identity (a camera
        looking straight down, its image the mask frame). It must keep the
        image's handedness (a mirror is refused).
    dictionary : str, optional
        One of :data:`TAG_DICTIONARIES`, default ``"apriltag_36h11"``.
    camera_matrix : array_like, shape (3, 3), optional
        The camera's intrinsic matrix ``K``; with it, corners are undistorted
        (``cv2.undistortPoints``) before the homography.
    distortion : array_like, shape (k,), optional
        OpenCV's distortion coefficients (k = 4, 5, 8, 12 or 14), with
        ``camera_matrix`` only; default none.
    tag_size : float, optional
        The marker's side in metres (its black border's outer edge), with
        ``resolution``: a marker whose side differs by more than
        :data:`SIZE_TOLERANCE` is refused (status ``"wrong_size"``).
    resolution : float, optional
        Metres per pixel of comcore's frame, with ``tag_size`` only.

    Returns
    -------
    TagTrack
        A pose per frame where the marker was found once; a status per frame;
        the lost frames' indices.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments, naming them (an unknown dictionary lists the known
        ones); a ValueError naming ``pixels_from_image`` if it mirrors a marker.
    ImportError
        If OpenCV is not installed (``pip install comcore[sim]``).

    Examples
    --------
    The module's docstring tracks a tag over three frames; a dictionary must be known:

    >>> import numpy as np
    >>> frames = [np.zeros((40, 40), np.uint8)]
    >>> track_tag(frames, 3, dictionary="apriltag_36h12")
    Traceback (most recent call last):
    ...
    ValueError: dictionary must be one of ['apriltag_16h5', ...], got 'apriltag_36h12'
    """
    h = np.eye(3)
    if pixels_from_image is not None:
        h = _check_homography(pixels_from_image, "pixels_from_image")
    cv2, d = _aruco_dictionary(dictionary)
    _check_tag_id(tag_id, d, dictionary)
    undistort = _undistortion(camera_matrix, distortion)
    expected = _expected_side(tag_size, resolution)
    frames = _check_images(images)

    params = cv2.aruco.DetectorParameters()
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_CONTOUR
    cells = int(d.markerSize) + 2
    detector = cv2.aruco.ArucoDetector(d, params)

    poses: list[TagPose | None] = []
    status: list[str] = []
    for image in frames:
        what, corners = _find(detector, image, tag_id)
        if what != "found":
            poses.append(None)
            status.append(what)
            continue
        corners = _refine_edges(image, corners, cells)
        if undistort is not None:
            corners = cv2.undistortPoints(
                corners.reshape(-1, 1, 2), undistort[0], undistort[1], P=undistort[0]
            ).reshape(4, 2)
        mapped = _apply(h, corners)
        x, y = mapped[:, 0], mapped[:, 1]
        if np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) <= 0:
            raise ValueError(
                "pixels_from_image mirrors the marker (or maps it behind the horizon): it "
                "must keep the image's handedness, x = column and y = row down"
            )
        pose = _pose_from_corners(mapped)
        if expected is not None and abs(pose.side / expected - 1.0) > SIZE_TOLERANCE:
            poses.append(None)
            status.append("wrong_size")
            continue
        poses.append(pose)
        status.append("found")
    lost = tuple(i for i, s in enumerate(status) if s != "found")
    return TagTrack(tuple(poses), tuple(status), lost)


def _check_tag_id(tag_id, d, dictionary: str) -> None:
    """Raise unless ``tag_id`` is an int naming a marker of the dictionary ``d``."""
    if isinstance(tag_id, bool) or not isinstance(tag_id, (int, np.integer)):
        raise TypeError(f"tag_id must be an int, got {type(tag_id).__name__}")
    n_ids = int(d.bytesList.shape[0])
    if not 0 <= tag_id < n_ids:
        raise ValueError(f"tag_id must be in 0..{n_ids - 1} for {dictionary!r}, got {tag_id}")


def _undistortion(camera_matrix, distortion):
    """``(K, coefficients)`` to undistort the corners with, or None without ``camera_matrix``."""
    if camera_matrix is None:
        if distortion is not None:
            raise ValueError("distortion needs camera_matrix (the intrinsics it belongs to)")
        return None
    k = _check_matrix(camera_matrix, "camera_matrix", (3, 3))
    dist = np.zeros(5)
    if distortion is not None:
        dist = np.array(distortion, dtype=float).ravel()
        if dist.size not in (4, 5, 8, 12, 14) or not np.isfinite(dist).all():
            raise ValueError(
                f"distortion must hold 4, 5, 8, 12 or 14 finite coefficients, got {dist.size}"
            )
    return (k, dist)


def _expected_side(tag_size, resolution) -> float | None:
    """The marker's side in pixels of comcore's frame, or None when its size is not given."""
    if (tag_size is None) != (resolution is None):
        raise ValueError(
            "tag_size and resolution go together (the marker's side in metres and the "
            "frame's metres per pixel): give both or neither"
        )
    if tag_size is None:
        return None
    return check_positive(tag_size, "tag_size") / check_positive(resolution, "resolution")


def _find(detector, image: np.ndarray, tag_id: int):
    """``("found", corners (4, 2))``, ``("missing", None)`` or ``("ambiguous", None)``."""
    corners, ids, _ = detector.detectMarkers(image)
    if ids is None:
        return ("missing", None)
    hits = np.flatnonzero(np.asarray(ids).ravel() == tag_id)
    if hits.size == 0:
        return ("missing", None)
    if hits.size > 1:
        return ("ambiguous", None)
    return ("found", np.asarray(corners[hits[0]], dtype=float).reshape(4, 2))


def _edge_line(image, a, b, centre, cell):
    """``(normal, offset)`` of the outer edge from corner ``a`` to ``b``, or None."""
    edge = b - a
    length = float(np.hypot(*edge))
    along = edge / length
    normal = np.array([along[1], -along[0]])
    if normal @ ((a + b) / 2 - centre) < 0:  # outwards
        normal = -normal
    inner = min(max(EDGE_REACH_CELLS[0] * cell, 1.0), 3.0)
    outer = min(max(EDGE_REACH_CELLS[1] * cell, 1.5), 4.0)
    step = 0.25
    across = np.arange(-inner, outer + 1e-9, step)
    s = np.arange(0.15 * length, 0.85 * length, 1.0)
    base = a + s[:, None] * along
    points = base[:, None, :] + across[None, :, None] * normal  # (m, k, 2)
    profile = ndimage.map_coordinates(
        image, [points[..., 1].ravel(), points[..., 0].ravel()], order=1, mode="nearest"
    ).reshape(points.shape[:2])
    dark, light = np.median(profile[:, 0]), np.median(profile[:, -1])
    if light - dark < MIN_EDGE_CONTRAST:
        return None
    mid = 0.5 * (dark + light)
    first = np.argmax(profile > mid, axis=1)  # the first sample past halfway, outwards
    ok = first > 0
    i = np.clip(first, 1, len(across) - 1)
    rows = np.arange(len(s))
    p0, p1 = profile[rows, i - 1], profile[rows, i]
    d = across[i - 1] + step * (mid - p0) / np.where(p1 > p0, p1 - p0, 1.0)
    q = (base + d[:, None] * normal)[ok]
    for _ in range(2):
        if len(q) < 4:
            return None
        m = q.mean(axis=0)
        n = np.linalg.svd(q - m)[2][1]
        r = (q - m) @ n
        spread = 1.4826 * np.median(np.abs(r - np.median(r)))
        q = q[np.abs(r) <= max(3 * spread, 0.05)]
    if len(q) < 4:
        return None
    m = q.mean(axis=0)
    n = np.linalg.svd(q - m)[2][1]
    return n, float(n @ m)


def _refine_edges(image: np.ndarray, corners: np.ndarray, cells: int) -> np.ndarray:
    """The corners where the marker's four fitted outer edges meet (see the module)."""
    lo = np.maximum(np.floor(corners.min(axis=0)).astype(int) - 6, 0)
    hi = np.minimum(np.ceil(corners.max(axis=0)).astype(int) + 7, image.shape[::-1])
    patch = image[lo[1] : hi[1], lo[0] : hi[0]].astype(float)
    local = corners - lo
    centre = local.mean(axis=0)
    side = float(np.linalg.norm(local - np.roll(local, -1, axis=0), axis=1).mean())
    lines = [
        _edge_line(patch, local[k], local[(k + 1) % 4], centre, side / cells) for k in range(4)
    ]
    if any(line is None for line in lines):
        return corners
    out = np.empty((4, 2))
    for k in range(4):  # corner k is where the edges into and out of it meet
        (n1, d1), (n2, d2) = lines[k - 1], lines[k]
        a = np.array([n1, n2])
        if abs(np.linalg.det(a)) < 0.5:  # the edges are not near perpendicular: keep OpenCV's
            return corners
        out[k] = np.linalg.solve(a, [d1, d2])
    if np.abs(out - local).max() > 2.0:  # the fit wandered off: keep OpenCV's
        return corners
    return out + lo


def centroid_in_tag(tag: TagPose, mask) -> np.ndarray:
    """The object's area centroid in the tag's frame: where the object lies about the tag.

    Parameters
    ----------
    tag : TagPose
        The tag's pose in a frame.
    mask : Mask or array_like, shape (2,)
        The object's mask in the same frame (its area centroid is used), or
        that centroid ``(x, y)`` in pixels.

    Returns
    -------
    numpy.ndarray, shape (2,)
        The centroid along the tag's x and y axes from its centre (pixels).

    Examples
    --------
    A tag turned a quarter turn counter-clockwise on screen: its x axis points
    up the screen, so a centroid 10 px above the tag is 10 px along that axis.

    >>> import numpy as np
    >>> np.round(centroid_in_tag(TagPose(50.0, 50.0, np.pi / 2, 20.0), (50.0, 40.0)), 9) + 0.0
    array([10.,  0.])
    """
    if not isinstance(tag, TagPose):
        raise TypeError(f"tag must be a TagPose, got {type(tag).__name__}")
    centre = np.asarray(mask.centroid) if isinstance(mask, Mask) else check_point(mask, "mask")
    return rotation_matrix(-tag.theta) @ (centre - (tag.x, tag.y))


def _motion(before: TagPose, after: TagPose, offset: np.ndarray) -> Motion:
    c0 = np.array([before.x, before.y]) + rotation_matrix(before.theta) @ offset
    c1 = np.array([after.x, after.y]) + rotation_matrix(after.theta) @ offset
    return Motion(_wrap(after.theta - before.theta), *(c1 - c0))


def motion_from_tags(before: TagPose, after: TagPose, centroid_in_tag) -> Motion:
    """The object's motion between two tag poses, as :func:`comcore.measure_motion` gives it.

    The object turns by the tag's turn (a rigid body turns the same at every
    point), wrapped into (-pi, pi]; the translation is that of the object's
    area centroid before the motion, ``c = (x, y) + R(theta) centroid_in_tag``
    (:func:`comcore.conventions.rotation_matrix`), not the tag's.

    Parameters
    ----------
    before, after : TagPose
        The tag's poses before and after.
    centroid_in_tag : array_like, shape (2,)
        The object's area centroid in the tag's frame (:func:`centroid_in_tag`).

    Returns
    -------
    Motion
        ``(theta, tx, ty)`` in the camera frame about the centroid before.

    Examples
    --------
    The object turned a quarter turn counter-clockwise on screen about its
    centroid, 10 px right of the tag: the tag swings down, the centroid stays.

    >>> before = TagPose(40.0, 50.0, 0.0, 20.0)
    >>> after = TagPose(50.0, 60.0, np.pi / 2, 20.0)
    >>> m = motion_from_tags(before, after, (10.0, 0.0))
    >>> round(m.theta, 6), round(m.tx, 9) + 0.0, round(m.ty, 9) + 0.0
    (1.570796, 0.0, 0.0)
    """
    for name, pose in (("before", before), ("after", after)):
        if not isinstance(pose, TagPose):
            raise TypeError(f"{name} must be a TagPose, got {type(pose).__name__}")
    return _motion(before, after, check_point(centroid_in_tag, "centroid_in_tag"))
