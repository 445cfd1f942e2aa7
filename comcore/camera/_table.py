"""The table plane under a tilted camera: :func:`calibrate_table`, :class:`TableView`.

A camera that looks at the table at an angle sees it in perspective: one
resolution for the whole frame puts the object and every push in the wrong
place. A :class:`TableCalibration`, made once from four or more image points
whose table coordinates (metres) are known, maps camera pixels to the table's
metres (a homography, after the lens's distortion is taken off when the
camera's intrinsics are given) and the table's metres to the robot's (a
planar rigid transform, :class:`RobotFromTable`, given or fitted from touched
points by :func:`fit_robot_from_table`). A :class:`TableView` is a region of
the table at a chosen resolution: it rectifies a camera frame to a metric
top-down image (what :func:`comcore.mask_from_image` then segments) and takes
the session's pushes, in its pixels, to the robot's metres.

Frames: the table's and the robot's ``(x, y)`` are right-handed seen from
above (``y`` up the top-down image); a top-down image's pixels follow
:mod:`comcore.conventions` (``x`` the column, ``y`` the row, down), so its
row 0 is the region's largest table ``y``. opencv is needed only for a lens
with distortion (``pip install comcore[sim]``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from .._checks import check_finite, check_points
from ..conventions import check_image_size, check_plausible, rotate_components

__all__ = [
    "RobotFromTable",
    "TableCalibration",
    "TableView",
    "calibrate_table",
    "fit_robot_from_table",
]

#: The spread of a table's points (their largest distance apart) believable in metres.
TABLE_SPAN = (0.01, 5.0)
#: Points closer than this share of their spread count as one point repeated.
REPEAT_SHARE = 1e-6
#: Points whose thinner spread (a singular value) is under this share of the wider lie on a line.
LINE_SHARE = 1e-3


def _checked_points(points, name: str, minimum: int, *, plane: bool = True) -> np.ndarray:
    """``points`` as (n, 2) floats, n >= ``minimum``, none repeated, not on a line (``plane``)."""
    arr = np.array(check_points(points, name), dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (n, 2), got {arr.shape}")
    if len(arr) < minimum:
        raise ValueError(
            f"{name} must hold at least {minimum} points, got {len(arr)}: a plane's "
            "homography needs four points, no three of them on a line"
        )
    centred = arr - arr.mean(axis=0)
    span = float(np.max(np.hypot(*(arr[:, None] - arr[None]).transpose(2, 0, 1))))
    gaps = np.hypot(*(arr[:, None] - arr[None]).transpose(2, 0, 1)) + np.eye(len(arr)) * span
    if span == 0 or gaps.min() <= REPEAT_SHARE * span:
        i, j = np.unravel_index(int(np.argmin(gaps)), gaps.shape)
        raise ValueError(
            f"{name} repeats a point (points {min(i, j)} and {max(i, j)} are the same): give "
            "distinct points, each once"
        )
    s = np.linalg.svd(centred, compute_uv=False)
    if plane and s[1] <= LINE_SHARE * s[0]:
        raise ValueError(
            f"{name} lie on a line: the plane cannot be calibrated from them; give points "
            "spread over the table (such as the four corners of a printed board)"
        )
    if plane and len(arr) == 4:
        for skip in range(4):
            a, b, c = np.delete(arr, skip, axis=0)
            area = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            if area <= LINE_SHARE * span**2:
                raise ValueError(
                    f"{name}: three of the four points lie on a line (all but point {skip}), "
                    "which does not fix a plane; give four points no three of which are on a line"
                )
    return arr


def _check_span(table: np.ndarray, name: str) -> None:
    span = float(np.max(np.hypot(*(table[:, None] - table[None]).transpose(2, 0, 1))))
    low, high = TABLE_SPAN
    if span > high:
        raise ValueError(
            f"{name} span {span:g} m, implausible for a table in metres (expected {low:g} to "
            f"{high:g} m): millimetres given for metres? divide by 1000 ({span / 1000:g} m)"
        )
    if span < low:
        raise ValueError(
            f"{name} span {span:g} m, too close together to calibrate a table (expected "
            f"{low:g} to {high:g} m): spread them over the table, or check the unit"
        )


def _normaliser(points: np.ndarray) -> np.ndarray:
    """The similarity taking ``points`` to mean 0 and mean distance sqrt(2) (Hartley)."""
    mean = points.mean(axis=0)
    scale = np.sqrt(2) / np.mean(np.hypot(*(points - mean).T))
    return np.array([[scale, 0, -scale * mean[0]], [0, scale, -scale * mean[1]], [0, 0, 1]])


def _homography(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The homography taking ``source`` to ``target`` (normalised DLT, least squares)."""
    ns, nt = _normaliser(source), _normaliser(target)
    s = _apply(ns, source)
    t = _apply(nt, target)
    rows = []
    for (x, y), (u, v) in zip(s, t):
        rows.append([-x, -y, -1, 0, 0, 0, u * x, u * y, u])
        rows.append([0, 0, 0, -x, -y, -1, v * x, v * y, v])
    _, sv, vt = np.linalg.svd(np.asarray(rows))
    if len(sv) >= 8 and sv[7] <= 1e-9 * sv[0]:
        raise ValueError(
            "image_points and table_points do not fix a plane: three of the four points lie "
            "on a line; give four points no three of which are on a line"
        )
    h = np.linalg.solve(nt, vt[-1].reshape(3, 3) @ ns)
    return h / h[2, 2] if h[2, 2] != 0 else h


def _apply(h: np.ndarray, points: np.ndarray) -> np.ndarray:
    """A homography applied to (n, 2) points."""
    p = points @ h[:, :2].T + h[:, 2]
    return p[:, :2] / p[:, 2:]


def _intrinsics(camera_matrix, distortion):
    """The checked camera matrix (3, 3) and distortion coefficients, or (None, None)."""
    if camera_matrix is None:
        if distortion is not None:
            raise ValueError("distortion needs camera_matrix (the camera's intrinsics) too")
        return None, None
    k = np.asarray(camera_matrix, dtype=float)
    if k.shape != (3, 3) or not np.isfinite(k).all() or not (k[0, 0] > 0 and k[1, 1] > 0):
        raise ValueError(
            "camera_matrix must be a finite 3 x 3 matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] "
            f"with fx, fy > 0 (pixels), got {np.asarray(camera_matrix).tolist()!r}"
        )
    d = np.zeros(5) if distortion is None else np.asarray(distortion, dtype=float).ravel()
    if d.size not in (4, 5, 8, 12, 14) or not np.isfinite(d).all():
        raise ValueError(
            "distortion must be 4, 5, 8, 12 or 14 finite coefficients (opencv's k1, k2, p1, "
            f"p2[, k3, ...]), got {np.asarray(distortion).tolist()!r}"
        )
    k.flags.writeable = d.flags.writeable = False
    return k, d


def _cv2():
    try:
        import cv2
    except ImportError as e:
        raise ImportError(
            "a camera's distortion needs opencv: pip install comcore[sim] (or calibrate "
            "without camera_matrix and distortion)"
        ) from e
    return cv2


class RobotFromTable(NamedTuple):
    """A planar rigid transform from the table's metres to the robot's.

    ``robot = R(theta) @ table + (tx, ty)``, ``R`` the counter-clockwise turn
    in frames whose ``y`` points up (right-handed seen from above).
    """

    theta: float
    """The turn from the table's x axis to the robot's, radians (counter-clockwise)."""
    tx: float
    """The table's origin in the robot's frame, x, metres."""
    ty: float
    """The table's origin in the robot's frame, y, metres."""
    residual: float = 0.0
    """Root-mean-square distance, metres, of the fitted points from the transform (0: given)."""

    def apply(self, points) -> np.ndarray:
        """Table points (n, 2) in metres to the robot's frame."""
        p = np.asarray(points, dtype=float)
        c, s = np.cos(self.theta), np.sin(self.theta)
        x, y = rotate_components(
            p[..., 0], p[..., 1], c, s, inverse=True, origin=(self.tx, self.ty)
        )
        return np.stack([x, y], axis=-1)

    def invert(self, points) -> np.ndarray:
        """Robot points (n, 2) in metres to the table's frame."""
        p = np.asarray(points, dtype=float)
        c, s = np.cos(self.theta), np.sin(self.theta)
        x, y = rotate_components(p[..., 0] - self.tx, p[..., 1] - self.ty, c, s)
        return np.stack([x, y], axis=-1)


def fit_robot_from_table(table_points, robot_points) -> RobotFromTable:
    """The rigid transform (least squares) taking table points to the robot's touched points.

    Parameters
    ----------
    table_points, robot_points : array_like, shape (n, 2)
        The same n >= 2 points, in the table's metres and in the robot's
        (where its tool touched them), both right-handed seen from above.

    Returns
    -------
    RobotFromTable
        With ``residual`` the root-mean-square distance, metres, between the
        robot's points and the transformed table points.

    Raises
    ------
    ValueError
        For fewer than 2 points, shapes that differ, repeated points,
        millimetres for metres, or points that only a mirror would match (one
        frame's ``y`` points the other way).

    Examples
    --------
    >>> t = [(0, 0), (0.3, 0), (0.3, 0.2)]
    >>> fit = fit_robot_from_table(t, [(0.5, 0.1), (0.5, 0.4), (0.3, 0.4)])
    >>> [round(float(v), 6) for v in (np.degrees(fit.theta), fit.tx, fit.ty, fit.residual)]
    [90.0, 0.5, 0.1, 0.0]
    """
    table = _checked_points(table_points, "table_points", 2, plane=False)
    robot = np.array(check_points(robot_points, "robot_points"), dtype=float)
    if robot.shape != table.shape:
        raise ValueError(
            f"robot_points must have the shape of table_points {table.shape}, got {robot.shape}"
        )
    _check_span(table, "table_points")
    _check_span(robot, "robot_points")
    a, b = table - table.mean(axis=0), robot - robot.mean(axis=0)
    cross = a.T @ b
    u, _, vt = np.linalg.svd(cross)
    spread = np.linalg.svd(a, compute_uv=False)
    flat = spread[1] <= LINE_SHARE * spread[0]
    if np.linalg.det(vt.T @ u.T) < 0 and not flat:
        raise ValueError(
            "robot_points match table_points only through a mirror: one frame's y axis points "
            "the other way; both must be right-handed seen from above (y counter-clockwise "
            "from x)"
        )
    theta = float(np.arctan2(cross[0, 1] - cross[1, 0], cross[0, 0] + cross[1, 1]))
    c, s = np.cos(theta), np.sin(theta)
    x, y = rotate_components(*table.mean(axis=0), c, s, inverse=True)
    tx, ty = robot.mean(axis=0) - (x, y)
    fit = RobotFromTable(theta, float(tx), float(ty))
    residual = float(np.sqrt(np.mean(np.sum((fit.apply(table) - robot) ** 2, axis=1))))
    return fit._replace(residual=residual)


@dataclass(frozen=True)
class TableCalibration:
    """How a camera sees the table: made once by :func:`calibrate_table`."""

    homography: np.ndarray
    """(3, 3): table metres to the camera's (undistorted) pixels, read-only."""
    camera_matrix: np.ndarray | None = None
    """(3, 3) intrinsics, or None (the frames' pixels are taken as undistorted)."""
    distortion: np.ndarray | None = None
    """opencv's distortion coefficients, or None."""
    robot: RobotFromTable | None = None
    """The table's metres to the robot's, or None (the robot's frame is the table's)."""
    residual_px: float = 0.0
    """Root-mean-square distance, pixels, of the image points from the fitted plane."""
    table_box: tuple[float, float, float, float] = (0.0, 0.0, 1.0, 1.0)
    """``(x_min, y_min, x_max, y_max)`` of the calibration's table points, metres."""

    def image_from_table(self, points) -> np.ndarray:
        """Table points (n, 2) in metres to camera pixels ``(x, y) = (column, row)``."""
        p = _apply(self.homography, np.atleast_2d(np.asarray(points, dtype=float)))
        if self.camera_matrix is None:
            return p
        cv2 = _cv2()
        k = self.camera_matrix
        normal = np.column_stack([(p[:, 0] - k[0, 2]) / k[0, 0], (p[:, 1] - k[1, 2]) / k[1, 1]])
        rays = np.column_stack([normal, np.ones(len(p))])
        out, _ = cv2.projectPoints(rays, np.zeros(3), np.zeros(3), k, self.distortion)
        return out.reshape(-1, 2)

    def table_from_image(self, points) -> np.ndarray:
        """Camera pixels (n, 2) ``(x, y) = (column, row)`` to table points in metres."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if self.camera_matrix is not None:
            k = self.camera_matrix
            p = _cv2().undistortPoints(p.reshape(-1, 1, 2), k, self.distortion, P=k).reshape(-1, 2)
        return _apply(np.linalg.inv(self.homography), p)

    def robot_from_table(self, points) -> np.ndarray:
        """Table points (n, 2) to the robot's frame (the same if no ``robot`` was given)."""
        p = np.asarray(points, dtype=float)
        return p.copy() if self.robot is None else self.robot.apply(p)

    def view(self, region=None, *, resolution: float) -> TableView:
        """A region of the table at ``resolution`` metres per pixel: see :class:`TableView`.

        ``region``: ``(x_min, y_min, x_max, y_max)`` in table metres (default:
        the box of the calibration's table points).
        """
        res = check_plausible(_positive(resolution, "resolution"), "resolution", "resolution")
        if region is None:
            region = self.table_box
        box = np.asarray(region, dtype=float)
        if (
            box.shape != (4,)
            or not np.isfinite(box).all()
            or not (box[2] > box[0] and box[3] > box[1])
        ):
            raise ValueError(
                "region must be (x_min, y_min, x_max, y_max) in table metres with x_max > x_min "
                f"and y_max > y_min, got {region!r}"
            )
        shape = (int(np.floor((box[3] - box[1]) / res + 1e-9)) + 1,
                 int(np.floor((box[2] - box[0]) / res + 1e-9)) + 1)
        check_image_size(shape, f"the top-down image of region {tuple(box.tolist())}")
        corners = np.array([[box[0], box[1]], [box[2], box[1]], [box[0], box[3]], [box[2], box[3]]])
        w = corners @ self.homography[2, :2] + self.homography[2, 2]
        if not (np.all(w > 0) or np.all(w < 0)):
            raise ValueError(
                f"region {tuple(box.tolist())} reaches the camera's horizon (part of it is "
                "behind the camera): give a region of the table the camera sees"
            )
        return TableView(
            self, (float(box[0]), float(box[1]), float(box[2]), float(box[3])), res, shape
        )


def _positive(value, name: str) -> float:
    v = check_finite(value, name)
    if v <= 0:
        raise ValueError(f"{name} must be positive (metres per pixel), got {v:g}")
    return v


def calibrate_table(
    image_points, table_points, *, camera_matrix=None, distortion=None, robot=None
) -> TableCalibration:
    """A camera-to-table calibration from four or more points seen in a frame.

    Parameters
    ----------
    image_points : array_like, shape (n, 2)
        Where the points are in the camera's frame, pixels ``(x, y) =
        (column, row)``; n >= 4, no three of four on a line.
    table_points : array_like, shape (n, 2)
        The same points on the table, metres, right-handed seen from above
        (the corners of a printed board, tags, or points the robot touched).
    camera_matrix : array_like, shape (3, 3), optional
        The camera's intrinsics; with ``distortion``, the lens's distortion is
        taken off first (opencv's ``undistortPoints``, ``pip install comcore[sim]``).
    distortion : array_like, optional
        opencv's distortion coefficients ``(k1, k2, p1, p2[, k3, ...])``.
    robot : RobotFromTable, optional
        The table's metres to the robot's (:func:`fit_robot_from_table`).

    Returns
    -------
    TableCalibration

    Raises
    ------
    ValueError
        For fewer than four points, repeated points, points on a line (or
        three of four on one), millimetres for metres, or table points that
        the image shows mirrored (a table ``y`` axis that points the wrong
        way, or ``x`` and ``y`` swapped).

    Examples
    --------
    A camera straight above, 2 mm per pixel, the table's origin at pixel (100, 400):

    >>> cal = calibrate_table([(100, 400), (400, 400), (400, 200), (100, 200)],
    ...                       [(0, 0), (0.6, 0), (0.6, 0.4), (0, 0.4)])
    >>> np.round(cal.table_from_image([(250, 300)]), 9).tolist()
    [[0.3, 0.2]]
    >>> calibrate_table([(100, 400), (400, 400), (400, 200), (100, 200)],
    ...                 [(0, 0), (600, 0), (600, 400), (0, 400)])
    Traceback (most recent call last):
    ...
    ValueError: table_points span 721.11 m, implausible for a table in metres (expected 0.01 to 5 m): millimetres given for metres? divide by 1000 (0.72111 m)
    """  # noqa: E501
    if np.shape(image_points)[:1] != np.shape(table_points)[:1]:
        raise ValueError(
            "image_points and table_points must hold the same points, got "
            f"{len(image_points)} and {len(table_points)}"
        )
    image = _checked_points(image_points, "image_points", 4)
    table = _checked_points(table_points, "table_points", 4)
    _check_span(table, "table_points")
    if robot is not None and not isinstance(robot, RobotFromTable):
        raise TypeError(f"robot must be a RobotFromTable, got {type(robot).__name__}")
    k, d = _intrinsics(camera_matrix, distortion)
    seen = image
    if k is not None:
        seen = _cv2().undistortPoints(image.reshape(-1, 1, 2), k, d, P=k).reshape(-1, 2)
    h = _homography(table, seen)
    _check_orientation(h, table)
    residual = float(np.sqrt(np.mean(np.sum((_apply(h, table) - seen) ** 2, axis=1))))
    h.flags.writeable = False
    box = (*table.min(axis=0), *table.max(axis=0))
    return TableCalibration(h, k, d, robot, residual, tuple(float(v) for v in box))


def _check_orientation(h: np.ndarray, table: np.ndarray) -> None:
    """ValueError unless the table is seen from above, unmirrored, in front of the camera."""
    w = table @ h[2, :2] + h[2, 2]
    if not (np.all(w > 0) or np.all(w < 0)):
        raise ValueError(
            "image_points and table_points do not describe one plane in front of the camera "
            "(the fitted plane puts some points behind it): check that they are the same "
            "points in the same order"
        )
    centre = table.mean(axis=0)
    step = 1e-3 * max(float(np.ptp(table)), 1e-9)
    jac = np.column_stack([
        (_apply(h, centre[None] + (step, 0)) - _apply(h, centre[None] - (step, 0)))[0],
        (_apply(h, centre[None] + (0, step)) - _apply(h, centre[None] - (0, step)))[0],
    ])
    if np.linalg.det(jac) > 0:
        raise ValueError(
            "table_points are mirrored relative to image_points: seen from above, the table's "
            "y axis must be counter-clockwise from its x axis (up the image when x points "
            "right); did you give y down the table, or swap x and y?"
        )


@dataclass(frozen=True)
class TableView:
    """A region of the table seen top-down at one resolution: :meth:`TableCalibration.view`.

    Its pixel ``(x, y) = (column, row)`` is the table point ``(x_min + x *
    resolution, y_max - y * resolution)``: the top-down image's row 0 is the
    region's far edge (largest table ``y``), so angles counter-clockwise on
    its screen are counter-clockwise on the table.
    """

    calibration: TableCalibration
    """The camera-to-table calibration."""
    region: tuple[float, float, float, float]
    """``(x_min, y_min, x_max, y_max)``, table metres."""
    resolution: float
    """Metres per pixel of the top-down image."""
    shape: tuple[int, int]
    """(H, W) of the top-down image."""

    def table_from_pixels(self, points) -> np.ndarray:
        """Top-down pixels (n, 2) to table metres."""
        p = np.asarray(points, dtype=float)
        return np.stack([self.region[0] + p[..., 0] * self.resolution,
                         self.region[3] - p[..., 1] * self.resolution], axis=-1)

    def pixels_from_table(self, points) -> np.ndarray:
        """Table metres (n, 2) to top-down pixels."""
        p = np.asarray(points, dtype=float)
        return np.stack([(p[..., 0] - self.region[0]) / self.resolution,
                         (self.region[3] - p[..., 1]) / self.resolution], axis=-1)

    def robot_from_pixels(self, points) -> np.ndarray:
        """Top-down pixels (n, 2) to the robot's metres."""
        return self.calibration.robot_from_table(self.table_from_pixels(points))

    def image_from_pixels(self, points) -> np.ndarray:
        """Top-down pixels (n, 2) to the camera's pixels (where to draw them on a frame)."""
        return self.calibration.image_from_table(self.table_from_pixels(points))

    def robot_pushes(self, actions) -> np.ndarray:
        """Pushes (``comcore.Action``s or rows ``(sx, sy, ex, ey)`` in top-down pixels) in metres.

        Returns an array (n, 4): each push's start ``(x, y)`` and end ``(x, y)``
        in the robot's frame, metres.
        """
        rows = np.asarray([tuple(a) for a in actions] if not isinstance(actions, np.ndarray)
                          else actions, dtype=float).reshape(-1, 4)
        if not np.isfinite(rows).all():
            raise ValueError("actions must hold finite numbers (sx, sy, ex, ey) in pixels")
        starts = self.robot_from_pixels(rows[:, :2])
        ends = self.robot_from_pixels(rows[:, 2:])
        return np.hstack([starts, ends])

    def _camera_coordinates(self) -> np.ndarray:
        h, w = self.shape
        rows, cols = np.mgrid[0:h, 0:w]
        points = np.column_stack([cols.ravel(), rows.ravel()]).astype(float)
        return self.image_from_pixels(points).reshape(h, w, 2)

    def in_view(self, frame_shape) -> np.ndarray:
        """Which top-down pixels a camera frame of ``frame_shape`` (H, W) sees, bool (H, W)."""
        xy = self._camera_coordinates()
        fh, fw = int(frame_shape[0]), int(frame_shape[1])
        return (
            (xy[..., 0] >= -0.5)
            & (xy[..., 0] <= fw - 0.5)
            & (xy[..., 1] >= -0.5)
            & (xy[..., 1] <= fh - 0.5)
        )

    def rectify(self, frame, *, fill: float = 0.0) -> np.ndarray:
        """The top-down image of the region from a camera frame (bilinear).

        ``frame``: grey (H, W) or colour (H, W, C); the result has the view's
        ``shape`` (and the frame's channels and dtype); pixels the camera does
        not see are ``fill``.
        """
        image = np.asarray(frame)
        if image.ndim not in (2, 3) or image.dtype.kind not in "uifb" or min(image.shape[:2]) < 2:
            raise ValueError(
                "frame must be a numeric image (H, W) or (H, W, C), got "
                f"shape {image.shape}, dtype {image.dtype}"
            )
        xy = self._camera_coordinates()
        coords = [xy[..., 1], xy[..., 0]]
        planes = image[..., None] if image.ndim == 2 else image
        out = np.stack([
            ndimage.map_coordinates(planes[..., c].astype(float), coords, order=1,
                                    mode="constant", cval=float(fill))
            for c in range(planes.shape[2])
        ], axis=-1)
        if image.dtype.kind in "ui":
            info = np.iinfo(image.dtype)
            out = np.clip(np.rint(out), info.min, info.max)
        elif image.dtype.kind == "b":
            out = out >= 0.5
        out = out.astype(image.dtype)
        return out[..., 0] if image.ndim == 2 else out
